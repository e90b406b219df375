//! The charts drawn by `plotters` as PNG and SVG: axes on the model's ticks, the legend placed where it covers no
//! point, labels placed apart.

use super::{Chart, Color, FAMILY, FONT, Mark, Point, Tick, ZERO_GAP};
use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::prelude::*;
use plotters::style::{Color as _, FontStyle, register_font};
use std::sync::OnceLock;

/// Registers [`FONT`] with plotters (once).
fn font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    ok.then_some(())
        .ok_or_else(|| anyhow!("the chart font (egui's Ubuntu Light) does not load"))
}

/// Renders `chart` as a `width`×`height` PNG.
pub fn png(chart: &Chart, width: u32, height: u32) -> Result<Vec<u8>> {
    font()?;
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        draw(chart, &root).map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
        root.present()
            .map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
    }
    let img = image::RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| anyhow!("cannot encode the chart as PNG: wrong buffer size"))?;
    crate::io::encode_png(&img)
}

/// Renders `chart` as a `width`×`height` SVG document.
pub fn svg(chart: &Chart, width: u32, height: u32) -> Result<String> {
    font()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        draw(chart, &root).map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
        root.present()
            .map_err(|e| anyhow!("cannot draw the chart: {e}"))?;
    }
    Ok(out)
}

fn rgb(c: Color) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

const INK: RGBColor = RGBColor(30, 30, 30);
const NOTE: RGBColor = RGBColor(90, 90, 90);
const FRONT: RGBColor = RGBColor(0, 0, 0);
const POINT_RADIUS: i32 = 5;
const RING_RADIUS: i32 = 9;
const TITLE_SIZE: f64 = 30.0;
const TEXT_SIZE: f64 = 19.0;
const LABEL_SIZE: f64 = 16.0;

/// A linear plot axis over `lo..hi` (plot coordinates) with the model's ticks: labelled ones as plotters' bold
/// key points, every one as a light grid line.
struct TickedAxis {
    lo: f64,
    hi: f64,
    major: Vec<f64>,
    all: Vec<f64>,
}

impl TickedAxis {
    fn new(lo: f64, hi: f64, ticks: &[Tick]) -> TickedAxis {
        TickedAxis {
            lo,
            hi,
            major: ticks.iter().filter(|t| t.label.is_some()).map(|t| t.at).collect(),
            all: ticks.iter().map(|t| t.at).collect(),
        }
    }
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        limit.0 + (t * (limit.1 - limit.0) as f64).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.all.clone()
        } else {
            self.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A pixel box `[x0, y0, x1, y1]`.
type PxBox = [i32; 4];

fn overlaps(a: PxBox, b: PxBox) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// `text` cut to `max` pixels wide in `style`, ending in `...` when cut.
fn fit_text<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    max: u32,
) -> String {
    let width = |t: &str| area.estimate_text_size(t, style).map_or(0, |s| s.0);
    if width(text) <= max {
        return text.to_string();
    }
    let mut t: Vec<char> = text.chars().collect();
    while !t.is_empty() && width(&format!("{}...", t.iter().collect::<String>())) > max {
        t.pop();
    }
    format!("{}...", t.into_iter().collect::<String>())
}

/// The legend's entries (the named series with points, then the front) and its box size in pixels.
struct Legend<'a> {
    names: Vec<&'a str>,
    style: TextStyle<'a>,
    size: (i32, i32),
}

/// Height of a legend row.
const LEGEND_ROW: i32 = 24;

impl<'a> Legend<'a> {
    fn of<DB: DrawingBackend>(chart: &'a Chart, root: &DrawingArea<DB, Shift>, style: TextStyle<'a>) -> Self {
        let names: Vec<&str> = chart
            .series
            .iter()
            .filter(|s| !s.name.is_empty() && !s.points.is_empty())
            .map(|s| s.name.as_str())
            .chain(chart.front.iter().map(|f| f.name.as_str()))
            .collect();
        let text_w = names
            .iter()
            .map(|n| root.estimate_text_size(n, &style).map_or(0, |s| s.0 as i32))
            .max()
            .unwrap_or(0);
        let size = (text_w + 60, names.len() as i32 * LEGEND_ROW + 16);
        Legend { names, style, size }
    }

