//! The bench's PNG charts, drawn without a font or plotting crate: a 5×7 bitmap font for printable ASCII (with
//! an eighth row for descenders), anti-aliased discs, rings and lines, and a scatter chart with a linear or
//! logarithmic x axis, tick labels, axis titles, a legend and a highlighted front (the Pareto front) with
//! labelled points. The axes span the point series; line series (fits) are clipped to the plot.
//!
//! A logarithmic axis cannot show 0, and a configuration whose own passes cost nothing measurable (the opaque
//! shadow map reuses the shared light-depth pass) has 0 ms: such points sit in a separate "0" column left of
//! the logarithmic axis, behind an axis break.

use image::{Rgba, RgbaImage};

/// Glyph size in font pixels (row 7 holds only descenders); glyphs advance by `GLYPH_W + 1`.
pub const GLYPH_W: u32 = 5;
pub const GLYPH_H: u32 = 8;

/// Printable ASCII (`' '..='~'`), one glyph per character: five columns, bit `r` of a column is row `r`
/// (row 0 at the top, row 7 the descenders of g, j, p, q, y).
const FONT: [[u8; 5]; 95] = [
    [0x00, 0x00, 0x00, 0x00, 0x00], // ' '
    [0x00, 0x00, 0x5F, 0x00, 0x00], // !
    [0x00, 0x07, 0x00, 0x07, 0x00], // "
    [0x14, 0x7F, 0x14, 0x7F, 0x14], // #
    [0x24, 0x2A, 0x7F, 0x2A, 0x12], // $
    [0x23, 0x13, 0x08, 0x64, 0x62], // %
    [0x36, 0x49, 0x55, 0x22, 0x50], // &
    [0x00, 0x05, 0x03, 0x00, 0x00], // '
    [0x00, 0x1C, 0x22, 0x41, 0x00], // (
    [0x00, 0x41, 0x22, 0x1C, 0x00], // )
    [0x08, 0x2A, 0x1C, 0x2A, 0x08], // *
    [0x08, 0x08, 0x3E, 0x08, 0x08], // +
    [0x00, 0x50, 0x30, 0x00, 0x00], // ,
    [0x08, 0x08, 0x08, 0x08, 0x08], // -
    [0x00, 0x60, 0x60, 0x00, 0x00], // .
    [0x20, 0x10, 0x08, 0x04, 0x02], // /
    [0x3E, 0x51, 0x49, 0x45, 0x3E], // 0
    [0x00, 0x42, 0x7F, 0x40, 0x00], // 1
    [0x42, 0x61, 0x51, 0x49, 0x46], // 2
    [0x21, 0x41, 0x45, 0x4B, 0x31], // 3
    [0x18, 0x14, 0x12, 0x7F, 0x10], // 4
    [0x27, 0x45, 0x45, 0x45, 0x39], // 5
    [0x3C, 0x4A, 0x49, 0x49, 0x30], // 6
    [0x01, 0x71, 0x09, 0x05, 0x03], // 7
    [0x36, 0x49, 0x49, 0x49, 0x36], // 8
    [0x06, 0x49, 0x49, 0x29, 0x1E], // 9
    [0x00, 0x36, 0x36, 0x00, 0x00], // :
    [0x00, 0x56, 0x36, 0x00, 0x00], // ;
    [0x08, 0x14, 0x22, 0x41, 0x00], // <
    [0x14, 0x14, 0x14, 0x14, 0x14], // =
    [0x00, 0x41, 0x22, 0x14, 0x08], // >
    [0x02, 0x01, 0x51, 0x09, 0x06], // ?
    [0x32, 0x49, 0x79, 0x41, 0x3E], // @
    [0x7E, 0x11, 0x11, 0x11, 0x7E], // A
    [0x7F, 0x49, 0x49, 0x49, 0x36], // B
    [0x3E, 0x41, 0x41, 0x41, 0x22], // C
    [0x7F, 0x41, 0x41, 0x22, 0x1C], // D
    [0x7F, 0x49, 0x49, 0x49, 0x41], // E
    [0x7F, 0x09, 0x09, 0x09, 0x01], // F
    [0x3E, 0x41, 0x49, 0x49, 0x7A], // G
    [0x7F, 0x08, 0x08, 0x08, 0x7F], // H
    [0x00, 0x41, 0x7F, 0x41, 0x00], // I
    [0x20, 0x40, 0x41, 0x3F, 0x01], // J
    [0x7F, 0x08, 0x14, 0x22, 0x41], // K
    [0x7F, 0x40, 0x40, 0x40, 0x40], // L
    [0x7F, 0x02, 0x0C, 0x02, 0x7F], // M
    [0x7F, 0x04, 0x08, 0x10, 0x7F], // N
    [0x3E, 0x41, 0x41, 0x41, 0x3E], // O
    [0x7F, 0x09, 0x09, 0x09, 0x06], // P
    [0x3E, 0x41, 0x51, 0x21, 0x5E], // Q
    [0x7F, 0x09, 0x19, 0x29, 0x46], // R
    [0x46, 0x49, 0x49, 0x49, 0x31], // S
    [0x01, 0x01, 0x7F, 0x01, 0x01], // T
    [0x3F, 0x40, 0x40, 0x40, 0x3F], // U
    [0x1F, 0x20, 0x40, 0x20, 0x1F], // V
    [0x3F, 0x40, 0x38, 0x40, 0x3F], // W
    [0x63, 0x14, 0x08, 0x14, 0x63], // X
    [0x07, 0x08, 0x70, 0x08, 0x07], // Y
    [0x61, 0x51, 0x49, 0x45, 0x43], // Z
    [0x00, 0x7F, 0x41, 0x41, 0x00], // [
    [0x02, 0x04, 0x08, 0x10, 0x20], // \
    [0x00, 0x41, 0x41, 0x7F, 0x00], // ]
    [0x04, 0x02, 0x01, 0x02, 0x04], // ^
    [0x40, 0x40, 0x40, 0x40, 0x40], // _
    [0x00, 0x01, 0x02, 0x04, 0x00], // `
    [0x20, 0x54, 0x54, 0x54, 0x78], // a
    [0x7F, 0x48, 0x44, 0x44, 0x38], // b
    [0x38, 0x44, 0x44, 0x44, 0x20], // c
    [0x38, 0x44, 0x44, 0x48, 0x7F], // d
    [0x38, 0x54, 0x54, 0x54, 0x18], // e
    [0x08, 0x7E, 0x09, 0x01, 0x02], // f
    [0x18, 0xA4, 0xA4, 0xA4, 0x7C], // g
    [0x7F, 0x08, 0x04, 0x04, 0x78], // h
    [0x00, 0x44, 0x7D, 0x40, 0x00], // i
    [0x40, 0x80, 0x80, 0x7D, 0x00], // j
    [0x7F, 0x10, 0x28, 0x44, 0x00], // k
    [0x00, 0x41, 0x7F, 0x40, 0x00], // l
    [0x7C, 0x04, 0x18, 0x04, 0x78], // m
    [0x7C, 0x08, 0x04, 0x04, 0x78], // n
    [0x38, 0x44, 0x44, 0x44, 0x38], // o
    [0xFC, 0x24, 0x24, 0x24, 0x18], // p
    [0x18, 0x24, 0x24, 0x24, 0xFC], // q
    [0x7C, 0x08, 0x04, 0x04, 0x08], // r
    [0x48, 0x54, 0x54, 0x54, 0x20], // s
    [0x04, 0x3F, 0x44, 0x40, 0x20], // t
    [0x3C, 0x40, 0x40, 0x20, 0x7C], // u
    [0x1C, 0x20, 0x40, 0x20, 0x1C], // v
    [0x3C, 0x40, 0x30, 0x40, 0x3C], // w
    [0x44, 0x28, 0x10, 0x28, 0x44], // x
    [0x1C, 0xA0, 0xA0, 0xA0, 0x7C], // y
    [0x44, 0x64, 0x54, 0x4C, 0x44], // z
    [0x00, 0x08, 0x36, 0x41, 0x00], // {
    [0x00, 0x00, 0x7F, 0x00, 0x00], // |
    [0x00, 0x41, 0x36, 0x08, 0x00], // }
    [0x08, 0x04, 0x08, 0x10, 0x08], // ~
];

