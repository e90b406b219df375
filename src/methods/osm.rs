//! Opacity Shadow Maps (Kim & Neumann 2001, as described by Yuksel & Keyser 2008 §2 and Voicu's thesis §3):
//! `N` uniform slices (1..=256) across the strands' whole fitted light range; each stored value is the optical
//! depth accumulated up to a slice's far plane, and `V(z)` interpolates linearly between planes. The CPU model
//! is `visibility::osm`.
//!
//! GPU (`methods::opacity_layers` with this method's shader and uniforms): the slices live in an array texture
//! (4 slices per layer). `build = auto` (the default) takes the colour targets up to 32 slices with f32
//! storage and the atomic build otherwise (measured, `docs/design.md`). `build = atomic`: one geometry pass
//! adds each fragment's fixed-point optical depth to its (texel, slice) counter with storage atomics, and a
//! compute resolve over the occupied texels sums the counters into the map, so OSM-256 costs the light-depth
//! pass plus one geometry pass (at 512² on lavapipe too: its 256 MiB of counters span two of the four storage
//! bindings the pass may take); `storage` = f32, f16 or u8 takes 4,
//! 2 or 1 bytes per slice and texel (OSM-256 at 512²: 256, 128 or 64 MiB). `build = targets`: additive
//! blending into RGBA32F colour targets, 8 targets × 4 channels = 32 slices per geometry pass, so OSM-256
//! takes 8 geometry passes. Quantisation and storage are part of the CPU model (`visibility::opacity_layers`).

use super::opacity_layers::{self, BUILD, LayerMethod, LayerSetup, LayersGpu, STORAGE};
use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::GpuError;
use crate::visibility::opacity_layers::Layered;
use crate::visibility::osm::MAX_SLICES;
use crate::visibility::{OsmParams, TexelModel};
use bytemuck::{Pod, Zeroable};

/// Slices one geometry pass fills (8 RGBA32F targets).
pub const SLICES_PER_PASS: u32 = 32;

const SLICES: ParamSpec = ParamSpec {
    key: "slices",
    label: "slices",
    help: "uniform slices across the strands' light-depth range (1..=256)",
    kind: ParamKind::Int { min: 1, max: 256 },
    default: 16.0,
};
const PARAMS: &[ParamSpec] = &[SLICES, BUILD, STORAGE];

pub struct Osm;

fn slices(values: &ParamValues) -> u32 {
    value(values, &SLICES) as u32
}

static INFO: MethodInfo = MethodInfo {
    name: "osm",
    label: "Opacity shadow maps",
    paper: "Kim & Neumann 2001 (as in Yuksel & Keyser 2008 §2)",
    role: Role::Approximation,
    lookup_wgsl: "methods/osm.wgsl",
    light_wgsl: &["osm.wgsl"],
    params: PARAMS,
    color: [31, 119, 180],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

/// The bench's slice counts.
const SWEEP_SLICES: &[u32] = &[4, 8, 16, 32, 64, 128, 256];

impl LightMethod for Osm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "OsmUniforms",
            OsmUniforms {
                slices,
                unit,
                pad0,
                pad1
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        let method = LayerMethod {
            name: INFO.name,
            unit: "slices",
            shader: "osm.wgsl",
            setup: osm_setup,
        };
        Ok(Box::new(LayersGpu::create(ctx, method)?))
    }
}

impl ShadowMethod for Osm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(Layered {
            params: OsmParams {
                slices: slices(values),
            },
            build: opacity_layers::build(values, slices(values).clamp(1, MAX_SLICES)),
        })
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        SWEEP_SLICES
            .iter()
            .map(|&n| SweepPoint::fixed(&[("slices", n as f32)]))
            .collect()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        [16, 64]
            .map(|n| ParamValues::from([("slices".to_string(), n as f32)]))
            .to_vec()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        [16, 64, 256]
            .map(|n| ParamValues::from([("slices".to_string(), n as f32)]))
            .to_vec()
    }
}

/// Mirrors `OsmUniforms` in `shaders/common/osm_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct OsmUniforms {
    pub slices: u32,
    /// What the lookup multiplies a stored value by ([`opacity_layers::unit`]).
    pub unit: f32,
    pub pad0: u32,
    pub pad1: u32,
}

/// The slice count and uniforms for `values` (the map holds `ceil(N / 4)` RGBA layers).
fn osm_setup(values: &ParamValues) -> LayerSetup<OsmUniforms> {
    let n = slices(values).clamp(1, MAX_SLICES);
    let build = opacity_layers::build(values, n);
    LayerSetup {
        values: n,
        depth_maps: 0,
        build,
        uniforms: OsmUniforms {
            slices: n,
            unit: opacity_layers::unit(build),
            ..Zeroable::zeroed()
        },
    }
}