    /// The plot corner (and the legend's box there) clear of every point and every line of `chart` drawn in
    /// `cc`; `None` when no corner is, or there is nothing to list.
    fn corner<DB: DrawingBackend>(
        &self,
        chart: &Chart,
        cc: &ChartContext<DB, Cartesian2d<TickedAxis, TickedAxis>>,
    ) -> Option<(SeriesLabelPosition, PxBox)> {
        if self.names.is_empty() {
            return None;
        }
        let ([x0, x1], [y0, y1]) = chart.bounds();
        let (ax, ay) = cc.backend_coord(&(x0, y1));
        let (bx, by) = cc.backend_coord(&(x1, y0));
        let (lw, lh) = self.size;
        let px = |p: &Point| {
            let (x, y) = (chart.plot_x(p.x), chart.plot_y(p.y));
            (x.is_finite() && y.is_finite()).then(|| cc.backend_coord(&(x, y)))
        };
        // Every point, and every line (the fits, the front) sampled every 8 pixels along it.
        let mut marks: Vec<(i32, i32)> = Vec::new();
        let lines = chart.series.iter().map(|s| (s.mark == Mark::Line, &s.points));
        for (line, points) in lines.chain(chart.front.iter().map(|f| (true, &f.points))) {
            let pts: Vec<_> = points.iter().filter_map(px).collect();
            if line {
                for w in pts.windows(2) {
                    let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
                    let n = (f64::from(dx).hypot(f64::from(dy)) / 8.0).ceil().max(1.0) as i32;
                    marks.extend((0..n).map(|i| (w[0].0 + dx * i / n, w[0].1 + dy * i / n)));
                }
            }
            marks.extend(pts);
        }
        let r = RING_RADIUS;
        [
            (SeriesLabelPosition::UpperRight, [bx - lw - 12, ay + 12]),
            (SeriesLabelPosition::UpperLeft, [ax + 12, ay + 12]),
            (SeriesLabelPosition::LowerRight, [bx - lw - 12, by - lh - 12]),
            (SeriesLabelPosition::LowerLeft, [ax + 12, by - lh - 12]),
        ]
        .into_iter()
        .map(|(position, [x, y])| (position, [x, y, x + lw, y + lh]))
        .find(|(_, b)| {
            b[0] >= ax
                && b[2] <= bx
                && b[3] <= by
                && !marks
                    .iter()
                    .any(|&(x, y)| overlaps(*b, [x - r, y - r, x + r, y + r]))
        })
    }

    /// The legend in `area` beside the plot, level with the plot's top `top` (a backend pixel row): each
    /// series' marker and name, then the front's.
    fn draw_beside<DB: DrawingBackend>(
        &self,
        chart: &Chart,
        area: &DrawingArea<DB, Shift>,
        top: i32,
    ) -> DrawResult<DB> {
        let (_, area_top) = area.get_base_pixel();
        let mut y = (top - area_top).max(0) + 12;
        let label = |name: &str, y: i32| Text::new(name.to_string(), (28, y - 9), self.style.clone());
        for s in chart
            .series
            .iter()
            .filter(|s| !s.name.is_empty() && !s.points.is_empty())
        {
            area.draw(&Circle::new((14, y), POINT_RADIUS, rgb(s.color).filled()))?;
            area.draw(&label(&s.name, y))?;
            y += LEGEND_ROW;
        }
        if let Some(f) = &chart.front {
            area.draw(&PathElement::new(vec![(4, y), (24, y)], FRONT.stroke_width(2)))?;
            area.draw(&Circle::new((14, y), RING_RADIUS, FRONT.stroke_width(2)))?;
            area.draw(&label(&f.name, y))?;
        }
        Ok(())
    }
}

