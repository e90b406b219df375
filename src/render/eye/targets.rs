//! A technique's viewport-sized targets: [`Textures`], named render targets re-created when the viewport changes
//! (a depth format becomes the technique's own depth image, the others are read by later passes), and
//! [`storage`], a per-pixel storage buffer refused beyond the device's storage binding size ([`check_storage`]).

use crate::gpu::{Gpu, GpuError};
use crate::render::targets::eye_texture;

/// Viewport-sized render targets `hairlab.<technique>.<name>`, in declared order.
pub struct Textures {
    technique: &'static str,
    declared: Vec<(&'static str, wgpu::TextureFormat)>,
    views: Vec<wgpu::TextureView>,
    size: (u32, u32),
}

impl Textures {
    /// The targets `declared` (name, format) of `technique` at `size`.
    pub fn new(
        device: &wgpu::Device,
        technique: &'static str,
        declared: &[(&'static str, wgpu::TextureFormat)],
        size: (u32, u32),
    ) -> Textures {
        let views = declared
            .iter()
            .map(|&(name, format)| {
                // A depth image is only ever attached; every other target is read by a later pass.
                let usage = if format.is_depth_stencil_format() {
                    wgpu::TextureUsages::empty()
                } else {
                    wgpu::TextureUsages::TEXTURE_BINDING
                };
                eye_texture(
                    device,
                    &format!("hairlab.{technique}.{name}"),
                    size,
                    format,
                    usage,
                    &[],
                )
                .create_view(&Default::default())
            })
            .collect();
        Textures {
            technique,
            declared: declared.to_vec(),
            views,
            size,
        }
    }

    /// Re-creates the targets for `size` (nothing when it is unchanged).
    pub fn resize(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        if self.size != size {
            *self = Textures::new(device, self.technique, &self.declared, size);
        }
    }

    /// Re-creates the targets with target `index` of `format` (nothing when it has it).
    pub fn set_format(&mut self, device: &wgpu::Device, index: usize, format: wgpu::TextureFormat) {
        if self.declared[index].1 != format {
            self.declared[index].1 = format;
            *self = Textures::new(device, self.technique, &self.declared, self.size);
        }
    }

    /// The view of target `index`.
    pub fn view(&self, index: usize) -> &wgpu::TextureView {
        &self.views[index]
    }

    pub fn format(&self, index: usize) -> wgpu::TextureFormat {
        self.declared[index].1
    }

    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Colour attachments of the first `clears.len()` targets, each cleared to its value.
    pub fn cleared(&self, clears: &[[f64; 4]]) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
        self.views
            .iter()
            .zip(clears)
            .map(|(view, &clear)| crate::render::transparency::cleared(view, clear))
            .collect()
    }

    /// Bytes held: every target's texel size over the viewport.
    pub fn bytes(&self) -> u64 {
        let texel: u64 = self
            .declared
            .iter()
            .filter_map(|(_, f)| f.block_copy_size(None))
            .map(u64::from)
            .sum();
        self.size.0 as u64 * self.size.1 as u64 * texel
    }
}

/// Whether a buffer of `bytes` bound whole as storage fits the device: [`GpuError::TooLarge`] naming `what`
/// when it exceeds the storage binding or buffer size.
pub fn check_storage(gpu: &Gpu, what: &str, bytes: u64) -> Result<(), GpuError> {
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    if bytes > limit {
        return Err(GpuError::TooLarge {
            what: what.to_string(),
            bytes,
            limit,
        });
    }
    Ok(())
}

/// A storage buffer `hairlab.<technique>.<name>` of `bytes` bound whole, after [`check_storage`].
pub fn storage(
    gpu: &Gpu,
    technique: &str,
    name: &str,
    what: &str,
    bytes: u64,
) -> Result<wgpu::Buffer, GpuError> {
    check_storage(gpu, what, bytes)?;
    Ok(super::bindings::storage(
        &gpu.device,
        &format!("hairlab.{technique}.{name}"),
        bytes,
    ))
}
