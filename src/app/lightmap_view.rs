//! The light-map view: a per-texel quantity of the light's exact fragment lists (nearest depth, furthest depth,
//! depth range, depth complexity, occupied occupancy-map slices) or one value the selected method stores (an
//! opacity slice or layer, a cluster density, a slab count; built by its CPU model, which the GPU matches) as an
//! image in a plot that zooms and pans, with a colour scale and the value under the cursor. Clicking a texel
//! inspects it: [`LightMapView::ui`] reads the inspector's lists through [`LightMapDeps`] and returns the
//! clicked texel.

use super::inspector::{ReferenceLists, inspected};
use crate::methods::registry;
use crate::settings::Settings;
use crate::visibility::{Fragment, OccupancyParams, TexelModel, occupancy};
use egui::Color32;
use egui_plot::{MarkerShape, Plot, PlotImage, PlotPoint, Points};

/// What the view shows per texel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MapQuantity {
    /// Fragments per texel.
    #[default]
    Complexity,
    Near,
    Far,
    /// `far - near`.
    Range,
    /// Set bits of the texel's 128-slice occupancy bitmap (Sintorn & Assarsson).
    OccupiedSlices,
    /// Value `LightMapView::stored` of what the selected method stores (`TexelModel::stored_values`).
    Stored,
}

impl MapQuantity {
    const ALL: [MapQuantity; 6] = [
        Self::Complexity,
        Self::Near,
        Self::Far,
        Self::Range,
        Self::OccupiedSlices,
        Self::Stored,
    ];

    fn label(self) -> &'static str {
        match self {
            Self::Complexity => "depth complexity",
            Self::Near => "nearest depth",
            Self::Far => "furthest depth",
            Self::Range => "depth range (far − near)",
            Self::OccupiedSlices => "occupied slices (of 128)",
            Self::Stored => "stored value of the method",
        }
    }

    /// The quantity of one texel's list (sorted by depth); NaN for an empty texel. `stored`: the selected
    /// method's model and the index of its stored value, for [`MapQuantity::Stored`].
    fn of(
        self,
        list: &[crate::render::passes::abuffer::RefFragment],
        stored: Option<(&dyn TexelModel, usize)>,
    ) -> f32 {
        let (Some(first), Some(last)) = (list.first(), list.last()) else {
            return f32::NAN;
        };
        let fragments = || -> Vec<Fragment> { list.iter().map(|f| f.fragment()).collect() };
        match self {
            Self::Complexity => list.len() as f32,
            Self::Near => first.depth,
            Self::Far => last.depth,
            Self::Range => last.depth - first.depth,
            Self::OccupiedSlices => {
                // The bitmap does not depend on alpha.
                let texel = occupancy::build(&OccupancyParams::new(0.5), &fragments());
                texel.occupancy.iter().map(|w| w.count_ones()).sum::<u32>() as f32
            }
            Self::Stored => stored
                .and_then(|(model, k)| model.stored_values(&fragments()).get(k).copied())
                .unwrap_or(f32::NAN),
        }
    }
}

/// The image of one quantity of one read of the lists.
struct MapImage {
    quantity: MapQuantity,
    /// The model (its `Debug` text: the parameters it was built with) and stored-value index a
    /// [`MapQuantity::Stored`] image shows.
    stored: Option<(String, usize)>,
    generation: u64,
    resolution: u32,
    /// Row-major, NaN where the texel is empty.
    values: Vec<f32>,
    min: f32,
    max: f32,
    texture: egui::TextureHandle,
}

/// The view's state.
#[derive(Default)]
pub struct LightMapView {
    /// The light-map window is shown.
    pub open: bool,
    pub quantity: MapQuantity,
    /// Which stored value [`MapQuantity::Stored`] shows (slice, layer, cluster or slab index).
    pub stored: usize,
    image: Option<MapImage>,
}

/// Colour of an empty texel.
const EMPTY: Color32 = Color32::from_rgb(24, 24, 28);