/// Draws `chart` on `root`: titles, axes and ticks, fit lines, the front line, the points, the front's rings,
/// the legend in a clear corner of the plot (beside it when none is), and the front's labels where they overlap
/// nothing.
fn draw<DB: DrawingBackend>(chart: &Chart, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (width, _) = root.dim_in_pixel();
    let text = |size: f64| TextStyle::from((FAMILY, size).into_font()).color(&INK);
    root.draw(&Text::new(chart.title.clone(), (24, 14), text(TITLE_SIZE)))?;
    let note_style = text(TEXT_SIZE).color(&NOTE);
    let mut top = 52;
    for n in &chart.notes {
        let line = fit_text(root, n, &note_style, width.saturating_sub(48));
        root.draw(&Text::new(line, (24, top), note_style.clone()))?;
        top += 24;
    }
    let (_, body) = root.split_vertically(top + 6);

    let ([x0, x1], [y0, y1]) = chart.bounds();
    let x_ticks = chart.x_ticks(x0, x1);
    let y_ticks = chart.y_ticks(y0, y1);
    let build = |area: &DrawingArea<DB, Shift>| {
        ChartBuilder::on(area)
            .margin_left(16)
            .margin_right(32)
            .margin_bottom(12)
            .x_label_area_size(64)
            .y_label_area_size(88)
            .build_cartesian_2d(
                TickedAxis::new(x0, x1, &x_ticks),
                TickedAxis::new(y0, y1, &y_ticks),
            )
    };
    let legend = Legend::of(chart, root, text(LABEL_SIZE));
    // The legend sits in a corner of the plot when one is clear of every point and line, else beside it.
    let corner = legend.corner(chart, &build(&body)?);
    let (plot_area, side) = match corner {
        Some(_) => (body.clone(), None),
        None => {
            let (w, _) = body.dim_in_pixel();
            let (plot, side) = body.split_horizontally(w.saturating_sub(legend.size.0 as u32 + 24));
            (plot, Some(side))
        }
    };
    let mut cc = build(&plot_area)?;
    let x_label = |v: &f64| chart.x_tick_label(*v, x0, x1);
    let y_label = |v: &f64| {
        y_ticks
            .iter()
            .find(|t| (t.at - v).abs() < 1e-12)
            .and_then(|t| t.label.clone())
            .unwrap_or_default()
    };
    cc.configure_mesh()
        .x_desc(chart.x.label.as_str())
        .y_desc(chart.y.label.as_str())
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .label_style(text(LABEL_SIZE))
        .axis_desc_style(text(TEXT_SIZE))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(240, 240, 240))
        .axis_style(INK)
        .draw()?;

    let at = |p: &Point| (chart.plot_x(p.x), chart.plot_y(p.y));
    let finite = |p: &&Point| chart.plot_x(p.x).is_finite() && chart.plot_y(p.y).is_finite();
    // The break between the "0" column and the logarithmic axis.
    if let Some(z) = chart.zero_column() {
        let bx = z + ZERO_GAP * 0.5;
        let (px, py) = cc.backend_coord(&(bx, y0));
        let (_, ptop) = cc.backend_coord(&(bx, y1));
        root.draw(&Rectangle::new(
            [(px - 4, ptop), (px + 4, py + 3)],
            WHITE.filled(),
        ))?;
        for dx in [-4, 3] {
            root.draw(&PathElement::new(
                vec![(px + dx - 3, py + 6), (px + dx + 3, py - 6)],
                INK.stroke_width(2),
            ))?;
        }
    }
    for s in chart.series.iter().filter(|s| s.mark == Mark::Line) {
        let pts: Vec<(f64, f64)> = s.points.iter().filter(finite).map(at).collect();
        cc.draw_series(std::iter::once(PathElement::new(
            pts,
            rgb(s.color).stroke_width(2),
        )))?;
    }
    let front_pts: Vec<&Point> = chart
        .front
        .iter()
        .flat_map(|f| &f.points)
        .filter(finite)
        .collect();
    if let Some(f) = &chart.front {
        let line: Vec<(f64, f64)> = front_pts.iter().map(|p| at(p)).collect();
        cc.draw_series(std::iter::once(PathElement::new(line, FRONT.stroke_width(2))))?
            .label(f.name.clone())
            .legend(|(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(-12, 0), (12, 0)], FRONT.stroke_width(2))
                    + Circle::new((0, 0), RING_RADIUS, FRONT.stroke_width(2))
            });
    }
    let mut occupied: Vec<PxBox> = Vec::new();
    for s in chart.series.iter().filter(|s| s.mark == Mark::Points) {
        let color = rgb(s.color);
        let pts: Vec<(f64, f64)> = s.points.iter().filter(finite).map(at).collect();
        for p in &pts {
            let (x, y) = cc.backend_coord(p);
            occupied.push([
                x - POINT_RADIUS,
                y - POINT_RADIUS,
                x + POINT_RADIUS,
                y + POINT_RADIUS,
            ]);
        }
        let drawn = cc.draw_series(
            pts.into_iter()
                .map(|p| Circle::new(p, POINT_RADIUS, color.filled())),
        )?;
        if !s.name.is_empty() {
            drawn
                .label(s.name.clone())
                .legend(move |(x, y)| Circle::new((x, y), POINT_RADIUS, color.filled()));
        }
    }
    let front_px: Vec<(i32, i32)> = front_pts.iter().map(|p| cc.backend_coord(&at(p))).collect();
    cc.draw_series(
        front_pts
            .iter()
            .map(|p| Circle::new(at(p), RING_RADIUS, FRONT.stroke_width(2))),
    )?;
    for &(x, y) in &front_px {
        let r = RING_RADIUS + 1;
        occupied.push([x - r, y - r, x + r, y + r]);
    }

    let (ax, ay) = cc.backend_coord(&(x0, y1));
    let (bx, by) = cc.backend_coord(&(x1, y0));
    match (corner, side) {
        (Some((position, b)), _) => {
            cc.configure_series_labels()
                .position(position)
                .margin(12)
                .legend_area_size(36)
                .label_font(legend.style.clone())
                .background_style(WHITE.mix(0.92))
                .border_style(RGBColor(160, 160, 160))
                .draw()?;
            occupied.push(b);
        }
        (None, Some(side)) => legend.draw_beside(chart, &side, ay)?,
        (None, None) => {}
    }

    // Labels keep off the front line: sample it every 2 pixels.
    let line_samples: Vec<(i32, i32)> = front_px
        .windows(2)
        .flat_map(|w| {
            let (dx, dy) = ((w[1].0 - w[0].0) as f64, (w[1].1 - w[0].1) as f64);
            let n = (dx.hypot(dy) / 2.0).ceil().max(1.0) as i32;
            (0..=n).map(move |i| {
                let t = i as f64 / n as f64;
                (w[0].0 + (t * dx) as i32, w[0].1 + (t * dy) as i32)
            })
        })
        .collect();
    let plot = [ax, ay, bx, by];
    for (p, &(x, y)) in front_pts.iter().zip(&front_px) {
        place_label(root, plot, &mut occupied, &line_samples, (x, y), &p.label)?;
    }
    Ok(())
}

