//! Opaque shadow map (Williams 1978) applied to hair: strands treated as opaque, so a point is shadowed (`V = 0`)
//! as soon as it lies behind the nearest hair fragment of its light texel. The classic failure that motivates
//! every semi-transparent method: hair goes black one strand deep.

use super::{MethodGpu, NoMaps, ParamKind, ParamSpec, ParamValues, ShadowMethod, value};
use crate::gpu::Gpu;
use crate::visibility::Fragment;

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

impl ShadowMethod for OpaqueShadowMap {
    fn name(&self) -> &'static str {
        "opaque-shadow-map"
    }
    fn label(&self) -> &'static str {
        "Opaque shadow map"
    }
    fn source(&self) -> &'static str {
        "Williams 1978, hair as opaque occluders"
    }
    fn lookup_wgsl(&self) -> &'static str {
        "methods/opaque_shadow_map.wgsl"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn uniform_params(&self, values: &ParamValues) -> [f32; 4] {
        [value(values, &PARAMS[0]), 0.0, 0.0, 0.0]
    }
    fn visibility(&self, values: &ParamValues, _alpha: f32, fragments: &[Fragment], z: f32) -> f32 {
        let near = fragments.iter().map(|f| f.depth).fold(f32::INFINITY, f32::min);
        if z > near + value(values, &PARAMS[0]) {
            0.0
        } else {
            1.0
        }
    }
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu> {
        // Reads the shared nearest- and furthest-depth maps (two R32Float).
        Box::new(NoMaps::new(gpu, 8))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadowed_only_behind_nearest_fragment_plus_bias() {
        let m = OpaqueShadowMap;
        let v = ParamValues::from([("bias".to_string(), 0.01)]);
        let frags = [(0.5, 0.2), (0.3, 0.1), (0.8, 0.9)].map(Fragment::from);
        assert_eq!(m.visibility(&v, 1.0, &frags, 0.1), 1.0);
        assert_eq!(m.visibility(&v, 1.0, &frags, 0.305), 1.0, "inside the bias");
        assert_eq!(m.visibility(&v, 1.0, &frags, 0.32), 0.0);
        assert_eq!(m.visibility(&v, 1.0, &[], 0.9), 1.0, "an empty texel is lit");
    }
}
