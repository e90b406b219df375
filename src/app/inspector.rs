//! The texel inspector: one light-map texel's exact fragments, the reference visibility `V(z)` and the methods'
//! reconstructions of it, with what each method stores drawn on the plot and the texel's error figures.
//!
//! The curves come from the methods' CPU models (`ShadowMethod::model`, `visibility::<method>::build`), fed with
//! the texel's exact fragment list from the reference A-buffer; the GPU lookups equal these models (tested in
//! `tests/gpu_*.rs`), so the plot shows what the GPU computes. The fragment lists are read back on demand and
//! cached: they are refreshed only when the scene, the light, the map resolution or the hair alpha change, and not
//! while a drag is under way.
//!
//! A texel is chosen by clicking hair in the viewport ([`pick_segment`], then [`light_texel`]), by clicking the
//! light-map view (`lightmap_view.rs`), or made up in the synthetic texel lab (`texel_lab.rs`). Texels can be
//! pinned for comparison, and every curve shown exported as CSV.

use super::lightmap_view::LightMapView;
use super::texel_lab::{LabSettings, LabSource, MAX_GAUSSIANS, MAX_PER_GAUSSIAN, MAX_SPREAD};
use super::{DialogPurpose, HairlabApp};
use crate::methods::{ParamValues, registry};
use crate::methods::{Role, ShadowMethod};
use crate::render::light_frame::LightFrame;
use crate::render::passes::abuffer::RefFragment;
use crate::scene::{Light, Mesh, Strands};
use crate::settings::SceneSettings;
use crate::visibility::{self, Fragment, Stored, TexelError, TexelModel, depth_range, metrics};
use egui::Color32;
use egui_plot::{Legend, Line, LineStyle, MarkerShape, Plot, PlotPoints, Points, Polygon, VLine};
use glam::{Mat4, Vec2, Vec3, Vec4};
use std::path::Path;
use std::sync::Arc;

/// How far (in points) from a strand a click may land and still pick it.
const PICK_RADIUS: f32 = 4.0;
/// Texels around the picked one searched for the clicked segment's fragments: the rasteriser's line rule can put a
/// segment's fragment in a neighbour of the texel its clicked point projects to.
const PICK_SEARCH: i64 = 2;
/// Uniform samples of each curve across the plotted range (the events of [`plot_depths`] come on top).
const CURVE_SAMPLES: usize = 400;
/// Colours of pinned texels, in turn.
const PIN_COLORS: [Color32; 6] = [
    Color32::from_rgb(0, 200, 210),
    Color32::from_rgb(240, 200, 40),
    Color32::from_rgb(255, 120, 180),
    Color32::from_rgb(150, 220, 90),
    Color32::from_rgb(160, 160, 255),
    Color32::from_rgb(255, 160, 90),
];

/// Where the inspected fragments come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Source {
    /// A texel of the scene's light map.
    #[default]
    Scene,
    /// The synthetic texel lab.
    Synthetic,
}

/// A texel of the scene's light map and, when it was picked in the viewport, what was clicked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneTexel {
    pub texel: [u32; 2],
    pub picked: Option<Pick>,
}

/// A texel kept on the plot for comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Pin {
    pub label: String,
    pub color: Color32,
    source: PinSource,
}