/// The glyph of `c`; characters outside printable ASCII draw as `?`.
pub fn glyph(c: char) -> [u8; 5] {
    let i = match c {
        ' '..='~' => c as usize - ' ' as usize,
        _ => '?' as usize - ' ' as usize,
    };
    FONT[i]
}

/// Whether font pixel (`col`, `row`) of `c` is set.
pub fn glyph_pixel(c: char, col: u32, row: u32) -> bool {
    col < GLYPH_W && row < GLYPH_H && glyph(c)[col as usize] >> row & 1 == 1
}

/// Width in image pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    if n == 0 {
        0
    } else {
        (n * (GLYPH_W + 1) - 1) * scale
    }
}

pub type Color = [u8; 3];

/// Blends `color` into the pixel at (`x`, `y`) with coverage `a` in [0, 1]; outside the image it does nothing.
fn blend(img: &mut RgbaImage, x: i64, y: i64, color: Color, a: f64) {
    if x < 0 || y < 0 || x >= img.width() as i64 || y >= img.height() as i64 || a <= 0.0 {
        return;
    }
    let a = a.min(1.0);
    let p = img.get_pixel_mut(x as u32, y as u32);
    for (dst, src) in p.0.iter_mut().zip(color) {
        *dst = (*dst as f64 * (1.0 - a) + src as f64 * a).round() as u8;
    }
    p.0[3] = 255;
}

