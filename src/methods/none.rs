//! No hair self-shadowing: every strand is fully lit (`V = 1`). The baseline that shows what shadows add.

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, NoMaps, ParamValues, Role, ShadowMethod, SweepPoint,
};
use crate::gpu::GpuError;
use crate::visibility::{Fragment, TexelModel};

pub struct NoShadow;

static INFO: MethodInfo = MethodInfo {
    name: "none",
    label: "None",
    paper: "baseline: hair casts no shadow",
    role: Role::Baseline,
    lookup_wgsl: "methods/none.wgsl",
    light_wgsl: &[],
    params: &[],
    color: [23, 190, 207],
    gpu_tolerance: 0.0,
    gpu_outliers: 0.0,
};

/// `V = 1` everywhere.
#[derive(Debug)]
struct Lit;

impl TexelModel for Lit {
    fn label(&self) -> String {
        INFO.name.to_string()
    }
    fn curve(&self, _fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        vec![1.0; zs.len()]
    }
}

impl LightMethod for NoShadow {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        NoMaps::create(ctx, 0)
    }
}

impl ShadowMethod for NoShadow {
    fn model(&self, _values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(Lit)
    }
    /// Nothing to bench: no light pass, no error bound beyond "no shadow".
    fn sweep(&self) -> Vec<SweepPoint> {
        Vec::new()
    }
}