impl Pin {
    /// The texel of a scene pin.
    pub fn texel(&self) -> Option<[u32; 2]> {
        match self.source {
            PinSource::Scene(t) => Some(t),
            PinSource::Synthetic { .. } => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum PinSource {
    /// A scene texel: its fragments follow the scene and the light.
    Scene([u32; 2]),
    /// A synthetic texel, frozen when pinned.
    Synthetic {
        fragments: Vec<Fragment>,
        hair_alpha: f32,
    },
}

/// What the reference fragment lists were read for.
#[derive(Clone, Debug, PartialEq)]
struct ListsKey {
    scene: Option<SceneSettings>,
    /// The light, without intensity and colour (they do not move fragments).
    light: Light,
    map_resolution: u32,
    /// The hair alpha's bits.
    hair_alpha: u32,
}

/// The reference's per-texel fragment lists of the current light view.
pub struct ReferenceLists {
    key: ListsKey,
    pub resolution: u32,
    /// Row-major texels (row 0 at the top of the map), each sorted by depth.
    pub lists: Vec<Vec<RefFragment>>,
    /// Increases with every read, so views of the lists know when to rebuild.
    pub generation: u64,
    densest: Option<[u32; 2]>,
}

impl ReferenceLists {
    /// The fragments of texel `[x, y]` (`None` outside the map).
    pub fn fragments(&self, [x, y]: [u32; 2]) -> Option<Vec<Fragment>> {
        let list = (x < self.resolution && y < self.resolution)
            .then(|| self.lists.get((y * self.resolution + x) as usize))??;
        Some(list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect())
    }

    /// `lists` holds `resolution²` texels (the A-buffer's heads), the resolution is taken from its length.
    fn new(key: ListsKey, lists: Vec<Vec<RefFragment>>, generation: u64) -> ReferenceLists {
        let resolution = lists.len().isqrt() as u32;
        let densest = lists
            .iter()
            .enumerate()
            .max_by_key(|(i, l)| (l.len(), std::cmp::Reverse(*i)))
            .filter(|(_, l)| !l.is_empty())
            .map(|(i, _)| [i as u32 % resolution, i as u32 / resolution]);
        ReferenceLists {
            key,
            resolution,
            lists,
            generation,
            densest,
        }
    }

    /// The texel holding the most fragments (the first in row-major order on ties), if any holds one.
    pub fn densest(&self) -> Option<[u32; 2]> {
        self.densest
    }
}

/// The inspector's state (the windows' contents, the cached fragment lists and curves).
#[derive(Default)]
pub struct Inspector {
    /// The inspector window is shown.
    pub open: bool,
    /// The light-map window is shown.
    pub show_light_map: bool,
    pub source: Source,
    /// The inspected scene texel.
    pub selected: Option<SceneTexel>,
    /// Plot every method with a CPU model, not only the selected one.
    pub show_all: bool,
    pub lab: LabSettings,
    pins: Vec<Pin>,
    pins_made: usize,
    pub(super) lists: Option<ReferenceLists>,
    /// The key of the last read attempt (a failed read is not retried until something changes).
    tried: Option<ListsKey>,
    /// The lists are older than the settings (a drag is under way).
    stale: bool,
    generation: u64,
    curves: Option<(CurvesInput, TexelCurves)>,
    lab_error: Option<String>,
    pub(super) map: LightMapView,
    /// Where the viewport is (the windows' first placement).
    viewport_rect: Option<egui::Rect>,
}

impl Inspector {
    /// The curves of the last frame (or of the last export).
    pub fn curves(&self) -> Option<&TexelCurves> {
        self.curves.as_ref().map(|(_, c)| c)
    }

    pub fn pins(&self) -> &[Pin] {
        &self.pins
    }

    pub fn remove_pin(&mut self, index: usize) {
        if index < self.pins.len() {
            self.pins.remove(index);
        }
    }

    /// The cached reference lists, if read.
    pub fn lists(&self) -> Option<&ReferenceLists> {
        self.lists.as_ref()
    }

    /// Pins the inspected texel (a scene texel, or the lab's fragments as they are now).
    pub fn pin_current(&mut self) {
        let source = match self.source {
            Source::Scene => match self.selected {
                Some(s) => PinSource::Scene(s.texel),
                None => return,
            },
            Source::Synthetic => match self.lab.fragments() {
                Ok(fragments) => PinSource::Synthetic {
                    hair_alpha: self.lab.hair_alpha(&fragments),
                    fragments,
                },
                Err(_) => return,
            },
        };
        if self.pins.iter().any(|p| p.source == source) {
            return;
        }
        let label = match &source {
            PinSource::Scene([x, y]) => format!("texel ({x}, {y})"),
            PinSource::Synthetic { .. } => self.lab.label(),
        };
        let color = PIN_COLORS[self.pins_made % PIN_COLORS.len()];
        self.pins_made += 1;
        self.pins.push(Pin { label, color, source });
    }

    /// Inspects scene texel `texel` (opens the window).
    pub(super) fn select(&mut self, texel: SceneTexel) {
        self.selected = Some(texel);
        self.source = Source::Scene;
        self.open = true;
    }

    /// Whether the scene's fragment lists are needed this frame.
    fn needs_lists(&self) -> bool {
        (self.open
            && (self.source == Source::Scene
                || self.pins.iter().any(|p| matches!(p.source, PinSource::Scene(_)))))
            || self.show_light_map
    }
}

/// A method's CPU model and the method's colour: what the plot needs of a method.
#[derive(Clone, Debug)]
pub struct PlotModel {
    pub model: Arc<dyn TexelModel>,
    pub color: Color32,
}

impl PlotModel {
    /// `method`'s model with `values` and its colour.
    pub fn of(method: &dyn ShadowMethod, values: &ParamValues, hair_alpha: f32) -> PlotModel {
        PlotModel {
            model: method.model(values, hair_alpha).into(),
            color: method_color(method),
        }
    }
}

/// One method's reconstruction of `V` on a texel.
#[derive(Clone, Debug)]
pub struct MethodCurve {
    /// Short name with the parameter that matters, e.g. `osm-16`.
    pub label: String,
    pub model: PlotModel,
    /// `V` at [`TexelPlot::depths`].
    pub values: Vec<f32>,
    /// Texel error against the reference (`metrics::texel_error`, default grid); `None` for an empty texel.
    pub error: Option<TexelError>,
    /// The method chosen in the side panel (its stored structure is drawn).
    pub selected: bool,
}

/// One texel's curves.
#[derive(Clone, Debug)]
pub struct TexelPlot {
    pub label: String,
    pub fragments: Vec<Fragment>,
    /// Nearest and furthest fragment depth (`(1, 0)` when empty, as the light-depth pass clears).
    pub near: f32,
    pub far: f32,
    /// Plotted depths: the range `[near, far]` with a margin on both sides (empty for an empty texel).
    pub depths: Vec<f32>,
    /// The exact reference at [`TexelPlot::depths`] (a step curve: each fragment depth `d` is sampled at `d`
    /// and just after it).
    pub reference: Vec<f32>,
    /// The reference's own texel error (0 by definition: a check of the metric).
    pub reference_error: Option<TexelError>,
    pub methods: Vec<MethodCurve>,
    /// A pin's colour.
    pub color: Option<Color32>,
}

impl TexelPlot {
    /// Depth complexity: the number of fragments.
    pub fn depth_complexity(&self) -> usize {
        self.fragments.len()
    }
}

/// Everything plotted.
#[derive(Clone, Debug, Default)]
pub struct TexelCurves {
    /// The inspected texel, when there is one.
    pub current: Option<TexelPlot>,
    /// What the selected method stores for the inspected texel.
    pub stored: Option<Stored>,
    pub pins: Vec<TexelPlot>,
}

impl TexelCurves {
    /// The depths of the CSV: every plotted depth of every texel, sorted, once each.
    pub fn csv_depths(&self) -> Vec<f32> {
        let mut zs: Vec<f32> = self
            .current
            .iter()
            .chain(&self.pins)
            .flat_map(|t| t.depths.iter().copied())
            .collect();
        zs.sort_by(f32::total_cmp);
        zs.dedup();
        zs
    }

    /// CSV `depth,reference,<method>...,pin1 reference,pin1 <method>...`: every curve shown, evaluated at
    /// [`TexelCurves::csv_depths`].
    pub fn csv(&self) -> String {
        let zs = self.csv_depths();
        let mut header = vec!["depth".to_string()];
        let mut columns: Vec<Vec<f32>> = Vec::new();
        let texels = self.current.iter().map(|t| (String::new(), t)).chain(
            self.pins
                .iter()
                .enumerate()
                .map(|(i, t)| (format!("pin{} ", i + 1), t)),
        );
        for (prefix, t) in texels {
            header.push(format!("{prefix}reference"));
            columns.push(visibility::Reference.curve(&t.fragments, &zs));
            for m in &t.methods {
                header.push(format!("{prefix}{}", m.label));
                columns.push(m.model.model.curve(&t.fragments, &zs));
            }
        }
        let mut out = header.join(",");
        out.push('\n');
        for (i, z) in zs.iter().enumerate() {
            out.push_str(&z.to_string());
            for c in &columns {
                out.push(',');
                out.push_str(&c[i].to_string());
            }
            out.push('\n');
        }
        out
    }
}

/// One texel to plot.
#[derive(Clone, Debug, PartialEq)]
struct TexelInput {
    label: String,
    fragments: Vec<Fragment>,
    /// The uniform alpha the occupancy model assumes.
    hair_alpha: f32,
    color: Option<Color32>,
}

/// Everything the curves depend on (they are recomputed when it changes).
#[derive(Clone, Debug, PartialEq)]
struct CurvesInput {
    current: Option<TexelInput>,
    pins: Vec<TexelInput>,
    method: String,
    params: ParamValues,
    show_all: bool,
}

/// Whether the inspector plots `method` against the reference: the approximations do; the reference is the
/// plot's own curve and the baselines are no transparency model.
pub fn inspected(method: &dyn ShadowMethod) -> bool {
    method.info().role == Role::Approximation
}

/// The models to plot and which of them is the selected method: the selected method's (if [`inspected`]), or
/// every inspected method's (the others at their default parameters).
fn models(
    method: &str,
    params: &ParamValues,
    show_all: bool,
    hair_alpha: f32,
) -> (Vec<PlotModel>, Option<usize>) {
    let empty = ParamValues::new();
    let mut out = Vec::new();
    let mut selected = None;
    for m in registry::all().iter().copied().filter(|m| inspected(*m)) {
        let is_selected = m.name() == method;
        if !(show_all || is_selected) {
            continue;
        }
        if is_selected {
            selected = Some(out.len());
        }
        out.push(PlotModel::of(
            m,
            if is_selected { params } else { &empty },
            hair_alpha,
        ));
    }
    (out, selected)
}

/// The plotted depth range of a texel: `[near, far]` with 5% of it (at least 0.005) on both sides.
pub fn plot_range(near: f32, far: f32) -> (f32, f32) {
    let margin = ((far - near) * 0.05).max(0.005);
    (near - margin, far + margin)
}

/// Plotted depths: [`CURVE_SAMPLES`] uniform samples of [`plot_range`], plus each event depth in range (fragment
/// depths, stored boundaries) and the next f32 after it, so that steps are drawn upright. Sorted, once each.
fn plot_depths(fragments: &[Fragment], events: impl Iterator<Item = f32>) -> Vec<f32> {
    if fragments.is_empty() {
        return Vec::new();
    }
    let (near, far) = depth_range(fragments);
    let (lo, hi) = plot_range(near, far);
    let mut zs: Vec<f32> = (0..CURVE_SAMPLES)
        .map(|i| lo + (hi - lo) * (i as f32 / (CURVE_SAMPLES - 1) as f32))
        .collect();
    for e in fragments.iter().map(|f| f.depth).chain(events) {
        if (lo..=hi).contains(&e) {
            zs.push(e);
            zs.push(e.next_up());
        }
    }
    zs.sort_by(f32::total_cmp);
    zs.dedup();
    zs
}

/// The curves of one texel for `models`, drawing on `stored`'s events for the samples.
fn texel_plot(
    input: &TexelInput,
    models: &[PlotModel],
    selected: Option<usize>,
    stored: Option<&Stored>,
) -> TexelPlot {
    let f = &input.fragments;
    let depths = plot_depths(f, stored.into_iter().flat_map(Stored::events));
    let (near, far) = depth_range(f);
    let grid = metrics::DEFAULT_GRID_POINTS;
    TexelPlot {
        label: input.label.clone(),
        fragments: f.clone(),
        near,
        far,
        reference: visibility::Reference.curve(f, &depths),
        reference_error: metrics::texel_error(&visibility::Reference, f, grid),
        methods: models
            .iter()
            .enumerate()
            .map(|(i, m)| MethodCurve {
                label: m.model.label(),
                model: m.clone(),
                values: m.model.curve(f, &depths),
                error: metrics::texel_error(m.model.as_ref(), f, grid),
                selected: selected == Some(i),
            })
            .collect(),
        depths,
        color: input.color,
    }
}

fn compute_curves(input: &CurvesInput) -> TexelCurves {
    let (current, stored) = match &input.current {
        Some(t) => {
            let (ms, selected) = models(&input.method, &input.params, input.show_all, t.hair_alpha);
            let stored = selected.and_then(|i| ms[i].model.stored(&t.fragments));
            (Some(texel_plot(t, &ms, selected, stored.as_ref())), stored)
        }
        None => (None, None),
    };
    let pins = input
        .pins
        .iter()
        .map(|t| {
            let (ms, selected) = models(&input.method, &input.params, false, t.hair_alpha);
            texel_plot(t, &ms, selected, None)
        })
        .collect();
    TexelCurves {
        current,
        stored,
        pins,
    }
}

/// A strand segment under a click: its id (the index of its first point, as the light passes number segments) and
/// the clicked point on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    pub segment: u32,
    pub world: Vec3,
    /// Normalised device depth of the point (0 near, 1 far).
    pub ndc_depth: f32,
}

/// Clips the segment `(a, b)` (clip-space and world pairs) to `z >= 0` (the near plane of a 0..1 depth range).
fn clip_near(mut a: (Vec4, Vec3), mut b: (Vec4, Vec3)) -> Option<((Vec4, Vec3), (Vec4, Vec3))> {
    if a.0.z < 0.0 && b.0.z < 0.0 {
        return None;
    }
    let cut = |p: (Vec4, Vec3), q: (Vec4, Vec3)| {
        let t = p.0.z / (p.0.z - q.0.z);
        (p.0.lerp(q.0, t), p.1.lerp(q.1, t))
    };
    if a.0.z < 0.0 {
        a = cut(a, b);
    } else if b.0.z < 0.0 {
        b = cut(b, a);
    }
    (a.0.w > 0.0 && b.0.w > 0.0).then_some((a, b))
}

/// Pixel position (origin top left, y down) and NDC depth of a clip-space point in an image of `size` pixels.
fn to_pixels(c: Vec4, size: Vec2) -> (Vec2, f32) {
    let n = c.truncate() / c.w;
    (
        Vec2::new((n.x * 0.5 + 0.5) * size.x, (0.5 - n.y * 0.5) * size.y),
        n.z,
    )
}

/// The front-most strand segment within `radius` pixels of `cursor` (pixels, origin top left) in an image of
/// `size` pixels drawn with `world_to_clip`, nearer than `max_ndc_depth` (an opaque surface under the cursor),
/// and its point closest to the cursor.
pub fn pick_segment(
    strands: &Strands,
    world_to_clip: Mat4,
    size: Vec2,
    cursor: Vec2,
    radius: f32,
    max_ndc_depth: f32,
) -> Option<Pick> {
    let mut best: Option<Pick> = None;
    for (start, n) in strands.ranges() {
        for i in start..(start + n).saturating_sub(1) {
            let (wa, wb) = (strands.points[i], strands.points[i + 1]);
            let a = (world_to_clip * wa.extend(1.0), wa);
            let b = (world_to_clip * wb.extend(1.0), wb);
            let Some((a, b)) = clip_near(a, b) else { continue };
            let ((pa, za), (pb, zb)) = (to_pixels(a.0, size), to_pixels(b.0, size));
            let d = pb - pa;
            let t = if d.length_squared() > 0.0 {
                ((cursor - pa).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            if (pa + d * t).distance(cursor) > radius {
                continue;
            }
            // NDC depth is affine in screen space; the world point needs the perspective-correct parameter.
            let z = za + (zb - za) * t;
            if z > max_ndc_depth || best.is_some_and(|p| p.ndc_depth <= z) {
                continue;
            }
            let s = (t / b.0.w) / ((1.0 - t) / a.0.w + t / b.0.w);
            best = Some(Pick {
                segment: i as u32,
                world: a.1.lerp(b.1, s),
                ndc_depth: z,
            });
        }
    }
    best
}

/// NDC depth of the nearest opaque triangle under `cursor` (1 when none): strands behind it cannot be picked.
pub fn mesh_depth(meshes: &[Mesh], world_to_clip: Mat4, size: Vec2, cursor: Vec2) -> f32 {
    let inv = world_to_clip.inverse();
    let ndc = Vec2::new(cursor.x / size.x * 2.0 - 1.0, 1.0 - cursor.y / size.y * 2.0);
    let origin = inv.project_point3(ndc.extend(0.0));
    let dir = inv.project_point3(ndc.extend(1.0)) - origin;
    let mut nearest = f32::INFINITY;
    for m in meshes {
        for tri in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions.get(tri[k] as usize).copied());
            let (Some(a), Some(b), Some(c)) = (a, b, c) else {
                continue;
            };
            // Möller-Trumbore, both faces.
            let (e1, e2) = (b - a, c - a);
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-12 {
                continue;
            }
            let s = origin - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = dir.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (0.0..nearest).contains(&t) {
                nearest = t;
            }
        }
    }
    if nearest.is_finite() {
        world_to_clip.project_point3(origin + dir * nearest).z
    } else {
        1.0
    }
}

/// The light-map texel of world point `p` in `frame` for a `resolution`² map (`uv = (ndc.x * 0.5 + 0.5,
/// 0.5 - ndc.y * 0.5)`, texel `floor(uv * resolution)`), and its normalised light depth; `None` outside the map.
pub fn light_texel(frame: &LightFrame, resolution: u32, p: Vec3) -> Option<([u32; 2], f32)> {
    let c = frame.world_to_clip() * p.extend(1.0);
    if c.w <= 0.0 || resolution == 0 {
        return None;
    }
    let uv = Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5);
    if !(0.0..1.0).contains(&uv.x) || !(0.0..1.0).contains(&uv.y) {
        return None;
    }
    let t = (uv * resolution as f32)
        .floor()
        .as_uvec2()
        .min(glam::UVec2::splat(resolution - 1));
    Some(([t.x, t.y], frame.depth(p)))
}

/// The texel near `texel` (within [`PICK_SEARCH`]) that holds a fragment of `segment`, the nearest one first and
/// then the one whose fragment depth is closest to `depth`; `texel` itself when none does.
pub fn resolve_pick(lists: &ReferenceLists, texel: [u32; 2], segment: u32, depth: f32) -> [u32; 2] {
    let res = i64::from(lists.resolution);
    let mut best: Option<((i64, f32), [u32; 2])> = None;
    for dy in -PICK_SEARCH..=PICK_SEARCH {
        for dx in -PICK_SEARCH..=PICK_SEARCH {
            let (x, y) = (i64::from(texel[0]) + dx, i64::from(texel[1]) + dy);
            if !(0..res).contains(&x) || !(0..res).contains(&y) {
                continue;
            }
            let list = lists
                .lists
                .get((y * res + x) as usize)
                .map_or(&[][..], Vec::as_slice);
            for f in list.iter().filter(|f| f.segment == segment) {
                let key = (dx.abs().max(dy.abs()), (f.depth - depth).abs());
                if best.is_none_or(|(k, _)| key < k) {
                    best = Some((key, [x as u32, y as u32]));
                }
            }
        }
    }
    best.map_or(texel, |(_, t)| t)
}

/// Colour of a method's curves: the method's own ([`crate::methods::MethodInfo::color`]).
pub fn method_color(m: &dyn ShadowMethod) -> Color32 {
    let [r, g, b] = m.info().color;
    Color32::from_rgb(r, g, b)
}

fn series(depths: &[f32], values: &[f32]) -> PlotPoints<'static> {
    depths
        .iter()
        .zip(values)
        .map(|(&z, &v)| [f64::from(z), f64::from(v)])
        .collect()
}

