//! The two groups the renderer owns and every pass binds: group 0, the frame uniforms ([`FrameUniforms`], one
//! buffer written once per frame), and the eye passes' scene group (the uniforms again, the hair light-depth maps,
//! the meshes' shadow map and its comparison sampler, the Chiang shading's table), re-bound when the light maps
//! are re-sized.

use super::passes::light_depth::LightDepthMaps;
use super::passes::shadow_map::ShadowMap;
use super::uniforms::FrameUniforms;

pub struct FrameBindings {
    /// The frame uniforms.
    pub buffer: wgpu::Buffer,
    /// Group 0 of every pass: the frame uniforms alone.
    pub frame_layout: wgpu::BindGroupLayout,
    pub frame_group: wgpu::BindGroup,
    /// The eye passes' scene group (and the evaluation pass's).
    pub scene_layout: wgpu::BindGroupLayout,
    pub scene_group: wgpu::BindGroup,
    shadow_sampler: wgpu::Sampler,
    /// `shading::chiang::table`, read by `shaders/common/chiang.wgsl`.
    chiang_table: wgpu::TextureView,
}

impl FrameBindings {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        maps: &LightDepthMaps,
        shadow: &ShadowMap,
    ) -> FrameBindings {
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.frame.uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform_entry = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniforms>() as u64),
            },
            count: None,
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.frame.bind_group_layout"),
            entries: &[uniform_entry],
        });
        let float_tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.scene.bind_group_layout"),
            entries: &[
                uniform_entry,
                float_tex(1),
                float_tex(2),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D3,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let chiang_table = chiang_table(device, queue);
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("hairlab.shadow_map.sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let frame_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.frame.bind_group"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buffer.as_entire_binding(),
            }],
        });
        let scene_group = scene_group(
            device,
            &scene_layout,
            &frame_buffer,
            maps,
            shadow,
            &shadow_sampler,
            &chiang_table,
        );
        FrameBindings {
            buffer: frame_buffer,
            frame_layout,
            frame_group: frame_bind_group,
            scene_layout,
            scene_group,
            shadow_sampler,
            chiang_table,
        }
    }

    /// Binds the scene group to new light maps (after a resolution change).
    pub fn rebind_scene(&mut self, device: &wgpu::Device, maps: &LightDepthMaps, shadow: &ShadowMap) {
        self.scene_group = scene_group(
            device,
            &self.scene_layout,
            &self.buffer,
            maps,
            shadow,
            &self.shadow_sampler,
            &self.chiang_table,
        );
    }
}

fn scene_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    frame: &wgpu::Buffer,
    maps: &LightDepthMaps,
    shadow: &ShadowMap,
    sampler: &wgpu::Sampler,
    chiang_table: &wgpu::TextureView,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hairlab.scene.bind_group"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&maps.near_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&maps.far_view),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&shadow.view),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(chiang_table),
            },
        ],
    })
}

/// `shading::chiang::table` as the 3D texture `shaders/common/chiang.wgsl` reads (`chiang::PHI_NODES` ×
/// `COS_NODES` × `LAYERS`, one float a texel).
pub fn chiang_table(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    use crate::shading::chiang::{COS_NODES, LAYERS, PHI_NODES, table};
    let texture = wgpu::util::DeviceExt::create_texture_with_data(
        device,
        queue,
        &wgpu::TextureDescriptor {
            label: Some("hairlab.chiang.table"),
            size: wgpu::Extent3d {
                width: PHI_NODES as u32,
                height: COS_NODES as u32,
                depth_or_array_layers: LAYERS as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(table()),
    );
    texture.create_view(&Default::default())
}
