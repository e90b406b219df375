//! Deep Opacity Maps (Yuksel & Keyser 2008, §3; layer sizes §5): `K` layers (1..=16) follow each texel's
//! nearest strand depth `z0`, layer `k` spanning `z0 + d_(k-1)` to `z0 + d_k`; each stored value is the optical
//! depth accumulated up to a layer's far end, and `V(z)` interpolates linearly between the layer boundaries.
//! The CPU model is `visibility::dom`.
//!
//! GPU: `z0` is the shared near map of the light-depth pass (the paper's first pass), read by texel, not stored
//! again (the paper keeps it in the first channel of its single RGBA target); the far map is read only by the
//! stretch option. The layers live in an array texture of `ceil(K / 4)` layers (4 opacity layers per texel
//! each), all written in ONE geometry pass (the paper's second pass): with `build = targets` (what the default `auto` takes with f32 storage) by
//! `ceil(K / 4)` RGBA32F colour targets with additive blending, a fragment adding its optical depth to its
//! layer and every later one; with `build = atomic` by fixed-point storage atomics per (texel, layer) and a
//! full-screen resolve into the `storage` format (f32, f16 or u8: 16, 8 or 4 bytes per texel per 4 layers;
//! `visibility::opacity_layers`). The ends `d_k` are a uniform filled from `visibility::dom::layer_ends`.
//! Memory (f32): 16 bytes per texel per 4 layers, plus the near map it reads (4 bytes) and, for the stretch,
//! the far map (4 bytes): DOM-3 takes 5 MiB at 512². The GPU side is `methods::opacity_layers` with this
//! method's shader and uniforms.

use super::opacity_layers::{self, BUILD, LayerMethod, LayerSetup, LayersGpu, STORAGE, VALUES_PER_LAYER};
use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, choice, value,
};
use crate::gpu::GpuError;
use crate::visibility::dom::{MAX_LAYERS, layer_ends};
use crate::visibility::opacity_layers::Layered;
use crate::visibility::{BeyondLastLayer, DomParams, LayerSpacing, TexelModel};
use bytemuck::{Pod, Zeroable};

const LAYERS: ParamSpec = ParamSpec {
    key: "layers",
    label: "layers",
    help: "opacity layers K behind each texel's nearest strand (1..=16; the paper uses 3)",
    kind: ParamKind::Int { min: 1, max: 16 },
    default: 3.0,
};
const DEPTH_SPAN: ParamSpec = ParamSpec {
    key: "depth_span",
    label: "depth span",
    help: "total depth d_K of the K layers, in normalised light depth (fraction of the strands' light range)",
    kind: ParamKind::Float {
        min: 1e-4,
        max: 1.0,
        log: true,
    },
    default: 0.25,
};
const SPACING: ParamSpec = ParamSpec {
    key: "spacing",
    label: "spacing",
    help: "layer sizes: linear = linearly increasing (size of layer k proportional to k, the paper's), \
           uniform = all the same, unreal = Unreal Engine's 4 groom deep shadow layers (ends at 2%, 10%, 40% and \
           100% of the depth span; K = 4)",
    kind: ParamKind::Choice {
        options: &["linear", "uniform", "unreal"],
    },
    default: 0.0,
};
const BEYOND: ParamSpec = ParamSpec {
    key: "beyond",
    label: "beyond last layer",
    help: "fragments beyond the last layer: ignore them, add them to the last layer (the paper's choice), or \
           stretch each texel's layers to reach its furthest strand",
    kind: ParamKind::Choice {
        options: &["ignore", "add-to-last", "stretch"],
    },
    default: 1.0,
};
const PARAMS: &[ParamSpec] = &[LAYERS, DEPTH_SPAN, SPACING, BEYOND, BUILD, STORAGE];

pub struct Dom;

fn dom_params(values: &ParamValues) -> DomParams {
    DomParams {
        layers: value(values, &LAYERS) as u32,
        depth_span: value(values, &DEPTH_SPAN),
        spacing: match choice(values, &SPACING) {
            "uniform" => LayerSpacing::Uniform,
            "unreal" => LayerSpacing::Unreal,
            _ => LayerSpacing::LinearlyIncreasing,
        },
        beyond: match choice(values, &BEYOND) {
            "ignore" => BeyondLastLayer::Ignore,
            "stretch" => BeyondLastLayer::Stretch,
            _ => BeyondLastLayer::AddToLast,
        },
    }
}