/// A filled box from `x0` to `x1` between `y0` and `y1`.
fn band(name: &str, [x0, x1]: [f32; 2], (y0, y1): (f64, f64), color: Color32) -> Polygon<'static> {
    let (x0, x1) = (f64::from(x0), f64::from(x1));
    Polygon::new(name, vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
        .fill_color(color.gamma_multiply(0.45))
        .stroke(egui::Stroke::new(1.0, color))
}

/// One labelled grid row; the label names the widget for screen readers.
fn row(ui: &mut egui::Ui, label: &str, widget: impl egui::Widget) -> egui::Response {
    let l = ui.label(label);
    let r = ui.add(widget).labelled_by(l.id);
    ui.end_row();
    r
}

fn error_text(e: Option<TexelError>) -> (String, String) {
    match e {
        Some(e) => (format!("{:.5}", e.mean), format!("{:.5}", e.max)),
        None => ("–".into(), "–".into()),
    }
}

impl HairlabApp {
    /// Inspects texel `(x, y)` of the scene's light map (row 0 at the top) and opens the inspector.
    pub fn select_texel(&mut self, x: u32, y: u32) {
        self.inspector.select(SceneTexel {
            texel: [x, y],
            picked: None,
        });
    }

    pub fn inspector(&self) -> &Inspector {
        &self.inspector
    }

