//! Bounding Opacity Maps (Voicu, "Real-time volumetric shadows for dynamic rendering", MSc thesis, §5 and
//! §5.2): each texel has a start AND an end depth, and `K` layers (1..=32) split that range by the hybrid
//! linear/logarithmic split with ratio `r` (§5.2.3: 0 linear, 1 logarithmic); each stored value is the optical
//! depth accumulated up to a layer's far end, and `V(z)` interpolates linearly between the layer boundaries in
//! the split coordinate. The CPU model is `visibility::bom`.
//!
//! GPU: the start and end depths are the shared near and far maps of the light-depth pass (the thesis's two
//! depth maps), read by texel, not stored again. The layers live in an array texture of `ceil(K / 4)` layers,
//! all written in ONE geometry pass: with `build = targets` (what the default `auto` takes with f32 storage) by `ceil(K / 4)` RGBA32F colour
//! targets (8 at most, thesis §3.4) with additive blending, a fragment adding its optical depth to its layer
//! and every later one; with `build = atomic` by fixed-point storage atomics per (texel, layer) and a
//! full-screen resolve into the `storage` format (f32, f16 or u8; `visibility::opacity_layers`). The split
//! function is evaluated in the shaders (the thesis's lookup texture of §5.2.2 is not needed). The GPU side is
//! `methods::opacity_layers` with this method's shader and uniforms. Memory (f32): 16 bytes per texel per 4
//! layers plus the near and far maps it reads (8 bytes): BOM-4 takes 6 MiB at 512², BOM-32 34 MiB; f16 and u8
//! halve and quarter the layers' part.
//!
//! The automatic split ratio (§5.2.3-5.2.4) is [`automatic_split_ratio`]: an on-demand computation over the
//! reference's fragment lists, off the per-frame path (the thesis reads the layers back for it, and does not
//! run it every frame either).

use super::opacity_layers::{self, BUILD, LayerMethod, LayerSetup, LayersGpu, STORAGE};
use super::{
    Analysis, AnalysisResult, LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec,
    ParamValues, Role, ShadowMethod, SweepPoint, UniformMirror, value,
};
use crate::gpu::GpuError;
use crate::render::passes::abuffer::RefFragment;
use crate::visibility::bom::search_split_ratio;
use crate::visibility::opacity_layers::Layered;
use crate::visibility::{BomParams, Fragment, SplitCriterion, SplitSearch, TexelModel};
use bytemuck::{Pod, Zeroable};

const LAYERS: ParamSpec = ParamSpec {
    key: "layers",
    label: "layers",
    help: "opacity layers K between each texel's start and end depth (1..=32)",
    kind: ParamKind::Int { min: 1, max: 32 },
    default: 4.0,
};
const SPLIT_RATIO: ParamSpec = ParamSpec {
    key: "split_ratio",
    label: "split ratio",
    help: "hybrid split of the layers: 0 = linear, 1 = logarithmic (more layers near the start), between = mix",
    kind: ParamKind::Float {
        min: 0.0,
        max: 1.0,
        log: false,
    },
    default: 0.0,
};
const PARAMS: &[ParamSpec] = &[LAYERS, SPLIT_RATIO, BUILD, STORAGE];

pub struct Bom;

fn bom_params(values: &ParamValues) -> BomParams {
    BomParams {
        layers: value(values, &LAYERS) as u32,
        split_ratio: value(values, &SPLIT_RATIO),
    }
}

/// The layer count, the depth maps read and the uniforms for `values`.
fn bom_setup(values: &ParamValues) -> LayerSetup<BomUniforms> {
    let p = bom_params(values);
    let layers = p.layer_count() as u32;
    let build = opacity_layers::build(values, layers);
    LayerSetup {
        values: layers,
        build,
        // The start and end depths.
        depth_maps: 2,
        uniforms: BomUniforms {
            layers,
            split_ratio: p.ratio(),
            unit: opacity_layers::unit(build),
            ..Zeroable::zeroed()
        },
    }
}