/// Draws `text` with its top-left corner at (`x`, `y`), each font pixel a `scale`×`scale` square.
pub fn draw_text(img: &mut RgbaImage, x: i64, y: i64, text: &str, scale: u32, color: Color) {
    let s = scale as i64;
    for (i, c) in text.chars().enumerate() {
        let gx = x + i as i64 * (GLYPH_W as i64 + 1) * s;
        for col in 0..GLYPH_W {
            for row in 0..GLYPH_H {
                if glyph_pixel(c, col, row) {
                    fill_rect(img, gx + col as i64 * s, y + row as i64 * s, s, s, color, 1.0);
                }
            }
        }
    }
}

/// Draws `text` reading upwards (turned 90° anticlockwise) with its baseline's start at (`x`, `y`): the text
/// occupies `x..x + 7·scale` and `y - width..y`.
pub fn draw_text_up(img: &mut RgbaImage, x: i64, y: i64, text: &str, scale: u32, color: Color) {
    let s = scale as i64;
    for (i, c) in text.chars().enumerate() {
        let gy = y - i as i64 * (GLYPH_W as i64 + 1) * s;
        for col in 0..GLYPH_W {
            for row in 0..GLYPH_H {
                if glyph_pixel(c, col, row) {
                    fill_rect(
                        img,
                        x + row as i64 * s,
                        gy - (col as i64 + 1) * s,
                        s,
                        s,
                        color,
                        1.0,
                    );
                }
            }
        }
    }
}

/// Fills a rectangle with `color` at opacity `a`.
pub fn fill_rect(img: &mut RgbaImage, x: i64, y: i64, w: i64, h: i64, color: Color, a: f64) {
    for py in y..y + h {
        for px in x..x + w {
            blend(img, px, py, color, a);
        }
    }
}

/// A pixel rectangle `[x0, x1) × [y0, y1)` that drawing is kept inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clip {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Clip {
    fn whole(img: &RgbaImage) -> Clip {
        Clip {
            x0: 0.0,
            y0: 0.0,
            x1: img.width() as f64,
            y1: img.height() as f64,
        }
    }
}

/// Calls `f(x, y, px, py)` for every pixel of the box `center ± r` inside `clip`, with the pixel centre.
fn for_pixels(clip: Clip, cx: f64, cy: f64, rx: f64, ry: f64, mut f: impl FnMut(i64, i64, f64, f64)) {
    let x0 = (cx - rx).floor().max(clip.x0) as i64;
    let x1 = (cx + rx).ceil().min(clip.x1 - 1.0) as i64;
    let y0 = (cy - ry).floor().max(clip.y0) as i64;
    let y1 = (cy + ry).ceil().min(clip.y1 - 1.0) as i64;
    for y in y0..=y1 {
        for x in x0..=x1 {
            f(x, y, x as f64 + 0.5, y as f64 + 0.5);
        }
    }
}

/// An anti-aliased filled disc.
pub fn fill_disc(img: &mut RgbaImage, clip: Clip, cx: f64, cy: f64, r: f64, color: Color) {
    let mut cover = Vec::new();
    for_pixels(clip, cx, cy, r + 1.0, r + 1.0, |x, y, px, py| {
        let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt();
        cover.push((x, y, (r + 0.5 - d).clamp(0.0, 1.0)));
    });
    for (x, y, a) in cover {
        blend(img, x, y, color, a);
    }
}

