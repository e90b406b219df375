//! Composite pass: the shape of every eye transparency technique's resolve. A full-screen triangle
//! (`common/fullscreen.wgsl`) runs the technique's resolve shader, which reads the technique's targets through
//! group 0 and blends its result onto the opaque colour image.

use crate::render::eye::pipelines;
use crate::render::targets::{CAPTURE_FORMAT, EyeTargets};

pub struct CompositePass {
    /// One pipeline per output format: the colour image, and the float capture target of the GPU = CPU tests
    /// ([`crate::render::targets::CAPTURE_FORMAT`]).
    pipelines: [(wgpu::TextureFormat, wgpu::RenderPipeline); 2],
}

impl CompositePass {
    /// A resolve running the WGSL pass `resolve_wgsl` (entry points `vs_main`, `fs_main`) over `layout` (group 0),
    /// blended onto the colour image with `blend`, colour channels only.
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        resolve_wgsl: &str,
        layout: &wgpu::BindGroupLayout,
        blend: wgpu::BlendState,
    ) -> CompositePass {
        let module = super::shader_module(device, &format!("{label}.shader"), resolve_wgsl, None);
        let pipeline = |format| {
            pipelines::fullscreen(
                device,
                &format!("{label}.pipeline"),
                &module,
                &[layout],
                &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(blend),
                    // The colour image keeps its alpha; the capture records coverage 1 - T in it.
                    write_mask: if format == CAPTURE_FORMAT {
                        wgpu::ColorWrites::ALL
                    } else {
                        wgpu::ColorWrites::COLOR
                    },
                })],
            )
        };
        CompositePass {
            pipelines: [EyeTargets::COLOR, CAPTURE_FORMAT].map(|f| (f, pipeline(f))),
        }
    }

    /// Draws the resolve onto `color` of `format` (loaded, not cleared) with `bind_group` as group 0.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (color, format): (&wgpu::TextureView, wgpu::TextureFormat),
        bind_group: &wgpu::BindGroup,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let pipeline = self.pipelines.iter().find(|(f, _)| *f == format);
        pipelines::record_fullscreen(
            encoder,
            "hairlab.composite.pass",
            color,
            timestamps,
            None,
            &pipeline.unwrap_or(&self.pipelines[0]).1,
            &[bind_group],
        );
    }
}
