//! The curves the inspector plots: the reference visibility `V(z)` of a texel's exact fragments and each
//! method's reconstruction of it from its CPU model (`ShadowMethod::model`), with the texel's error figures and
//! what the selected method stores. The GPU lookups equal these models (tested in `tests/gpu_*.rs`), so the
//! curves show what the GPU computes.

use super::traced::TracedRays;
use crate::methods::{ParamValues, Role, ShadowMethod, registry};
use crate::visibility::{self, Fragment, Stored, TexelError, TexelModel, depth_range, metrics};
use egui::Color32;
use std::sync::Arc;

/// Uniform samples of each curve across the plotted range (the events of [`plot_depths`] come on top).
const CURVE_SAMPLES: usize = 400;

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
    /// The method's hair count at [`TexelPlot::depths`] ([`TexelModel::count_curve`]).
    pub counts: Vec<f32>,
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
    /// The exact hair count at [`TexelPlot::depths`]: fragments in front.
    pub reference_count: Vec<f32>,
    /// The reference's own texel error (0 by definition: a check of the metric).
    pub reference_error: Option<TexelError>,
    /// The uniform hair alpha the methods' counts are read at ([`visibility::count_from_visibility`]).
    pub hair_alpha: f32,
    pub methods: Vec<MethodCurve>,
    /// The ray-traced `V` of the texel's fibres, once traced (scene texels under a directional light).
    pub traced: Option<TracedCurve>,
    /// A pin's colour.
    pub color: Option<Color32>,
}

/// The ray-traced `V(z)` of a texel ([`super::traced`]).
#[derive(Clone, Debug)]
pub struct TracedCurve {
    /// `V` at [`TexelPlot::depths`].
    pub values: Vec<f32>,
    /// The rays it counts (their footprint, seed and first crossings).
    pub rays: Arc<TracedRays>,
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

/// One texel to plot.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TexelInput {
    pub label: String,
    pub fragments: Vec<Fragment>,
    /// The uniform alpha the occupancy model assumes.
    pub hair_alpha: f32,
    pub color: Option<Color32>,
    /// The texel's ray-traced rays, when traced.
    pub traced: Option<Arc<TracedRays>>,
}

/// Everything the curves depend on (they are recomputed when it changes).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct CurvesInput {
    pub current: Option<TexelInput>,
    pub pins: Vec<TexelInput>,
    pub method: String,
    pub params: ParamValues,
    pub show_all: bool,
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
        reference_count: visibility::Reference.count_curve(f, &depths, input.hair_alpha),
        reference_error: metrics::texel_error(&visibility::Reference, f, grid),
        hair_alpha: input.hair_alpha,
        methods: models
            .iter()
            .enumerate()
            .map(|(i, m)| MethodCurve {
                label: m.model.label(),
                model: m.clone(),
                values: m.model.curve(f, &depths),
                counts: m.model.count_curve(f, &depths, input.hair_alpha),
                error: metrics::texel_error(m.model.as_ref(), f, grid),
                selected: selected == Some(i),
            })
            .collect(),
        traced: input.traced.as_ref().map(|r| TracedCurve {
            values: r.curve(&depths),
            rays: r.clone(),
        }),
        depths,
        color: input.color,
    }
}

/// Every curve of `input`: the inspected texel's (and what the selected method stores for it), each pin's.
pub(super) fn compute_curves(input: &CurvesInput) -> TexelCurves {
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

/// Colour of a method's curves: the method's own ([`crate::methods::MethodInfo::color`]).
pub fn method_color(m: &dyn ShadowMethod) -> Color32 {
    let [r, g, b] = m.info().color;
    Color32::from_rgb(r, g, b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::optical_depth;

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
            traced: None,
        };
        let mut params = ParamValues::new();
        params.insert("slices".into(), 4.0);
        use crate::methods::{LightMethod, bom::Bom, dc::Dc, dom::Dom, occupancy::Occupancy, osm::Osm};
        let (ms, sel) = models(Osm.name(), &params, false, 0.5);
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
        // The counts beside: 1 strand in front at 0.3 (the fragment at 0.2), 2 just after; OSM's count is
        // -ln V / ln 2 of its own curve.
        assert_eq!((plot.reference_count[i], plot.reference_count[i + 1]), (1.0, 2.0));
        let m = &plot.methods[0];
        for (c, v) in m.counts.iter().zip(&m.values) {
            assert!((c - visibility::count_from_visibility(*v, 0.5)).abs() < 1e-6);
        }
        assert!(plot.methods[0].error.unwrap().mean > 0.0);

        let empty = ParamValues::new();
        let all = models(Dc.name(), &empty, true, 0.5);
        let names: Vec<String> = all.0.iter().map(|m| m.model.label()).collect();
        let count = registry::all().iter().filter(|m| inspected(**m)).count();
        assert_eq!(names.len(), count, "every inspected method once: {names:?}");
        let at = |label: &str| {
            names
                .iter()
                .position(|n| n == label)
                .unwrap_or_else(|| panic!("{label}"))
        };
        let label = |m: &dyn ShadowMethod| m.model(&empty, 0.5).label();
        for m in [&Osm as &dyn ShadowMethod, &Dom, &Bom, &Occupancy] {
            at(&label(m));
        }
        assert_eq!(all.1, Some(at(&label(&Dc))), "the selected method");
        let dc = all.0[at(&label(&Dc))].model.stored(&f).unwrap();
        assert_eq!((dc.means.len(), dc.bins.len()), (4, 4));
        let occ = all.0[at(&label(&Occupancy))].model.stored(&f).unwrap();
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