/// An anti-aliased ring of radius `r` and line width `w`.
pub fn stroke_ring(img: &mut RgbaImage, clip: Clip, cx: f64, cy: f64, r: f64, w: f64, color: Color) {
    let mut cover = Vec::new();
    for_pixels(clip, cx, cy, r + w + 1.0, r + w + 1.0, |x, y, px, py| {
        let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt();
        cover.push((x, y, (w * 0.5 + 0.5 - (d - r).abs()).clamp(0.0, 1.0)));
    });
    for (x, y, a) in cover {
        blend(img, x, y, color, a);
    }
}

/// An anti-aliased polyline of width `w` (round joints, each pixel covered once).
pub fn stroke_polyline(img: &mut RgbaImage, clip: Clip, points: &[(f64, f64)], w: f64, color: Color) {
    if points.is_empty() {
        return;
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for &(x, y) in points {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let (cx, cy) = ((lo.0 + hi.0) * 0.5, (lo.1 + hi.1) * 0.5);
    let (rx, ry) = ((hi.0 - lo.0) * 0.5 + w + 1.0, (hi.1 - lo.1) * 0.5 + w + 1.0);
    let segments: Vec<_> = if points.len() == 1 {
        vec![(points[0], points[0])]
    } else {
        points.windows(2).map(|p| (p[0], p[1])).collect()
    };
    let mut cover = Vec::new();
    for_pixels(clip, cx, cy, rx, ry, |x, y, px, py| {
        let d = segments
            .iter()
            .map(|&(a, b)| segment_distance((px, py), a, b))
            .fold(f64::INFINITY, f64::min);
        let a = (w * 0.5 + 0.5 - d).clamp(0.0, 1.0);
        if a > 0.0 {
            cover.push((x, y, a));
        }
    });
    for (x, y, a) in cover {
        blend(img, x, y, color, a);
    }
}

fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p.0 - a.0 - t * dx).powi(2) + (p.1 - a.1 - t * dy).powi(2)).sqrt()
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A disc per point.
    Points,
    /// A line through the points in order.
    Line,
}

/// One named, coloured set of points.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub color: Color,
    pub style: Style,
    pub points: Vec<[f64; 2]>,
}

/// A point of the highlighted front, with its label.
#[derive(Clone, Debug, PartialEq)]
pub struct FrontPoint {
    pub x: f64,
    pub y: f64,
    pub label: String,
}

/// A scatter chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub title: String,
    /// Smaller lines under the title (the scene and the device), separated by `\n`.
    pub subtitle: String,
    pub x_label: String,
    pub y_label: String,
    /// Logarithmic x axis (points with x <= 0 go to the "0" column).
    pub x_log: bool,
    pub series: Vec<Series>,
    /// Connected in x order and ringed; named `front_name` in the legend. Empty: none.
    pub front: Vec<FrontPoint>,
    pub front_name: String,
}

const WHITE: Color = [255, 255, 255];
const INK: Color = [30, 30, 30];
const GRID: Color = [225, 225, 225];
const GRID_MINOR: Color = [242, 242, 242];
const FRONT: Color = [0, 0, 0];

/// Text scale of tick labels and axis titles.
const SCALE: u32 = 2;
/// Width of the "0" column of a logarithmic axis, and the gap after it.
const ZERO_COLUMN: f64 = 44.0;
const ZERO_GAP: f64 = 22.0;
const POINT_RADIUS: f64 = 5.0;
/// Line spacing of `SCALE` text.
const LINE_HEIGHT: f64 = 22.0;
/// Text scale of the front's point labels.
const LABEL_SCALE: u32 = 2;

/// A data range mapped onto a pixel range.
#[derive(Clone, Copy, Debug)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    p0: f64,
    p1: f64,
}

impl Axis {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
    fn map(&self, v: f64) -> f64 {
        self.p0 + self.t(v) * (self.p1 - self.p0)
    }
}

/// A tick: its value and, for a major (labelled, darker) one, its label.
struct Tick {
    value: f64,
    label: Option<String>,
}