    pub fn inspector_mut(&mut self) -> &mut Inspector {
        &mut self.inspector
    }

    /// Writes every curve shown (see [`TexelCurves::csv`]) to `path`; the outcome goes to the status line.
    pub fn export_inspector_csv(&mut self, path: &Path) {
        self.refresh_lists(true);
        self.update_curves();
        let Some(curves) = self.inspector.curves() else {
            return self.error("texel inspector: nothing to export (select a texel first)");
        };
        if curves.current.is_none() && curves.pins.is_empty() {
            return self.error("texel inspector: nothing to export (select a texel first)");
        }
        let rows = curves.csv_depths().len();
        match crate::io::write_atomic(path, curves.csv().as_bytes()) {
            Ok(()) => self.info(format!("curves exported: {} ({rows} depths)", path.display())),
            Err(e) => self.error(format!("curve export failed: {e:#}")),
        }
    }

    /// The side panel's switches for the inspector windows.
    pub(super) fn inspector_controls(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.inspector.open, "Texel inspector")
                .on_hover_text(
                    "V(z) of one light-map texel: click hair in the viewport or a texel in the light map",
                );
            ui.checkbox(&mut self.inspector.show_light_map, "Light map")
                .on_hover_text("the light's depth maps and depth complexity; click a texel to inspect it");
        });
    }

    /// The inspector and light-map windows (each frame; they do nothing while closed).
    pub(super) fn inspector_windows(&mut self, ctx: &egui::Context) {
        if !(self.inspector.open || self.inspector.show_light_map) {
            return;
        }
        let dragging = ctx.input(|i| i.pointer.any_down());
        self.refresh_lists(!dragging);
        self.update_curves();
        // First placement: the inspector along the bottom of the viewport, the light map in its top right corner,
        // so that the hair stays in view for picking.
        let area = self.inspector.viewport_rect.unwrap_or_else(|| ctx.content_rect());
        let width = (area.width() - 16.0).clamp(300.0, 900.0);
        let mut open = self.inspector.open;
        egui::Window::new("Texel inspector")
            .open(&mut open)
            .default_pos([area.left() + 8.0, (area.bottom() - 440.0).max(area.top())])
            .default_size([width, 400.0])
            .show(ctx, |ui| self.inspector_ui(ui, ctx));
        self.inspector.open = open;
        let mut open = self.inspector.show_light_map;
        egui::Window::new("Light map")
            .open(&mut open)
            .default_pos([(area.right() - 350.0).max(area.left()), area.top() + 8.0])
            .default_size([340.0, (area.height() - 470.0).clamp(240.0, 420.0)])
            .show(ctx, |ui| self.light_map_ui(ui));
        self.inspector.show_light_map = open;
    }

    /// Viewport input: a click without drag picks the strand under the cursor and inspects its light texel.
    pub(super) fn viewport_click(&mut self, response: &egui::Response, width: u32, height: u32, ppp: f32) {
        self.inspector.viewport_rect = Some(response.rect);
        if !response.clicked() {
            return;
        }
        let Some(pos) = response.interact_pointer_pos() else {
            return;
        };
        let (Some(r), Some(scene)) = (&self.renderer, &self.scene) else {
            return;
        };
        let m = r.world_to_clip(&self.settings.camera, width, height);
        let size = Vec2::new(width as f32, height as f32);
        let cursor = Vec2::new(pos.x - response.rect.min.x, pos.y - response.rect.min.y) * ppp;
        let limit = mesh_depth(&scene.meshes, m, size, cursor);
        let Some(pick) = pick_segment(&scene.strands, m, size, cursor, PICK_RADIUS * ppp, limit) else {
            if self.inspector.open {
                self.info("no strand under the cursor");
            }
            return;
        };
        let frame = r.hair_light_frame(&self.settings.light);
        let Some((texel, depth)) = light_texel(&frame, self.settings.render.map_resolution, pick.world)
        else {
            return self.error("the picked point lies outside the light map");
        };
        self.inspector.select(SceneTexel {
            texel,
            picked: Some(pick),
        });
        self.refresh_lists(true);
        let texel = match &self.inspector.lists {
            Some(l) if l.key == self.lists_key() => resolve_pick(l, texel, pick.segment, depth),
            _ => texel,
        };
        self.inspector.select(SceneTexel {
            texel,
            picked: Some(pick),
        });
        self.info(format!(
            "picked segment {} at light depth {depth:.4}: texel ({}, {})",
            pick.segment, texel[0], texel[1]
        ));
    }

    /// Marks the picked point in the viewport while its texel is inspected.
    pub(super) fn paint_pick(&self, painter: &egui::Painter, rect: egui::Rect, width: u32, height: u32) {
        let (true, Source::Scene, Some(SceneTexel { picked: Some(p), .. }), Some(r)) = (
            self.inspector.open,
            self.inspector.source,
            self.inspector.selected,
            &self.renderer,
        ) else {
            return;
        };
        let c = r.world_to_clip(&self.settings.camera, width, height) * p.world.extend(1.0);
        if c.w <= 0.0 {
            return;
        }
        let (px, _) = to_pixels(c, Vec2::new(rect.width(), rect.height()));
        let at = rect.min + egui::vec2(px.x, px.y);
        painter.circle_stroke(at, 7.0, egui::Stroke::new(2.0, Color32::YELLOW));
        painter.circle_filled(at, 1.5, Color32::YELLOW);
    }

    fn lists_key(&self) -> ListsKey {
        let mut light = self.settings.light;
        light.intensity = 0.0;
        light.color = [0.0; 3];
        ListsKey {
            scene: self.built_scene.clone(),
            light,
            map_resolution: self.settings.render.map_resolution,
            hair_alpha: self.settings.render.hair_alpha.to_bits(),
        }
    }

    /// Reads the reference lists again when what they depend on changed (and `allow`, i.e. no drag is under
    /// way); a failed read is reported once and not retried until something changes.
    fn refresh_lists(&mut self, allow: bool) {
        if !self.inspector.needs_lists() {
            return;
        }
        let key = self.lists_key();
        if self.inspector.lists.as_ref().is_some_and(|l| l.key == key) {
            self.inspector.stale = false;
            return;
        }
        self.inspector.stale = self.inspector.lists.is_some();
        if !allow || self.inspector.tried.as_ref() == Some(&key) {
            return;
        }
        self.inspector.tried = Some(key.clone());
        match self.read_reference_lists() {
            Ok(lists) => {
                self.inspector.generation += 1;
                self.inspector.lists = Some(ReferenceLists::new(key, lists, self.inspector.generation));
                self.inspector.stale = false;
                // The light pass replaced the frame's timings: render the viewport again to show its own.
                self.last_rendered = None;
            }
            Err(e) => {
                self.inspector.lists = None;
                self.error(format!("texel inspector: {e}"));
            }
        }
    }

    /// Renders the reference's light pass for the current settings and reads its fragment lists back.
    fn read_reference_lists(&mut self) -> Result<Vec<Vec<RefFragment>>, String> {
        let r = self
            .renderer
            .as_mut()
            .ok_or("no GPU renderer: only the synthetic texel lab works")?;
        let s = &self.settings;
        r.reference_lists(&s.camera, &s.light, &s.render)
            .map_err(|e| e.to_string())
    }

    fn curves_input(&mut self) -> CurvesInput {
        let alpha = self.settings.render.hair_alpha;
        let insp = &mut self.inspector;
        let scene_fragments = |t: [u32; 2]| insp.lists.as_ref().and_then(|l| l.fragments(t));
        let current = match insp.source {
            Source::Scene => insp.selected.and_then(|s| {
                Some(TexelInput {
                    label: format!("texel ({}, {})", s.texel[0], s.texel[1]),
                    fragments: scene_fragments(s.texel)?,
                    hair_alpha: alpha,
                    color: None,
                })
            }),
            Source::Synthetic => insp.lab.fragments().ok().map(|fragments| TexelInput {
                label: insp.lab.label(),
                hair_alpha: insp.lab.hair_alpha(&fragments),
                fragments,
                color: None,
            }),
        };
        // Every pin, so that the plot, the CSV and the list number them alike (a scene pin without fragment
        // lists, or outside the map, is empty).
        let pins = insp
            .pins
            .iter()
            .map(|p| {
                let (fragments, hair_alpha) = match &p.source {
                    PinSource::Scene(t) => (scene_fragments(*t).unwrap_or_default(), alpha),
                    PinSource::Synthetic {
                        fragments,
                        hair_alpha,
                    } => (fragments.clone(), *hair_alpha),
                };
                TexelInput {
                    label: p.label.clone(),
                    fragments,
                    hair_alpha,
                    color: Some(p.color),
                }
            })
            .collect();
        CurvesInput {
            current,
            pins,
            method: self.settings.method.name.clone(),
            params: self.settings.method.params.clone(),
            show_all: self.inspector.show_all,
        }
    }

    /// Recomputes the curves when their inputs changed; reports a new error in the lab's typed fragments.
    fn update_curves(&mut self) {
        let lab_error = match self.inspector.source {
            Source::Synthetic => self.inspector.lab.fragments().err(),
            Source::Scene => None,
        };
        if lab_error != self.inspector.lab_error {
            if let Some(e) = &lab_error {
                self.error(e.clone());
            }
            self.inspector.lab_error = lab_error;
        }
        let input = self.curves_input();
        if self.inspector.curves.as_ref().is_some_and(|(i, _)| *i == input) {
            return;
        }
        let curves = compute_curves(&input);
        self.inspector.curves = Some((input, curves));
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        ui.horizontal(|ui| {
            let insp = &mut self.inspector;
            ui.selectable_value(&mut insp.source, Source::Scene, "Scene texel");
            ui.selectable_value(&mut insp.source, Source::Synthetic, "Synthetic texel");
            ui.separator();
            ui.checkbox(&mut insp.show_all, "every method")
                .on_hover_text("plot every method with a CPU model (the others at their default parameters)");
            if ui
                .button("Pin")
                .on_hover_text("keep this texel's curves on the plot")
                .clicked()
            {
                insp.pin_current();
            }
            if ui
                .button("Export CSV…")
                .on_hover_text("depth, reference and every curve shown")
                .clicked()
            {
                self.open_dialog(DialogPurpose::ExportCurves, ctx);
            }
        });
        match self.inspector.source {
            Source::Scene => self.scene_source_ui(ui),
            Source::Synthetic => self.lab_ui(ui),
        }
        let method = registry::find(&self.settings.method.name).ok();
        if let Some(m) = method.filter(|m| !inspected(*m)) {
            ui.label(format!(
                "{} has no per-texel model: tick \"every method\" to compare the others",
                m.label()
            ));
        }
        self.pins_ui(ui);
        ui.separator();
        // The plot takes the height left, so that resizing the window resizes it.
        let height = ui.available_height().max(220.0);
        let Some((input, curves)) = self.inspector.curves.take() else {
            return;
        };
        ui.horizontal_top(|ui| {
            let side = 250.0;
            let width = (ui.available_width() - side).max(200.0);
            ui.vertical(|ui| {
                ui.set_width(width);
                plot(ui, &curves, height);
            });
            ui.vertical(|ui| {
                ui.set_width(side - 10.0);
                figures(ui, &curves);
            });
        });
        self.inspector.curves = Some((input, curves));
    }

    fn scene_source_ui(&mut self, ui: &mut egui::Ui) {
        let res = self.settings.render.map_resolution;
        let insp = &mut self.inspector;
        ui.horizontal_wrapped(|ui| {
            match insp.selected {
                Some(s) if s.texel[0] < res && s.texel[1] < res => {
                    ui.label(format!(
                        "texel ({}, {}) of the {res}² light map",
                        s.texel[0], s.texel[1]
                    ));
                }
                Some(_) => {
                    ui.label(format!(
                        "the selected texel lies outside the {res}² map: pick another"
                    ));
                }
                None => {
                    ui.label("no texel yet: click hair in the viewport, or a texel in the light map");
                }
            }
            if !insp.show_light_map && ui.button("Open light map").clicked() {
                insp.show_light_map = true;
            }
        });
        match &insp.lists {
            Some(l) => {
                let fragments: usize = l.lists.iter().map(Vec::len).sum();
                let stale = if insp.stale {
                    " (from before the drag; updates on release)"
                } else {
                    ""
                };
                ui.weak(format!("exact fragment lists: {fragments} fragments{stale}"));
            }
            None => {
                ui.weak("no fragment lists (see the status line)");
            }
        }
    }

    fn lab_ui(&mut self, ui: &mut egui::Ui) {
        let lab = &mut self.inspector.lab;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut lab.source, LabSource::Gaussians, "Gaussian mixture");
            ui.selectable_value(&mut lab.source, LabSource::Typed, "Typed fragments");
        });
        match lab.source {
            LabSource::Gaussians => {
                egui::Grid::new("lab").num_columns(4).show(ui, |ui| {
                    let l = ui.label("Gaussians Q");
                    ui.add(egui::Slider::new(&mut lab.gaussians, 1..=MAX_GAUSSIANS))
                        .labelled_by(l.id);
                    let l = ui.label("per Gaussian");
                    ui.add(egui::DragValue::new(&mut lab.per_gaussian).range(1..=MAX_PER_GAUSSIAN))
                        .labelled_by(l.id);
                    ui.end_row();
                    let l = ui.label("spread σ");
                    ui.add(egui::Slider::new(&mut lab.spread, 0.0..=MAX_SPREAD))
                        .labelled_by(l.id)
                        .on_hover_text("each Gaussian's standard deviation is drawn from [σ/4, σ]");
                    let l = ui.label("alpha");
                    ui.add(egui::Slider::new(&mut lab.alpha, 0.01..=0.99).logarithmic(true))
                        .labelled_by(l.id);
                    ui.end_row();
                    row(ui, "seed", egui::DragValue::new(&mut lab.seed));
                });
                ui.weak("means uniform in [0.1, 0.9] (Mertens et al. 2004, Fig. 5: Q Gaussians against K clusters)");
            }
            LabSource::Typed => {
                let l = ui.label("fragments, one `depth,alpha` per line (as `hairlab curve --fragments`)");
                ui.add(
                    egui::TextEdit::multiline(&mut lab.text)
                        .desired_rows(5)
                        .code_editor()
                        .hint_text("0.25,0.3"),
                )
                .labelled_by(l.id);
            }
        }
        if let Some(e) = &self.inspector.lab_error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
    }

    fn pins_ui(&mut self, ui: &mut egui::Ui) {
        if self.inspector.pins.is_empty() {
            return;
        }
        ui.separator();
        let mut remove = None;
        ui.horizontal_wrapped(|ui| {
            ui.label("Pinned:");
            for (i, p) in self.inspector.pins.iter().enumerate() {
                let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
                ui.painter().rect_filled(rect, 2.0, p.color);
                ui.label(format!("{} {}", i + 1, p.label));
                if ui.small_button("remove").clicked() {
                    remove = Some(i);
                }
                ui.separator();
            }
        });
        if let Some(i) = remove {
            self.inspector.remove_pin(i);
        }
    }
}

