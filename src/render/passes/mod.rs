//! One file per pass: each holds its pipeline(s) and records itself into an encoder.

pub mod abuffer;
pub mod composite;
pub mod depth_peel;
pub mod evaluate;
pub mod hair;
pub mod light_depth;
pub mod list_pages;
pub mod list_sort;
pub mod mesh;
pub mod shadow_map;

/// Creates a shader module from a composed WGSL pass (panics only on a shader that fails naga validation, which
/// the `shaders_validate` test rules out for every embedded shader).
pub fn shader_module(
    device: &wgpu::Device,
    label: &str,
    path: &str,
    method: Option<&str>,
) -> wgpu::ShaderModule {
    let src = crate::shaders::compose(path, method).unwrap_or_else(|e| panic!("{e}"));
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    })
}

/// Format of [`NullTarget`].
pub const NULL_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// The colour target of light passes that write only storage buffers: it sets the render area (a pass needs an
/// attachment) and is never written (write mask empty). One byte per texel.
pub struct NullTarget {
    view: wgpu::TextureView,
    resolution: u32,
}

impl NullTarget {
    pub fn new(device: &wgpu::Device, resolution: u32) -> NullTarget {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("hairlab.light.null_target"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: NULL_TARGET_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        NullTarget {
            view: texture.create_view(&Default::default()),
            resolution,
        }
    }

    /// Re-creates the target when the map resolution changed.
    pub fn ensure(&mut self, device: &wgpu::Device, resolution: u32) {
        if self.resolution != resolution {
            *self = NullTarget::new(device, resolution);
        }
    }

    /// The pipeline target state matching [`NullTarget::attachment`].
    pub fn target_state() -> Option<wgpu::ColorTargetState> {
        Some(wgpu::ColorTargetState {
            format: NULL_TARGET_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::empty(),
        })
    }

    pub fn attachment(&self) -> Option<wgpu::RenderPassColorAttachment<'_>> {
        Some(wgpu::RenderPassColorAttachment {
            view: &self.view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Discard,
            },
        })
    }

    pub fn bytes(&self) -> u64 {
        self.resolution as u64 * self.resolution as u64
    }
}