/// `v` with `decimals` decimals.
fn fmt_fixed(v: f64, decimals: i32) -> String {
    format!("{v:.*}", decimals.max(0) as usize)
}

/// Ticks at 1..9 × 10^k over `[lo, hi]`: decades labelled, and the 2 and 5 multiples too when the range spans
/// at most 2.5 decades.
fn log_ticks(lo: f64, hi: f64) -> Vec<Tick> {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let few = (hi / lo).log10() <= 2.5;
    let mut out = Vec::new();
    for k in k0..=k1 {
        for m in 1..10 {
            let v = m as f64 * 10f64.powi(k);
            if v < lo * (1.0 - 1e-9) || v > hi * (1.0 + 1e-9) {
                continue;
            }
            let labelled = m == 1 || (few && (m == 2 || m == 5));
            out.push(Tick {
                value: v,
                label: labelled.then(|| fmt_fixed(v, -k)),
            });
        }
    }
    out
}

/// A 1-2-5 step giving about `target` intervals over `span`, and its decimal exponent.
fn nice_step(span: f64, target: f64) -> (f64, i32) {
    let raw = (span / target).max(f64::MIN_POSITIVE);
    let e = raw.log10().floor() as i32;
    let base = 10f64.powi(e);
    let m = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| m * base >= raw)
        .unwrap_or(10.0);
    if m == 10.0 {
        (base * 10.0, e + 1)
    } else {
        (m * base, e)
    }
}

fn linear_ticks(lo: f64, hi: f64, step: f64, e: i32) -> Vec<Tick> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|i| {
            let v = i as f64 * step;
            Tick {
                value: v,
                label: Some(if i == 0 { "0".to_string() } else { fmt_fixed(v, -e) }),
            }
        })
        .collect()
}

/// A linear range starting at `min(0, lo)` ending on a tick at or above `hi`, and its ticks.
fn linear_range(lo: f64, hi: f64) -> (f64, f64, Vec<Tick>) {
    let lo = lo.min(0.0);
    let hi = if hi > lo { hi } else { lo + 1.0 };
    let (step, e) = nice_step(hi - lo, 8.0);
    let top = (hi / step).ceil() * step;
    let bottom = (lo / step).floor() * step;
    (bottom, top, linear_ticks(bottom, top, step, e))
}

/// A logarithmic range from the largest 1, 2 or 5 × 10^k below `lo` to the smallest above `hi` (positive), with
/// a little room on both sides.
fn log_range(lo: f64, hi: f64) -> (f64, f64) {
    let nice = |k: i32| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k));
    let (lo, hi) = (lo / 1.15, hi * 1.15);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let below = (k0..=k0 + 1)
        .flat_map(nice)
        .filter(|v| *v <= lo)
        .fold(10f64.powi(k0), f64::max);
    let above = (k1 - 1..=k1)
        .flat_map(nice)
        .filter(|v| *v >= hi)
        .fold(10f64.powi(k1), f64::min);
    (below, above.max(below * 2.0))
}

