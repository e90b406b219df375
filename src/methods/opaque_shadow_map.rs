//! Opaque shadow map (Williams 1978) applied to hair: strands treated as opaque, so a point is shadowed (`V = 0`)
//! as soon as it lies behind the nearest hair fragment of its light texel. The classic failure that motivates
//! every semi-transparent method: hair goes black one strand deep.

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, NoMaps, ParamKind, ParamSpec, ParamValues, Role,
    ShadowMethod, value,
};
use crate::gpu::GpuError;
use crate::visibility::{Fragment, TexelModel};

pub struct OpaqueShadowMap;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    key: "bias",
    label: "depth bias",
    help: "offset in normalised light depth before a point counts as behind the nearest fragment",
    kind: ParamKind::Float {
        min: 0.0,
        max: 0.1,
        log: false,
    },
    default: 0.002,
}];

static INFO: MethodInfo = MethodInfo {
    name: "opaque-shadow-map",
    label: "Opaque shadow map",
    paper: "Williams 1978, hair as opaque occluders",
    role: Role::Baseline,
    lookup_wgsl: "methods/opaque_shadow_map.wgsl",
    light_wgsl: &[],
    params: PARAMS,
    color: [127, 127, 127],
    gpu_tolerance: 0.0,
    gpu_outliers: 0.0,
};

/// `V = 0` behind the nearest fragment plus the bias, 1 in front of it (and in an empty texel).
#[derive(Debug)]
struct NearestOccluder {
    bias: f32,
}

impl TexelModel for NearestOccluder {
    fn label(&self) -> String {
        INFO.name.to_string()
    }
    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        let near = fragments.iter().map(|f| f.depth).fold(f32::INFINITY, f32::min);
        zs.iter()
            .map(|&z| if z > near + self.bias { 0.0 } else { 1.0 })
            .collect()
    }
}

impl LightMethod for OpaqueShadowMap {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_params(&self, values: &ParamValues) -> [f32; 4] {
        [value(values, &PARAMS[0]), 0.0, 0.0, 0.0]
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        // Reads the shared nearest- and furthest-depth maps (two R32Float).
        NoMaps::create(ctx, 8)
    }
}

impl ShadowMethod for OpaqueShadowMap {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(NearestOccluder {
            bias: value(values, &PARAMS[0]),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadowed_only_behind_nearest_fragment_plus_bias() {
        let v = ParamValues::from([("bias".to_string(), 0.01)]);
        let m = OpaqueShadowMap.model(&v, 1.0);
        let frags = [(0.5, 0.2), (0.3, 0.1), (0.8, 0.9)].map(Fragment::from);
        assert_eq!(
            m.curve(&frags, &[0.1, 0.305, 0.32]),
            [1.0, 1.0, 0.0],
            "lit, inside the bias, behind"
        );
        assert_eq!(m.curve(&[], &[0.9]), [1.0], "an empty texel is lit");
    }
}