/// The layer count, the depth maps read and the uniforms for `values`.
fn dom_setup(values: &ParamValues) -> LayerSetup<DomUniforms> {
    let p = dom_params(values);
    let mut ends = [[0.0; 4]; (MAX_LAYERS / VALUES_PER_LAYER) as usize];
    for (i, e) in layer_ends(&p).into_iter().enumerate() {
        ends[i / 4][i % 4] = e;
    }
    let beyond = match p.beyond {
        BeyondLastLayer::Ignore => 0,
        BeyondLastLayer::AddToLast => 1,
        BeyondLastLayer::Stretch => 2,
    };
    let layers = p.layer_count() as u32;
    let build = opacity_layers::build(values, layers);
    LayerSetup {
        values: layers,
        build,
        // z0, and the far depth for the stretch.
        depth_maps: if p.beyond == BeyondLastLayer::Stretch {
            2
        } else {
            1
        },
        uniforms: DomUniforms {
            ends,
            layers,
            beyond,
            unit: opacity_layers::unit(build),
            ..Zeroable::zeroed()
        },
    }
}

static INFO: MethodInfo = MethodInfo {
    name: "dom",
    label: "Deep opacity maps",
    paper: "Yuksel & Keyser 2008",
    role: Role::Approximation,
    lookup_wgsl: "methods/dom.wgsl",
    light_wgsl: &["dom.wgsl"],
    params: PARAMS,
    color: [255, 127, 14],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

/// The bench's layer counts; each is swept with the linear and uniform spacings.
const SWEEP_LAYERS: &[u32] = &[1, 2, 3, 4, 5, 7, 10, 15];

/// Unreal Engine's groom deep shadow as a DOM configuration (`visibility::dom`, [`LayerSpacing::Unreal`]): its
/// four layers at 0.01, 0.05, 0.2 and 0.5 of the light range, fragments beyond ignored.
pub fn unreal_config() -> ParamValues {
    [
        (LAYERS.key, 4.0),
        (DEPTH_SPAN.key, 0.5),
        (SPACING.key, 2.0),
        (BEYOND.key, 0.0),
    ]
    .map(|(k, v)| (k.to_string(), v))
    .into()
}

impl LightMethod for Dom {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "DomUniforms",
            DomUniforms {
                ends,
                layers,
                beyond,
                unit,
                pad0
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        let method = LayerMethod {
            name: INFO.name,
            unit: "layers",
            shader: "dom.wgsl",
            setup: dom_setup,
        };
        Ok(Box::new(LayersGpu::create(ctx, method)?))
    }
}

impl ShadowMethod for Dom {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        let params = dom_params(values);
        Box::new(Layered {
            params,
            build: opacity_layers::build(values, params.layer_count() as u32),
        })
    }
    /// Each of [`SWEEP_LAYERS`] with the linear and the uniform spacing, then Unreal's configuration.
    fn sweep(&self) -> Vec<SweepPoint> {
        let mut points: Vec<SweepPoint> = SWEEP_LAYERS
            .iter()
            .flat_map(|&k| {
                (0..2).map(move |s| SweepPoint::fixed(&[("layers", k as f32), ("spacing", s as f32)]))
            })
            .collect();
        points.push(SweepPoint {
            values: unreal_config(),
            analysed: false,
        });
        points
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::from([("layers".to_string(), 3.0)])]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        let mut configs: Vec<ParamValues> = [3, 7]
            .map(|k| ParamValues::from([("layers".to_string(), k as f32)]))
            .to_vec();
        configs.push(unreal_config());
        configs
    }
}

/// Mirrors `DomUniforms` in `shaders/common/dom_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct DomUniforms {
    /// `d_1..d_K` (layer `k` at `ends[k / 4][k % 4]`, 0-based), the rest 0.
    pub ends: [[f32; 4]; 4],
    pub layers: u32,
    /// 0 ignore, 1 add to the last layer, 2 stretch (the `beyond` parameter).
    pub beyond: u32,
    /// What the lookup multiplies a stored value by ([`opacity_layers::unit`]).
    pub unit: f32,
    pub pad0: u32,
}
