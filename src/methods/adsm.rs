//! Approximated deep shadow maps (Lacroix, GDC 2013; AMD TressFX `ComputeShadow`; vkhr, EGSR 2019): visibility
//! from the nearest strand depth alone and a constant fibre spacing, `V = (1 - alpha_s)^min(n_max, (z - z0)/s)`.
//! The baseline most shipped hair uses. The CPU model is `visibility::adsm`.
//!
//! GPU: no light pass and no map of its own — the lookup reads the shared near/far light-depth maps (8 bytes per
//! texel, reported as shared memory) and its three parameters from `FrameUniforms::method_params`
//! (x spacing, y shadow alpha, z max fibres).

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, NoMaps, ParamKind, ParamSpec, ParamValues, Role,
    ShadowMethod, SweepPoint, value,
};
use crate::gpu::GpuError;
use crate::visibility::TexelModel;
use crate::visibility::adsm::AdsmParams;

const SPACING: ParamSpec = ParamSpec {
    key: "fiber_spacing",
    label: "fibre spacing",
    help: "depth between fibres s, in normalised light depth (TressFX's fiber spacing × fiber radius over the \
           strands' light range; default 1/64 of the range)",
    kind: ParamKind::Float {
        min: 1e-4,
        max: 1.0,
        log: true,
    },
    default: 1.0 / 64.0,
};
const SHADOW_ALPHA: ParamSpec = ParamSpec {
    key: "shadow_alpha",
    label: "shadow alpha",
    help: "opacity of one fibre in front (TressFX's hair shadow alpha, 0.35)",
    kind: ParamKind::Float {
        min: 0.0,
        max: 0.99,
        log: false,
    },
    default: 0.35,
};
const MAX_FIBRES: ParamSpec = ParamSpec {
    key: "max_fibers",
    label: "max fibres",
    help: "most fibres counted in front of a point, the shadow's floor (TressFX's max shadow fibers, 50)",
    kind: ParamKind::Float {
        min: 1.0,
        max: 1024.0,
        log: true,
    },
    default: 50.0,
};
const PARAMS: &[ParamSpec] = &[SPACING, SHADOW_ALPHA, MAX_FIBRES];

pub struct Adsm;

static INFO: MethodInfo = MethodInfo {
    name: "adsm",
    label: "Approximated deep shadow maps",
    paper: "Lacroix 2013 (Tomb Raider), AMD TressFX ComputeShadow, vkhr (EGSR 2019)",
    role: Role::Approximation,
    lookup_wgsl: "methods/adsm.wgsl",
    light_wgsl: &[],
    params: PARAMS,
    color: [188, 189, 34],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

fn adsm_params(values: &ParamValues) -> AdsmParams {
    AdsmParams {
        spacing: value(values, &SPACING),
        shadow_alpha: value(values, &SHADOW_ALPHA),
        max_fibres: value(values, &MAX_FIBRES),
    }
}

impl LightMethod for Adsm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_params(&self, values: &ParamValues) -> [f32; 4] {
        let p = adsm_params(values);
        [p.spacing, p.shadow_alpha, p.max_fibres, 0.0]
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        // Reads the shared nearest- and furthest-depth maps (two R32Float).
        NoMaps::create(ctx, 8)
    }
}

impl ShadowMethod for Adsm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(adsm_params(values))
    }
    /// The defaults and half and twice the fibre spacing.
    fn sweep(&self) -> Vec<SweepPoint> {
        [0.5, 1.0, 2.0]
            .map(|f| SweepPoint::fixed(&[(SPACING.key, SPACING.default * f)]))
            .to_vec()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
}