/// The plot: reference, methods, stored structure, fragments, pins.
fn plot(ui: &mut egui::Ui, curves: &TexelCurves, height: f32) {
    let text = ui.visuals().text_color();
    Plot::new("texel_plot")
        .legend(
            Legend::default()
                .text_style(egui::TextStyle::Small)
                .position(egui_plot::Corner::RightTop),
        )
        .height(height)
        .x_axis_label("normalised light depth z")
        .y_axis_label("V(z)")
        .include_y(-0.12)
        .include_y(1.05)
        .label_formatter(|pos| {
            let (name, p) = match pos {
                egui_plot::HoverPosition::NearDataPoint {
                    plot_name, position, ..
                } => (*plot_name, position),
                egui_plot::HoverPosition::Elsewhere { position } => ("", position),
            };
            Some(format!("{name}\nz = {:.5}\nV = {:.5}", p.x, p.y))
        })
        .show(ui, |p| {
            if let Some(t) = &curves.current {
                if let Some(s) = &curves.stored {
                    stored_items(p, s, t);
                }
                p.line(
                    Line::new("reference", series(&t.depths, &t.reference))
                        .color(text)
                        .width(2.0),
                );
                for m in &t.methods {
                    let width = if m.selected { 2.0 } else { 1.5 };
                    p.line(
                        Line::new(m.label.clone(), series(&t.depths, &m.values))
                            .color(m.model.color)
                            .width(width),
                    );
                }
                let ticks: PlotPoints = t.fragments.iter().map(|f| [f64::from(f.depth), -0.02]).collect();
                p.points(
                    Points::new("fragments", ticks)
                        .shape(MarkerShape::Up)
                        .radius(3.0)
                        .color(text),
                );
            }
            for (i, t) in curves.pins.iter().enumerate() {
                let color = t.color.unwrap_or(text);
                let name = format!("pin {} {}", i + 1, t.label);
                p.line(Line::new(format!("{name} reference"), series(&t.depths, &t.reference)).color(color));
                for m in &t.methods {
                    p.line(
                        Line::new(format!("{name} {}", m.label), series(&t.depths, &m.values))
                            .color(color)
                            .style(LineStyle::dashed_dense()),
                    );
                }
            }
        });
}