/// Renders `chart` as a `width`×`height` image.
pub fn render(chart: &Chart, width: u32, height: u32) -> RgbaImage {
    let mut img = RgbaImage::from_pixel(width, height, Rgba([255, 255, 255, 255]));
    let (w, h) = (width as f64, height as f64);
    let s = SCALE as f64;
    // Titles.
    draw_text(&mut img, 20, 14, &chart.title, 3, INK);
    let mut top = 44.0;
    for line in chart.subtitle.lines() {
        draw_text(&mut img, 20, top as i64, line, SCALE, [90, 90, 90]);
        top += LINE_HEIGHT;
    }
    let plot = Clip {
        x0: 120.0,
        y0: top + 14.0,
        x1: w - 30.0,
        y1: h - 80.0,
    };
    // The axes span the points (lines, such as fits, are clipped to them).
    let all: Vec<[f64; 2]> = chart
        .series
        .iter()
        .filter(|se| se.style == Style::Points)
        .flat_map(|se| se.points.iter().copied())
        .chain(chart.front.iter().map(|f| [f.x, f.y]))
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    // x axis: logarithmic over the positive values, with a "0" column when some are not positive.
    let zero_column = chart.x_log && all.iter().any(|p| p[0] <= 0.0);
    let x_axis_start = if zero_column {
        plot.x0 + ZERO_COLUMN + ZERO_GAP
    } else {
        plot.x0
    };
    let (x_axis, x_ticks) = if chart.x_log {
        let pos: Vec<f64> = all.iter().map(|p| p[0]).filter(|x| *x > 0.0).collect();
        let (lo, hi) = if pos.is_empty() {
            (0.1, 10.0)
        } else {
            log_range(
                pos.iter().copied().fold(f64::INFINITY, f64::min),
                pos.iter().copied().fold(0.0, f64::max),
            )
        };
        let axis = Axis {
            lo,
            hi,
            log: true,
            p0: x_axis_start + 8.0,
            p1: plot.x1 - 8.0,
        };
        (axis, log_ticks(lo, hi))
    } else {
        let (lo, hi) = min_max(all.iter().map(|p| p[0]));
        let (lo, hi, ticks) = linear_range(lo, hi);
        let axis = Axis {
            lo,
            hi,
            log: false,
            p0: plot.x0,
            p1: plot.x1 - 8.0,
        };
        (axis, ticks)
    };
    let (ylo, yhi) = min_max(all.iter().map(|p| p[1]));
    let (ylo, yhi, y_ticks) = linear_range(ylo, yhi * 1.05);
    let y_axis = Axis {
        lo: ylo,
        hi: yhi,
        log: false,
        p0: plot.y1 - 10.0,
        p1: plot.y0 + 8.0,
    };
    let px = |x: f64| -> f64 {
        if chart.x_log && x <= 0.0 {
            plot.x0 + ZERO_COLUMN * 0.5
        } else {
            x_axis.map(x)
        }
    };
    let py = |y: f64| y_axis.map(y);
    // Grid and ticks.
    for t in &x_ticks {
        let x = x_axis.map(t.value).round() + 0.5;
        let color = if t.label.is_some() { GRID } else { GRID_MINOR };
        stroke_polyline(&mut img, plot, &[(x, plot.y0), (x, plot.y1)], 1.0, color);
        fill_rect(&mut img, x as i64, plot.y1 as i64, 1, 6, INK, 1.0);
        if let Some(l) = &t.label {
            let tw = text_width(l, SCALE) as f64;
            draw_text(
                &mut img,
                (x - tw / 2.0) as i64,
                plot.y1 as i64 + 10,
                l,
                SCALE,
                INK,
            );
        }
    }
    for t in &y_ticks {
        let y = y_axis.map(t.value).round() + 0.5;
        stroke_polyline(&mut img, plot, &[(plot.x0, y), (plot.x1, y)], 1.0, GRID);
        fill_rect(&mut img, plot.x0 as i64 - 6, y as i64, 6, 1, INK, 1.0);
        if let Some(l) = &t.label {
            let tw = text_width(l, SCALE) as f64;
            draw_text(
                &mut img,
                (plot.x0 - 10.0 - tw) as i64,
                (y - 3.5 * s) as i64,
                l,
                SCALE,
                INK,
            );
        }
    }
    // The frame, and the break between the "0" column and the logarithmic axis.
    let frame = [
        (plot.x0, plot.y0),
        (plot.x1, plot.y0),
        (plot.x1, plot.y1),
        (plot.x0, plot.y1),
        (plot.x0, plot.y0),
    ];
    let whole = Clip::whole(&img);
    stroke_polyline(&mut img, whole, &frame, 1.5, INK);
    if zero_column {
        let x = plot.x0 + ZERO_COLUMN * 0.5;
        fill_rect(&mut img, x as i64, plot.y1 as i64, 1, 6, INK, 1.0);
        draw_text(
            &mut img,
            (x - s * 2.5) as i64,
            plot.y1 as i64 + 10,
            "0",
            SCALE,
            INK,
        );
        let bx = plot.x0 + ZERO_COLUMN + ZERO_GAP * 0.5;
        fill_rect(
            &mut img,
            bx as i64 - 5,
            plot.y0 as i64 + 1,
            10,
            (plot.y1 - plot.y0) as i64 - 1,
            WHITE,
            1.0,
        );
        fill_rect(&mut img, bx as i64 - 5, plot.y1 as i64 - 1, 10, 4, WHITE, 1.0);
        for dx in [-4.0, 3.0] {
            let line = [(bx + dx - 3.0, plot.y1 + 6.0), (bx + dx + 3.0, plot.y1 - 6.0)];
            stroke_polyline(&mut img, whole, &line, 1.5, INK);
        }
    }
    // Axis titles.
    let tw = text_width(&chart.x_label, SCALE) as f64;
    draw_text(
        &mut img,
        ((plot.x0 + plot.x1 - tw) / 2.0) as i64,
        h as i64 - 36,
        &chart.x_label,
        SCALE,
        INK,
    );
    let th = text_width(&chart.y_label, SCALE) as f64;
    draw_text_up(
        &mut img,
        18,
        ((plot.y0 + plot.y1 + th) / 2.0) as i64,
        &chart.y_label,
        SCALE,
        INK,
    );
    // Data: lines, then the front line, then the points, then the front's rings and labels.
    let inner = Clip {
        x0: plot.x0 + 1.0,
        y0: plot.y0 + 1.0,
        x1: plot.x1 - 1.0,
        y1: plot.y1 - 1.0,
    };
    for se in chart.series.iter().filter(|se| se.style == Style::Line) {
        let pts: Vec<(f64, f64)> = se.points.iter().map(|p| (px(p[0]), py(p[1]))).collect();
        stroke_polyline(&mut img, inner, &pts, 2.0, se.color);
    }
    let mut front: Vec<&FrontPoint> = chart.front.iter().collect();
    front.sort_by(|a, b| a.x.total_cmp(&b.x).then(b.y.total_cmp(&a.y)));
    let front_px: Vec<(f64, f64)> = front.iter().map(|f| (px(f.x), py(f.y))).collect();
    stroke_polyline(&mut img, inner, &front_px, 2.0, FRONT);
    let mut occupied: Vec<[f64; 4]> = Vec::new();
    for se in chart.series.iter().filter(|se| se.style == Style::Points) {
        for p in &se.points {
            let (x, y) = (px(p[0]), py(p[1]));
            fill_disc(&mut img, inner, x, y, POINT_RADIUS, se.color);
            occupied.push([
                x - POINT_RADIUS,
                y - POINT_RADIUS,
                x + POINT_RADIUS,
                y + POINT_RADIUS,
            ]);
        }
    }
    for &(x, y) in &front_px {
        let r = POINT_RADIUS + 3.0;
        stroke_ring(&mut img, inner, x, y, r, 1.5, FRONT);
        occupied.push([x - r - 1.0, y - r - 1.0, x + r + 1.0, y + r + 1.0]);
    }
    // The legend goes in the corner with the fewest points; labels avoid the legend, points and each other.
    let legend = legend_entries(chart);
    let (lw, lh) = legend_size(&legend);
    let corners = [
        (plot.x1 - lw - 10.0, plot.y0 + 10.0),
        (plot.x0 + 10.0, plot.y0 + 10.0),
        (plot.x1 - lw - 10.0, plot.y1 - lh - 10.0),
        (x_axis_start + 10.0, plot.y1 - lh - 10.0),
    ];
    let (lx, ly) = corners
        .into_iter()
        .min_by_key(|&(x, y)| {
            occupied
                .iter()
                .filter(|r| overlaps(**r, [x - 12.0, y - 12.0, x + lw + 12.0, y + lh + 12.0]))
                .count()
        })
        .unwrap_or(corners[0]);
    if !legend.is_empty() {
        draw_legend(&mut img, lx, ly, lw, lh, &legend);
        occupied.push([lx, ly, lx + lw, ly + lh]);
    }
    // Labels keep off the front line too: sample it every 2 pixels.
    let line_samples: Vec<(f64, f64)> = front_px
        .windows(2)
        .flat_map(|w| {
            let n = (((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)) / 2.0).ceil().max(1.0) as usize;
            (0..=n).map(move |i| {
                let t = i as f64 / n as f64;
                (w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1))
            })
        })
        .collect();
    for (f, &(x, y)) in front.iter().zip(&front_px) {
        place_label(&mut img, inner, &mut occupied, &line_samples, x, y, &f.label);
    }
    img
}

fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

fn overlaps(a: [f64; 4], b: [f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// One legend line: a marker and a name; `None` colour: the front (a line through a ring).
struct LegendEntry {
    color: Option<Color>,
    name: String,
}

fn legend_entries(chart: &Chart) -> Vec<LegendEntry> {
    let mut out: Vec<LegendEntry> = chart
        .series
        .iter()
        .filter(|se| !se.points.is_empty() && !se.name.is_empty())
        .map(|se| LegendEntry {
            color: Some(se.color),
            name: se.name.clone(),
        })
        .collect();
    if !chart.front.is_empty() {
        out.push(LegendEntry {
            color: None,
            name: chart.front_name.clone(),
        });
    }
    out
}

const LEGEND_LINE: f64 = 22.0;

fn legend_size(entries: &[LegendEntry]) -> (f64, f64) {
    let text = entries
        .iter()
        .map(|e| text_width(&e.name, SCALE))
        .max()
        .unwrap_or(0) as f64;
    (text + 50.0, entries.len() as f64 * LEGEND_LINE + 12.0)
}

fn draw_legend(img: &mut RgbaImage, x: f64, y: f64, w: f64, h: f64, entries: &[LegendEntry]) {
    fill_rect(img, x as i64, y as i64, w as i64, h as i64, WHITE, 0.92);
    let border = [(x, y), (x + w, y), (x + w, y + h), (x, y + h), (x, y)];
    let whole = Clip::whole(img);
    stroke_polyline(img, whole, &border, 1.0, [160, 160, 160]);
    for (i, e) in entries.iter().enumerate() {
        let cy = y + 6.0 + LEGEND_LINE * (i as f64 + 0.5);
        let cx = x + 20.0;
        match e.color {
            Some(c) => fill_disc(img, whole, cx, cy, POINT_RADIUS, c),
            None => {
                stroke_polyline(img, whole, &[(cx - 12.0, cy), (cx + 12.0, cy)], 2.0, FRONT);
                stroke_ring(img, whole, cx, cy, POINT_RADIUS + 3.0, 1.5, FRONT);
            }
        }
        draw_text(
            img,
            (x + 38.0) as i64,
            (cy - 3.5 * SCALE as f64) as i64,
            &e.name,
            SCALE,
            INK,
        );
    }
}

/// Puts `label` beside the point at (`x`, `y`) where it overlaps nothing placed yet nor any of `avoid` (right,
/// left, above, below, then diagonally); leaves it out when every place is taken.
fn place_label(
    img: &mut RgbaImage,
    clip: Clip,
    occupied: &mut Vec<[f64; 4]>,
    avoid: &[(f64, f64)],
    x: f64,
    y: f64,
    label: &str,
) {
    let scale = LABEL_SCALE;
    let (tw, th) = (text_width(label, scale) as f64, (GLYPH_H * scale) as f64);
    let pad = 2.0;
    let d = POINT_RADIUS + 6.0;
    let candidates = [
        (x + d, y - th / 2.0),
        (x - d - tw, y - th / 2.0),
        (x - tw / 2.0, y - d - th),
        (x - tw / 2.0, y + d),
        (x + d, y - d - th),
        (x + d, y + d),
        (x - d - tw, y - d - th),
        (x - d - tw, y + d),
    ];
    for (lx, ly) in candidates {
        let r = [lx - pad, ly - pad, lx + tw + pad, ly + th + pad];
        let inside = r[0] >= clip.x0 && r[1] >= clip.y0 && r[2] <= clip.x1 && r[3] <= clip.y1;
        let clear = !occupied.iter().any(|o| overlaps(*o, r))
            && !avoid
                .iter()
                .any(|&(ax, ay)| (r[0]..=r[2]).contains(&ax) && (r[1]..=r[3]).contains(&ay));
        if inside && clear {
            fill_rect(
                img,
                r[0] as i64,
                r[1] as i64,
                (r[2] - r[0]) as i64,
                (r[3] - r[1]) as i64,
                WHITE,
                0.85,
            );
            draw_text(img, lx as i64, ly as i64, label, scale, INK);
            occupied.push(r);
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_label_decades() {
        let t = log_ticks(0.1, 100.0);
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
        assert_eq!(t.len(), 28);
    }

    #[test]
    fn linear_range_ends_on_ticks() {
        let (lo, hi, t) = linear_range(0.0, 0.27);
        assert_eq!(lo, 0.0);
        assert!((hi - 0.3).abs() < 1e-12, "{hi}");
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0", "0.05", "0.10", "0.15", "0.20", "0.25", "0.30"]);
    }
}
