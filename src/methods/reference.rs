//! The exact reference: every light-space fragment of every texel (A-buffer, verified against depth peeling),
//! `V(z) = exp(-sum of b over fragments with depth < z)` (design.md; Sintorn & Assarsson 2009 Fig. 2 and 5 use
//! depth peeling as ground truth). As a shadow method, the eye passes walk the texel's list.

use super::{LightMethod, MethodContext, MethodGpu, MethodInfo, ParamValues, Role, ShadowMethod};
use crate::gpu::GpuError;
use crate::gpu::timing::GpuTimer;
use crate::render::passes::abuffer::ABuffer;
use crate::visibility::{self, TexelModel};

pub struct Reference;

static INFO: MethodInfo = MethodInfo {
    name: "reference",
    label: "Reference (exact)",
    paper: "exact visibility from every fragment (A-buffer = depth peeling)",
    role: Role::Reference,
    lookup_wgsl: "methods/reference.wgsl",
    light_wgsl: &["abuffer.wgsl"],
    params: &[],
    color: [140, 86, 75],
    gpu_tolerance: 1e-5,
    gpu_outliers: 0.0,
};

impl LightMethod for Reference {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        Ok(Box::new(ReferenceGpu {
            abuffer: ABuffer::new(ctx.gpu, ctx.frame_layout, ctx.light),
        }))
    }
}

impl ShadowMethod for Reference {
    fn model(&self, _values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(visibility::Reference)
    }
}

/// The reference's GPU state: the A-buffer.
pub struct ReferenceGpu {
    abuffer: ABuffer,
}

impl MethodGpu for ReferenceGpu {
    fn prepare(&mut self, ctx: &MethodContext, timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        self.abuffer.prepare(
            ctx.gpu,
            ctx.frame_bind_group,
            ctx.casters,
            ctx.map_resolution(),
            timer,
        )
    }
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        self.abuffer
            .record(ctx.frame_bind_group, ctx.casters, encoder, timer);
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.abuffer.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.abuffer.lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.abuffer.memory_bytes()
    }
    fn geometry_passes(&self) -> u32 {
        2
    }
}
