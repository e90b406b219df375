//! No hair self-shadowing: every strand is fully lit (`V = 1`). The baseline that shows what shadows add.

use super::{MethodGpu, NoMaps, ParamValues, ShadowMethod};
use crate::gpu::Gpu;
use crate::visibility::Fragment;

pub struct NoShadow;

impl ShadowMethod for NoShadow {
    fn name(&self) -> &'static str {
        "none"
    }
    fn label(&self) -> &'static str {
        "None"
    }
    fn source(&self) -> &'static str {
        "baseline: hair casts no shadow"
    }
    fn lookup_wgsl(&self) -> &'static str {
        "methods/none.wgsl"
    }
    fn visibility(&self, _values: &ParamValues, _alpha: f32, _fragments: &[Fragment], _z: f32) -> f32 {
        1.0
    }
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu> {
        Box::new(NoMaps::new(gpu, 0))
    }
}
