//! No hair self-shadowing: every strand is fully lit (`V = 1`). The baseline that shows what shadows add.

use super::{ParamValues, ShadowMethod};

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
    fn memory_bytes(&self, _map_resolution: u32) -> u64 {
        0
    }
    fn visibility(&self, _values: &ParamValues, _fragments: &[(f32, f32)], _z: f32) -> f32 {
        1.0
    }
}