/// Puts `label` beside the point at `at` where it stays inside `plot` and overlaps nothing placed yet nor any
/// of `avoid` (right, left, above, below, then diagonally); leaves it out when every place is taken.
fn place_label<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: PxBox,
    occupied: &mut Vec<PxBox>,
    avoid: &[(i32, i32)],
    (x, y): (i32, i32),
    label: &str,
) -> DrawResult<DB> {
    let style = TextStyle::from((FAMILY, LABEL_SIZE).into_font()).color(&INK);
    let (tw, th) = root
        .estimate_text_size(label, &style)
        .map(|(w, h)| (w as i32, h as i32))
        .unwrap_or((0, 0));
    let (pad, d) = (2, RING_RADIUS + 4);
    let candidates = [
        (x + d, y - th / 2),
        (x - d - tw, y - th / 2),
        (x - tw / 2, y - d - th),
        (x - tw / 2, y + d),
        (x + d, y - d - th),
        (x + d, y + d),
        (x - d - tw, y - d - th),
        (x - d - tw, y + d),
    ];
    for (lx, ly) in candidates {
        let r = [lx - pad, ly - pad, lx + tw + pad, ly + th + pad];
        let inside = r[0] > plot[0] && r[1] > plot[1] && r[2] < plot[2] && r[3] < plot[3];
        let clear = !occupied.iter().any(|o| overlaps(*o, r))
            && !avoid
                .iter()
                .any(|&(ax, ay)| (r[0]..=r[2]).contains(&ax) && (r[1]..=r[3]).contains(&ay));
        if inside && clear {
            root.draw(&Rectangle::new(
                [(r[0], r[1]), (r[2], r[3])],
                WHITE.mix(0.85).filled(),
            ))?;
            root.draw(&Text::new(label.to_string(), (lx, ly), style))?;
            occupied.push(r);
            return Ok(());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn font_has_the_glyphs_the_charts_print() {
        use ab_glyph::Font;
        let font = ab_glyph::FontRef::try_from_slice(FONT).unwrap();
        for c in ['×', '²', 'Δ', 'σ', '±', 'A', 'z', '0', '|', '.'] {
            assert_ne!(font.glyph_id(c).0, 0, "no glyph for {c}");
        }
    }
}