static INFO: MethodInfo = MethodInfo {
    name: "bom",
    label: "Bounding opacity maps",
    paper: "Voicu, MSc thesis §5",
    role: Role::Approximation,
    lookup_wgsl: "methods/bom.wgsl",
    light_wgsl: &["bom.wgsl"],
    params: PARAMS,
    color: [44, 160, 44],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

/// The bench's layer counts; each is swept at the fixed split ratios and at the automatic one.
const SWEEP_LAYERS: &[u32] = &[1, 2, 3, 4, 6, 8, 12, 15];
/// The bench's fixed split ratios.
const SWEEP_RATIOS: &[f32] = &[0.0, 0.5, 1.0];

impl LightMethod for Bom {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "BomUniforms",
            BomUniforms {
                layers,
                split_ratio,
                unit,
                pad0
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        let method = LayerMethod {
            name: INFO.name,
            unit: "layers",
            shader: "bom.wgsl",
            setup: bom_setup,
        };
        Ok(Box::new(LayersGpu::create(ctx, method)?))
    }
}

impl ShadowMethod for Bom {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        let params = bom_params(values);
        Box::new(Layered {
            params,
            build: opacity_layers::build(values, params.layer_count() as u32),
        })
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        let mut out = Vec::new();
        for &k in SWEEP_LAYERS {
            let layers = ("layers", k as f32);
            out.extend(
                SWEEP_RATIOS
                    .iter()
                    .map(|&r| SweepPoint::fixed(&[layers, ("split_ratio", r)])),
            );
            out.push(SweepPoint {
                analysed: true,
                ..SweepPoint::fixed(&[layers])
            });
        }
        out
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::from([("layers".to_string(), 4.0)])]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        [4, 8]
            .map(|k| ParamValues::from([("layers".to_string(), k as f32)]))
            .to_vec()
    }
    fn analysis(&self) -> Option<Analysis> {
        Some(Analysis {
            label: "Find split ratio",
            note: "automatic split ratio",
            tunes: "split_ratio",
            help: "scores split ratios 0.0..1.0 by the correlation of successive layer images (Voicu 5.2.3) on \
                   the exact fragment lists and applies the least correlated",
            run: split_ratio_analysis,
        })
    }
}

/// Mirrors `BomUniforms` in `shaders/common/bom_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct BomUniforms {
    pub layers: u32,
    /// `BomParams::ratio()`: in `[0, 1]`.
    pub split_ratio: f32,
    /// What the lookup multiplies a stored value by ([`opacity_layers::unit`]).
    pub unit: f32,
    pub pad0: u32,
}

/// Automatic split ratio (thesis §5.2.3-5.2.4, Algorithm 5.2.3.1) for `layers` layers over a whole rendered
/// map: `lists` holds every texel's fragments, as `Renderer::reference_lists` returns them (empty texels
/// included: they are pixels of the layer images, as in the thesis's read-back). Scores the split ratios
/// 0.0, 0.1, ..., 1.0 by the correlation and the sum of absolute differences of successive layer images
/// (`visibility::bom::search_split_ratio`); `SplitSearch::best` picks one. Costs one CPU build of the whole map
/// per ratio: call it on demand, not every frame.
pub fn automatic_split_ratio(lists: &[Vec<RefFragment>], layers: u32) -> SplitSearch {
    let map: Vec<Vec<Fragment>> = lists
        .iter()
        .map(|list| list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect())
        .collect();
    search_split_ratio(layers, &map)
}

/// The automatic split ratio as a method-panel analysis: scores every ratio, applies the least correlated.
fn split_ratio_analysis(lists: &[Vec<RefFragment>], values: &ParamValues) -> AnalysisResult {
    let layers = value(values, &LAYERS) as u32;
    let search = automatic_split_ratio(lists, layers);
    // The search steps by 0.1: keep the ratio on that grid so that it prints and compares exactly.
    let best = (search.best(SplitCriterion::CrossCorrelation) * 10.0).round() / 10.0;
    let mut table = vec![vec![
        "ratio".to_string(),
        "correlation".to_string(),
        "SAD".to_string(),
    ]];
    table.extend(search.scores.iter().map(|s| {
        vec![
            format!("{:.1}", s.ratio),
            format!("{:.4}", s.correlation),
            format!("{:.1}", s.sad),
        ]
    }));
    AnalysisResult {
        apply: ParamValues::from([("split_ratio".to_string(), best)]),
        table,
        summary: format!(
            "least correlated: split ratio {best:.1} (by SAD: {:.1})",
            search.best(SplitCriterion::SumOfAbsoluteDifferences)
        ),
    }
}