/// What the selected method stores, over the plotted range of texel `t`.
fn stored_items(p: &mut egui_plot::PlotUi<'_>, s: &Stored, t: &TexelPlot) {
    let Some(model) = t.methods.iter().find(|m| m.selected) else {
        return;
    };
    let color = model.model.color;
    let (lo, hi) = plot_range(t.near, t.far);
    let inside = |z: f32| (lo..=hi).contains(&z);
    for &z in s.boundaries.iter().filter(|z| inside(**z)) {
        p.vline(
            VLine::new(format!("{} boundaries", s.label), z)
                .color(color.gamma_multiply(0.6))
                .style(LineStyle::dashed_loose()),
        );
    }
    let knots: PlotPoints = s
        .knots
        .iter()
        .filter(|k| inside(k[0]))
        .map(|&[z, v]| [f64::from(z), f64::from(v)])
        .collect();
    p.points(
        Points::new(format!("{} stored values", s.label), knots)
            .shape(MarkerShape::Diamond)
            .radius(4.0)
            .color(color),
    );
    for &b in &s.bins {
        p.polygon(band(&format!("{} bins", s.label), b, (-0.1, -0.06), color));
    }
    let means: PlotPoints = s.means.iter().map(|&m| [f64::from(m), -0.08]).collect();
    p.points(
        Points::new(format!("{} means", s.label), means)
            .shape(MarkerShape::Asterisk)
            .radius(5.0)
            .color(color),
    );
    for &o in &s.occupied {
        p.polygon(band(
            &format!("{} occupied slices", s.label),
            o,
            (-0.1, -0.06),
            color,
        ));
    }
    for z in [t.near, t.far] {
        p.vline(
            VLine::new("near / far", z)
                .color(Color32::GRAY)
                .style(LineStyle::dotted_dense()),
        );
    }
}

