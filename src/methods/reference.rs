//! The exact reference: every light-space fragment of every texel (A-buffer, verified against depth peeling),
//! `V(z) = exp(-sum of b over fragments with depth < z)` (design.md; Sintorn & Assarsson 2009 Fig. 2 and 5 use
//! depth peeling as ground truth). As a shadow method, the eye passes walk the texel's list.

use super::{MethodContext, MethodGpu, ShadowMethod};
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::passes::abuffer::ABuffer;
use crate::visibility::MethodParams;

pub struct Reference;

impl ShadowMethod for Reference {
    fn name(&self) -> &'static str {
        "reference"
    }
    fn label(&self) -> &'static str {
        "Reference (exact)"
    }
    fn source(&self) -> &'static str {
        "exact visibility from every fragment (A-buffer = depth peeling)"
    }
    fn lookup_wgsl(&self) -> &'static str {
        "methods/reference.wgsl"
    }
    fn model(&self, _values: &super::ParamValues, _hair_alpha: f32) -> Option<MethodParams> {
        Some(MethodParams::Reference)
    }
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu> {
        let _ = gpu;
        Box::new(ReferenceGpu { abuffer: None })
    }
}

/// The reference's GPU state: the A-buffer, created on first use (it needs the frame layout).
pub struct ReferenceGpu {
    abuffer: Option<ABuffer>,
}

impl ReferenceGpu {
    fn abuffer(&self) -> &ABuffer {
        self.abuffer
            .as_ref()
            .expect("the reference A-buffer exists after its first record()")
    }
}

impl MethodGpu for ReferenceGpu {
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let abuffer = self
            .abuffer
            .get_or_insert_with(|| ABuffer::new(ctx.gpu, ctx.frame_layout));
        abuffer.record(
            ctx.gpu,
            ctx.frame_bind_group,
            ctx.geometry,
            ctx.map_resolution(),
            encoder,
            timer,
        )
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.abuffer().lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.abuffer().lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.abuffer.as_ref().map_or(0, |a| a.memory_bytes())
    }
    fn geometry_passes(&self) -> u32 {
        2
    }
    fn as_reference(&self) -> Option<&ABuffer> {
        self.abuffer.as_ref()
    }
}
