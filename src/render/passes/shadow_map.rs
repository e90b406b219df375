//! Opaque shadow-map pass: meshes depth-only from the light, in the frame fitted to the whole scene. Gives the
//! shadows meshes cast on hair and on each other.

use crate::render::geometry::MeshVertex;
use crate::render::scene_gpu::SceneGpu;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub struct ShadowMapPass {
    pipeline: wgpu::RenderPipeline,
}

pub struct ShadowMap {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

impl ShadowMap {
    pub fn new(device: &wgpu::Device, resolution: u32) -> ShadowMap {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("hairlab.shadow_map.depth"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        ShadowMap {
            view: texture.create_view(&Default::default()),
            texture,
        }
    }

    pub fn bytes(&self) -> u64 {
        self.texture.width() as u64 * self.texture.height() as u64 * 4
    }
}

impl ShadowMapPass {
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> ShadowMapPass {
        let module = super::shader_module(device, "hairlab.shadow_map.shader", "shadow_map.wgsl", None);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.shadow_map.layout"),
            bind_group_layouts: &[Some(frame_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("hairlab.shadow_map.pipeline"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(MeshVertex::layout())],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState {
                    constant: 2,
                    slope_scale: 2.0,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        ShadowMapPass { pipeline }
    }

    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        map: &ShadowMap,
        frame: &wgpu::BindGroup,
        geometry: &SceneGpu,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.shadow_map.pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &map.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if geometry.mesh_index_count == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_vertex_buffer(0, geometry.mesh_vertices.slice(..));
        pass.set_index_buffer(geometry.mesh_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..geometry.mesh_index_count, 0, 0..1);
    }
}