/// Beside the plot: the texel's figures, error table and stored values.
fn figures(ui: &mut egui::Ui, curves: &TexelCurves) {
    let Some(t) = &curves.current else {
        ui.label("no texel");
        return;
    };
    ui.strong(&t.label);
    if t.fragments.is_empty() {
        ui.label("this texel holds no fragment");
        return;
    }
    let total: f64 = t.fragments.iter().map(|f| f64::from(f.optical_depth())).sum();
    egui::Grid::new("texel_figures").num_columns(2).show(ui, |ui| {
        ui.label("depth complexity");
        ui.label(t.depth_complexity().to_string());
        ui.end_row();
        ui.label("near / far");
        ui.label(format!("{:.5} / {:.5}", t.near, t.far));
        ui.end_row();
        ui.label("V beyond far");
        ui.label(format!("{:.5}", (-total).exp()));
        ui.end_row();
    });
    ui.add_space(4.0);
    egui::Grid::new("texel_errors")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("|ΔV|");
            ui.strong("mean");
            ui.strong("max");
            ui.end_row();
            let (mean, max) = error_text(t.reference_error);
            ui.label("reference");
            ui.label(mean);
            ui.label(max);
            ui.end_row();
            for m in &t.methods {
                let (mean, max) = error_text(m.error);
                ui.colored_label(m.model.color, &m.label);
                ui.label(mean);
                ui.label(max);
                ui.end_row();
            }
        });
    if let Some(s) = &curves.stored {
        ui.add_space(4.0);
        ui.strong(format!("{} stores", s.label));
        for line in &s.summary {
            ui.label(egui::RichText::new(line).small());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::optical_depth;

    /// A camera looking down -z with an orthographic projection: world (x, y) in [-1, 1]² fills the image, depth
    /// runs from z = -0.5 (NDC 0) to z = -4.5 (NDC 1).
    fn eye() -> Mat4 {
        Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.5, 4.5)
    }

    fn strands(segments: &[[Vec3; 2]]) -> Strands {
        Strands {
            points: segments.iter().flatten().copied().collect(),
            counts: vec![2; segments.len()],
            ..Default::default()
        }
    }

    #[test]
    fn picks_the_front_segment_under_the_cursor_and_its_light_texel() {
        let size = Vec2::new(200.0, 100.0);
        // World (0.6, 0.6) is pixel ((0.6 * 0.5 + 0.5) * 200, (0.5 - 0.6 * 0.5) * 100) = (160, 20).
        let cursor = Vec2::new(160.0, 20.0);
        let s = strands(&[
            // Behind, crossing the cursor.
            [Vec3::new(-0.5, 0.6, -3.0), Vec3::new(0.9, 0.6, -3.0)],
            // In front, crossing the cursor: the one to pick (segment id = its first point, 2).
            [Vec3::new(0.6, -0.5, -1.0), Vec3::new(0.6, 0.9, -1.0)],
            // Nearer still, but 0.1 (10 pixels) to the left of the cursor.
            [Vec3::new(0.5, -0.5, -0.6), Vec3::new(0.5, 0.9, -0.6)],
        ]);
        let pick = pick_segment(&s, eye(), size, cursor, 4.0, 1.0).expect("a segment under the cursor");
        assert_eq!(pick.segment, 2);
        assert!(
            pick.world.distance(Vec3::new(0.6, 0.6, -1.0)) < 1e-5,
            "{}",
            pick.world
        );
        // An opaque surface in front of it (NDC depth 0.1) hides every strand.
        assert!(pick_segment(&s, eye(), size, cursor, 4.0, 0.1).is_none());
        // Nothing within 4 pixels of an empty corner.
        assert!(pick_segment(&s, eye(), size, Vec2::new(5.0, 95.0), 4.0, 1.0).is_none());

        // A light frame looking down -z from z = 0: uv = (x * 0.5 + 0.5, 0.5 - y * 0.5) = (0.8, 0.2), so on a
        // 4² map texel (3, 0); depth (1 - 0) / (2 - 0) = 0.5.
        let frame = LightFrame {
            world_to_view: Mat4::IDENTITY,
            view_to_clip: Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.0, 2.0),
            near: 0.0,
            far: 2.0,
            position: Vec3::ZERO,
            to_light: Vec3::Z,
        };
        let (texel, depth) = light_texel(&frame, 4, pick.world).unwrap();
        assert_eq!(texel, [3, 0]);
        assert!((depth - 0.5).abs() < 1e-6);
        assert_eq!(light_texel(&frame, 4, Vec3::new(1.5, 0.0, -1.0)), None);
    }

    #[test]
    fn perspective_pick_finds_the_point_under_the_cursor() {
        // A perspective camera: the picked world point projects back onto the cursor.
        let cam = Mat4::perspective_rh(0.8, 1.5, 0.1, 10.0)
            * Mat4::look_at_rh(Vec3::new(0.3, 0.2, 3.0), Vec3::ZERO, Vec3::Y);
        let size = Vec2::new(300.0, 200.0);
        let s = strands(&[[Vec3::new(-1.0, -0.4, 0.5), Vec3::new(1.0, 0.3, -1.5)]]);
        let target = Vec3::new(-1.0, -0.4, 0.5).lerp(Vec3::new(1.0, 0.3, -1.5), 0.3);
        let (cursor, _) = to_pixels(cam * target.extend(1.0), size);
        let pick = pick_segment(&s, cam, size, cursor, 1.0, 1.0).unwrap();
        assert!(pick.world.distance(target) < 1e-4, "{} vs {target}", pick.world);
    }

    #[test]
    fn mesh_in_front_blocks_picking() {
        let size = Vec2::new(100.0, 100.0);
        // A triangle at z = -1 covering the image centre.
        let mesh = Mesh {
            positions: vec![
                Vec3::new(-0.5, -0.5, -1.0),
                Vec3::new(0.5, -0.5, -1.0),
                Vec3::new(0.0, 0.5, -1.0),
            ],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        let d = mesh_depth(&[mesh], eye(), size, Vec2::new(50.0, 50.0));
        // z = -1 is 0.5 of the way into [0.5, 4.5]: NDC 0.125.
        assert!((d - 0.125).abs() < 1e-5, "{d}");
        assert_eq!(mesh_depth(&[], eye(), size, Vec2::new(50.0, 50.0)), 1.0);
    }

    #[test]
    fn curves_and_stored_structures() {
        let f: Vec<Fragment> = [(0.2, 0.5), (0.3, 0.5), (0.6, 0.25)]
            .iter()
            .map(|&p| p.into())
            .collect();
        let input = TexelInput {
            label: "t".into(),
            fragments: f.clone(),
            hair_alpha: 0.5,
            color: None,
        };
        let mut params = ParamValues::new();
        params.insert("slices".into(), 4.0);
        let (ms, sel) = models("osm", &params, false, 0.5);
        assert_eq!((ms.len(), sel), (1, Some(0)));
        let s = ms[0].model.stored(&f).unwrap();
        assert_eq!(s.boundaries, [0.0, 0.25, 0.5, 0.75, 1.0]);
        // Planes: 0.25 holds the first fragment (ln 2), 0.5 the second too, 0.75 all three.
        let b = [2f32.ln(), 2.0 * 2f32.ln(), 2.0 * 2f32.ln() + optical_depth(0.25)];
        assert!((s.knots[1][1] - (-b[0]).exp()).abs() < 1e-6);
        assert!((s.knots[3][1] - (-b[2]).exp()).abs() < 1e-6);
        let plot = texel_plot(&input, &ms, sel, Some(&s));
        assert_eq!(plot.reference[0], 1.0);
        assert!((plot.reference.last().unwrap() - (-b[2]).exp()).abs() < 1e-6);
        // The step at 0.3: V(0.3) still sees one fragment, V just after it two.
        let i = plot.depths.iter().position(|&z| z == 0.3).unwrap();
        assert!((plot.reference[i] - 0.5).abs() < 1e-6 && (plot.reference[i + 1] - 0.25).abs() < 1e-6);
        assert_eq!(plot.reference_error.unwrap().max, 0.0);
        assert!(plot.methods[0].error.unwrap().mean > 0.0);

        let all = models("dc", &ParamValues::new(), true, 0.5);
        let names: Vec<String> = all.0.iter().map(|m| m.model.label()).collect();
        assert_eq!(names, ["osm-16", "dom-3", "bom-4", "occupancy", "dc-4"]);
        assert_eq!(all.1, Some(4));
        let dc = all.0[4].model.stored(&f).unwrap();
        assert_eq!((dc.means.len(), dc.bins.len()), (4, 4));
        let occ = all.0[3].model.stored(&f).unwrap();
        // Relative depths 0, 0.25 and 1: slices 0, 32 and 127 (the last one, clamped); slabs 0, 1 and 3.
        assert_eq!(occ.occupied.len(), 3);
        assert!((occ.occupied[1][0] - 0.3).abs() < 1e-6);
        for (b, want) in occ.boundaries.iter().zip([0.2, 0.3, 0.4, 0.5, 0.6]) {
            assert!((b - want).abs() < 1e-6, "{:?}", occ.boundaries);
        }
        // Before slab 1 lies 1 fragment, before the end all 3.
        let w = optical_depth(0.5);
        assert!(
            (occ.knots[1][1] - (-w).exp()).abs() < 1e-6 && (occ.knots[4][1] - (-3.0 * w).exp()).abs() < 1e-6
        );
    }
}
