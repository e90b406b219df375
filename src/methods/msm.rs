//! Moment shadow maps for translucent occluders (Peters & Klein, I3D 2015, Hamburger 4MSM; Münstermann,
//! Krumpen, Klein & Peters, I3D 2018, MBOIT; Peters et al., JCGT 2017): per texel the zeroth moment `b_0 = Σ b`
//! and 4 or 6 power moments of the absorbance over `x = 2z - 1`, reconstructed by the moment bound. The CPU
//! model is `visibility::msm`.
//!
//! Parameters: `moments` (4 or 6), `bias` (the moment bias β; MBOIT's single-precision value 5e-7 for 4
//! moments is the default, its 5e-6 for 6 moments is what the sweep and the usual configurations pair with 6),
//! `overestimation` (MBOIT's 0.25).
//!
//! GPU: `methods::opacity_layers` with this method's shader: one RGBA32F array map of 2 layers (5 or 7 floats:
//! layer 0 `b_0..b_3`, layer 1 `b_4..b_6`), 32 bytes per texel for either moment count, filled by one additive
//! geometry pass with 2 targets. f32 storage, so no quantisation transform.

use super::opacity_layers::{LayerBuild, LayerMethod, LayerSetup, LayersGpu};
use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::GpuError;
use crate::visibility::TexelModel;
use crate::visibility::msm::{DEFAULT_BIAS_4, DEFAULT_BIAS_6, DEFAULT_OVERESTIMATION, MsmParams};
use bytemuck::{Pod, Zeroable};

const MOMENTS: ParamSpec = ParamSpec {
    key: "moments",
    label: "moments",
    help: "power moments stored beyond b0 (4: Hamburger 4MSM / MBOIT-4, 6: MBOIT-6)",
    kind: ParamKind::Choice { options: &["4", "6"] },
    default: 0.0,
};
const BIAS: ParamSpec = ParamSpec {
    key: "bias",
    label: "moment bias",
    help: "moment bias β toward MBOIT's bias vector (MBOIT's f32 values: 5e-7 for 4 moments, the default; \
           5e-6 for 6)",
    kind: ParamKind::Float {
        min: 1e-9,
        max: 0.1,
        log: true,
    },
    default: DEFAULT_BIAS_4,
};
const OVERESTIMATION: ParamSpec = ParamSpec {
    key: "overestimation",
    label: "overestimation",
    help: "weight of the support point at the queried depth: 0 the lower bound, 1 the upper (MBOIT: 0.25)",
    kind: ParamKind::Float {
        min: 0.0,
        max: 1.0,
        log: false,
    },
    default: DEFAULT_OVERESTIMATION,
};
const PARAMS: &[ParamSpec] = &[MOMENTS, BIAS, OVERESTIMATION];

pub struct Msm;

static INFO: MethodInfo = MethodInfo {
    name: "msm",
    label: "Moment shadow maps",
    paper: "Peters & Klein 2015 (Hamburger 4MSM); Münstermann et al. 2018 (MBOIT); Peters et al. 2017 (JCGT)",
    role: Role::Approximation,
    lookup_wgsl: "methods/msm.wgsl",
    light_wgsl: &["msm.wgsl"],
    params: PARAMS,
    color: [227, 119, 194],
    gpu_tolerance: 1e-3,
    // The moment problem is ill-conditioned at MBOIT's f32 biases (texels of one or two fragments, queried at
    // a fragment's depth): the GPU's sums in another order and its own rounding move V by more than rounding.
    // Measured on the 300-strand test scene at 64²: 268 of 25,810 samples (1.04 %, max |ΔV| 1.1e-2) beyond
    // 1e-3 at the defaults, 102 (0.40 %, max 9.2e-3) at 6 moments and β 5e-6; `tests/it/gpu_msm.rs` shows
    // every sample beyond the tolerance ill-conditioned (the CPU model itself moves that much under a few ULPs).
    gpu_outliers: 0.015,
};

fn msm_params(values: &ParamValues) -> MsmParams {
    MsmParams {
        moments: if value(values, &MOMENTS) >= 1.0 { 6 } else { 4 },
        bias: value(values, &BIAS),
        overestimation: value(values, &OVERESTIMATION),
    }
}

/// `moments=6` at MBOIT's 6-moment bias.
fn six_moments() -> ParamValues {
    ParamValues::from([
        (MOMENTS.key.to_string(), 1.0),
        (BIAS.key.to_string(), DEFAULT_BIAS_6),
    ])
}

impl LightMethod for Msm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "MsmUniforms",
            MsmUniforms {
                moments,
                bias,
                overestimation,
                pad0
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        let method = LayerMethod {
            name: INFO.name,
            unit: "moments",
            shader: "msm.wgsl",
            setup: msm_setup,
        };
        Ok(Box::new(LayersGpu::create(ctx, method)?))
    }
}

impl ShadowMethod for Msm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(msm_params(values))
    }
    /// 4 and 6 moments at MBOIT's biases.
    fn sweep(&self) -> Vec<SweepPoint> {
        vec![
            SweepPoint::fixed(&[]),
            SweepPoint {
                values: six_moments(),
                analysed: false,
            },
        ]
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new(), six_moments()]
    }
}

/// Mirrors `MsmUniforms` in `shaders/common/msm_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct MsmUniforms {
    pub moments: u32,
    pub bias: f32,
    pub overestimation: f32,
    pub pad0: u32,
}

/// Values per texel: `b_0` and the moments (5 or 7, two RGBA layers either way).
fn msm_setup(values: &ParamValues) -> LayerSetup<MsmUniforms> {
    let p = msm_params(values);
    LayerSetup {
        values: 1 + p.moment_count() as u32,
        depth_maps: 0,
        build: LayerBuild::Targets,
        uniforms: MsmUniforms {
            moments: p.moment_count() as u32,
            bias: p.bias,
            overestimation: p.overestimation,
            ..Zeroable::zeroed()
        },
    }
}