/// Viridis, by linear interpolation between five of its colours; `t` in `[0, 1]`.
fn viridis(t: f32) -> Color32 {
    const STOPS: [[f32; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f32;
    let c = |k: usize| (STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f).round() as u8;
    Color32::from_rgb(c(0), c(1), c(2))
}

impl MapImage {
    fn new(
        ctx: &egui::Context,
        lists: &ReferenceLists,
        quantity: MapQuantity,
        stored: Option<(&dyn TexelModel, usize)>,
    ) -> MapImage {
        let n = lists.resolution as usize;
        let values: Vec<f32> = lists
            .lists
            .iter()
            .take(n * n)
            .map(|l| quantity.of(l, stored))
            .collect();
        let (min, max) = values
            .iter()
            .filter(|v| !v.is_nan())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let pixels = values
            .iter()
            .map(|&v| {
                if v.is_nan() {
                    EMPTY
                } else {
                    viridis(scale(v, min, max))
                }
            })
            .collect();
        let texture = ctx.load_texture(
            "hairlab.light_map",
            egui::ColorImage::new([n, n], pixels),
            egui::TextureOptions::NEAREST,
        );
        MapImage {
            quantity,
            stored: stored.map(|(m, k)| (format!("{m:?}"), k)),
            generation: lists.generation,
            resolution: lists.resolution,
            values,
            min,
            max,
            texture,
        }
    }

    fn value_text(&self, v: f32) -> String {
        match (v.is_nan(), self.quantity) {
            (true, _) => "empty".into(),
            (false, MapQuantity::Complexity) if v == 1.0 => "1 fragment".into(),
            (false, MapQuantity::Complexity) => format!("{v:.0} fragments"),
            (false, MapQuantity::OccupiedSlices) => format!("{v:.0} slices"),
            (false, _) => format!("{v:.5}"),
        }
    }
}

/// `v` in `[min, max]` mapped to `[0, 1]` (0.5 when the range is a point).
fn scale(v: f32, min: f32, max: f32) -> f32 {
    if max > min { (v - min) / (max - min) } else { 0.5 }
}

/// An axis label: the texel coordinate, none off the map.
fn axis_label(v: f64, res: u32) -> String {
    if (0.0..=f64::from(res)).contains(&v) {
        format!("{v:.0}")
    } else {
        String::new()
    }
}

/// The texel under plot point `p` (row 0 at the top of the image, which spans `[0, res]²`).
fn texel_at(p: PlotPoint, res: u32) -> Option<[u32; 2]> {
    let (x, y) = (p.x.floor(), (f64::from(res) - p.y).floor());
    let inside = |v: f64| (0.0..f64::from(res)).contains(&v);
    (inside(x) && inside(y)).then_some([x as u32, y as u32])
}

/// The plot point at the centre of texel `[x, y]`.
fn texel_centre([x, y]: [u32; 2], res: u32) -> [f64; 2] {
    [f64::from(x) + 0.5, f64::from(res - y) - 0.5]
}

/// What the light-map view reads besides its own state.
#[derive(Clone, Copy)]
pub struct LightMapDeps<'a> {
    /// The inspector's reference fragment lists, if read.
    pub lists: Option<&'a ReferenceLists>,
    /// The selected method, its parameters and the hair alpha (for [`MapQuantity::Stored`]).
    pub settings: &'a Settings,
    /// The inspected scene texel, marked in white.
    pub selected: Option<[u32; 2]>,
    /// The scene pins' texels, marked in their colours.
    pub pins: &'a [([u32; 2], Color32)],
}

impl LightMapView {
    /// The window's contents. Returns the texel to inspect when one was clicked (or "Densest texel" was).
    pub fn ui(&mut self, ui: &mut egui::Ui, deps: LightMapDeps<'_>) -> Option<[u32; 2]> {
        let densest = deps.lists.and_then(ReferenceLists::densest);
        let mut chosen = None;
        ui.horizontal(|ui| {
            let l = ui.label("show");
            egui::ComboBox::from_id_salt("light_map_quantity")
                .selected_text(self.quantity.label())
                .show_ui(ui, |ui| {
                    for q in MapQuantity::ALL {
                        ui.selectable_value(&mut self.quantity, q, q.label());
                    }
                })
                .response
                .labelled_by(l.id);
            if self.quantity == MapQuantity::Stored {
                ui.add(
                    egui::DragValue::new(&mut self.stored)
                        .range(0..=255)
                        .prefix("index "),
                )
                .on_hover_text("slice, layer, cluster or slab of the selected method");
            }
            if ui
                .add_enabled(densest.is_some(), egui::Button::new("Densest texel"))
                .on_hover_text("inspect the texel holding the most fragments")
                .clicked()
            {
                chosen = densest;
            }
        });
        let method = &deps.settings.method;
        let stored = match registry::find(&method.name) {
            Ok(m) if self.quantity == MapQuantity::Stored && inspected(m) => Some((
                m.model(&method.params, deps.settings.render.light_opacity()),
                self.stored,
            )),
            _ => None,
        };
        let Some(lists) = deps.lists else {
            ui.label("no fragment lists yet (see the status line)");
            return chosen;
        };
        let stored_key = stored.as_ref().map(|(m, k)| (format!("{m:?}"), *k));
        if self.quantity == MapQuantity::Stored && stored.is_none() {
            ui.label("the selected method stores no per-texel values beyond near/far");
            return chosen;
        }
        let fresh = self.image.as_ref().is_some_and(|i| {
            i.quantity == self.quantity && i.generation == lists.generation && i.stored == stored_key
        });
        if !fresh {
            let stored = stored.as_ref().map(|(m, k)| (m.as_ref(), *k));
            self.image = Some(MapImage::new(ui.ctx(), lists, self.quantity, stored));
        }
        let Some(image) = self.image.as_ref() else {
            return chosen;
        };
        let res = image.resolution;
        // A texel chosen this frame is the inspected one from now on.
        let selected = chosen.or(deps.selected);
        let marks: Vec<([f64; 2], Color32)> = selected
            .map(|t| (texel_centre(t, res), Color32::WHITE))
            .into_iter()
            .chain(deps.pins.iter().map(|&(t, c)| (texel_centre(t, res), c)))
            .filter(|(c, _)| c[0] < f64::from(res) && c[1] > 0.0)
            .collect();
        colour_scale(ui, image);
        let response = Plot::new("light_map_plot")
            .data_aspect(1.0)
            .show_grid(false)
            .include_x(0.0)
            .include_x(f64::from(res))
            .include_y(0.0)
            .include_y(f64::from(res))
            .height(ui.available_height().max(160.0))
            .x_axis_formatter(move |mark, _| axis_label(mark.value, res))
            .y_axis_formatter(move |mark, _| axis_label(f64::from(res) - mark.value, res))
            .label_formatter(|pos| {
                let p = match pos {
                    egui_plot::HoverPosition::NearDataPoint { position, .. } => position,
                    egui_plot::HoverPosition::Elsewhere { position } => position,
                };
                let [x, y] = texel_at(*p, res)?;
                let v = image.values[(y * res + x) as usize];
                Some(format!(
                    "texel ({x}, {y})\n{}: {}",
                    image.quantity.label(),
                    image.value_text(v)
                ))
            })
            .show(ui, |p| {
                let r = f64::from(res);
                p.image(PlotImage::new(
                    "light map",
                    image.texture.id(),
                    PlotPoint::new(r / 2.0, r / 2.0),
                    [r as f32, r as f32],
                ));
                for (c, color) in &marks {
                    p.points(
                        Points::new("selected", vec![*c])
                            .shape(MarkerShape::Circle)
                            .filled(false)
                            .radius(7.0)
                            .color(*color),
                    );
                }
                (p.response().clicked(), p.pointer_coordinate())
            });
        match response.inner {
            (true, Some(p)) => texel_at(p, res).or(chosen),
            _ => chosen,
        }
    }
}

/// The colour scale under the map: a gradient from the smallest to the largest value, the value under the
/// cursor on hover.
fn colour_scale(ui: &mut egui::Ui, image: &MapImage) {
    ui.horizontal(|ui| {
        ui.label(image.value_text(image.min));
        let width = (ui.available_width() - 90.0).max(60.0);
        let (rect, response) = ui.allocate_exact_size(egui::vec2(width, 14.0), egui::Sense::hover());
        let steps = 64;
        for i in 0..steps {
            let x0 = rect.left() + rect.width() * i as f32 / steps as f32;
            let x1 = rect.left() + rect.width() * (i + 1) as f32 / steps as f32;
            ui.painter().rect_filled(
                egui::Rect::from_x_y_ranges(x0..=x1, rect.y_range()),
                0.0,
                viridis((i as f32 + 0.5) / steps as f32),
            );
        }
        if let Some(p) = response.hover_pos() {
            let t = ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0);
            let v = image.min + (image.max - image.min) * t;
            response.on_hover_text_at_pointer(format!("{}: {}", image.quantity.label(), image.value_text(v)));
        }
        ui.label(image.value_text(image.max));
    });
    ui.weak("click: inspect · drag: pan · Ctrl+wheel: zoom · double-click: reset");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_points_map_to_texels_and_back() {
        // Row 0 is the top of the image: plot y in (res - 1, res].
        assert_eq!(texel_at(PlotPoint::new(0.5, 3.9), 4), Some([0, 0]));
        assert_eq!(texel_at(PlotPoint::new(3.2, 0.1), 4), Some([3, 3]));
        assert_eq!(texel_at(PlotPoint::new(-0.1, 2.0), 4), None);
        assert_eq!(texel_at(PlotPoint::new(1.0, 4.5), 4), None);
        for t in [[0, 0], [3, 1], [2, 3]] {
            let [x, y] = texel_centre(t, 4);
            assert_eq!(texel_at(PlotPoint::new(x, y), 4), Some(t));
        }
    }

    #[test]
    fn occupied_slices_and_stored_values() {
        use crate::render::passes::abuffer::RefFragment;
        use crate::visibility::OsmParams;
        let f = |depth| RefFragment {
            depth,
            alpha: 0.5,
            segment: 0,
        };
        // Range [0.2, 0.8] in 128 slices: 0.2 -> slice 0, 0.5 -> slice 64, 0.8 -> slice 127, 0.51 -> slice 66.
        let list = [f(0.2), f(0.5), f(0.51), f(0.8)];
        assert_eq!(MapQuantity::OccupiedSlices.of(&list, None), 4.0);
        assert_eq!(MapQuantity::OccupiedSlices.of(&[f(0.3), f(0.3)], None), 1.0);
        // OSM-4 planes: fragments in slices 0, 2, 2, 3 -> accumulated b at planes 1..4 = b, b, 3b, 4b (b = ln 2).
        let osm = OsmParams { slices: 4 };
        let b = 2f32.ln();
        for (k, want) in [(0, b), (1, b), (2, 3.0 * b), (3, 4.0 * b)] {
            let got = MapQuantity::Stored.of(&list, Some((&osm as &dyn TexelModel, k)));
            assert!((got - want).abs() < 1e-6, "plane {k}: {got} vs {want}");
        }
        assert!(
            MapQuantity::Stored
                .of(&list, Some((&osm as &dyn TexelModel, 4)))
                .is_nan(),
            "past the last plane"
        );
        assert!(
            MapQuantity::Stored
                .of(&[], Some((&osm as &dyn TexelModel, 0)))
                .is_nan(),
            "empty texel"
        );
    }

    #[test]
    fn colour_scale_ends() {
        assert_eq!(viridis(0.0), Color32::from_rgb(68, 1, 84));
        assert_eq!(viridis(1.0), Color32::from_rgb(253, 231, 37));
        assert_eq!(viridis(0.5), Color32::from_rgb(33, 145, 140));
        assert_eq!(scale(3.0, 1.0, 5.0), 0.5);
        assert_eq!(scale(2.0, 2.0, 2.0), 0.5);
    }
}
