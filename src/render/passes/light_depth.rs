//! Light-depth pass: nearest and furthest strand depth per light texel (R32Float, Min and Max blending), in the
//! frame fitted to the strand bounds. Every shadow method starts from these maps.

use crate::render::caster::{LightCaster, LightStage, draw_casters};

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

pub struct LightDepthPass {
    pipeline: wgpu::RenderPipeline,
}

/// The two maps, `resolution`² each.
pub struct LightDepthMaps {
    pub near: wgpu::Texture,
    pub far: wgpu::Texture,
    pub near_view: wgpu::TextureView,
    pub far_view: wgpu::TextureView,
}

impl LightDepthMaps {
    pub fn new(device: &wgpu::Device, resolution: u32) -> LightDepthMaps {
        let make = |label| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: resolution,
                    height: resolution,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let near = make("hairlab.light_depth.near");
        let far = make("hairlab.light_depth.far");
        LightDepthMaps {
            near_view: near.create_view(&Default::default()),
            far_view: far.create_view(&Default::default()),
            near,
            far,
        }
    }

    pub fn bytes(&self) -> u64 {
        2 * self.near.width() as u64 * self.near.height() as u64 * 4
    }
}

impl LightDepthPass {
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        light: &LightStage,
    ) -> LightDepthPass {
        let module = light.module(device, "hairlab.light_depth.shader", "light_depth.wgsl");
        let blend = |op| wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: op,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: op,
            },
        };
        let target = |op| {
            Some(wgpu::ColorTargetState {
                format: FORMAT,
                blend: Some(blend(op)),
                write_mask: wgpu::ColorWrites::RED,
            })
        };
        let targets = [
            target(wgpu::BlendOperation::Min),
            target(wgpu::BlendOperation::Max),
        ];
        let pipeline = light.pipeline(
            device,
            "hairlab.light_depth.pipeline",
            &[frame_layout],
            &module,
            "fs_main",
            &targets,
        );
        LightDepthPass { pipeline }
    }

    /// Clears near to 1 and far to 0, then draws every strand segment.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        maps: &LightDepthMaps,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let attach = |view, clear| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: clear,
                        g: 0.0,
                        b: 0.0,
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.light_depth.pass"),
            color_attachments: &[attach(&maps.near_view, 1.0), attach(&maps.far_view, 0.0)],
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw_casters(&mut pass, &self.pipeline, frame, None, casters, 0..1);
    }
}
