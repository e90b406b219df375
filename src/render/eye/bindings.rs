//! One binding vocabulary for the eye passes' bind groups: a pass declares its group as a list — e.g.
//! `&[StorageRw, StorageRw, StorageRw, MeshDepth]` — whose position is the binding number, and the layout and the
//! groups over it are derived from the list (vello's `add_shader!` style), instead of written-out entries.

/// What one binding of an eye pass's group holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binding {
    /// `var<uniform>`.
    Uniform,
    /// `var<storage, read_write>`.
    StorageRw,
    /// `var<storage, read>`.
    StorageRo,
    /// The meshes' depth, `texture_depth_2d` (tested by hand, `common/mesh_depth.wgsl`).
    MeshDepth,
    /// A float `texture_2d<f32>` read with `textureLoad` (not filtered).
    Texture,
}

impl Binding {
    pub const fn ty(self) -> wgpu::BindingType {
        match self {
            Binding::Uniform => wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            Binding::StorageRw | Binding::StorageRo => wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage {
                    read_only: matches!(self, Binding::StorageRo),
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            Binding::MeshDepth => wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            Binding::Texture => wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
        }
    }
}

/// The layout entries of `bindings` at bindings 0.., each visible to `visibility`.
pub fn entries(visibility: wgpu::ShaderStages, bindings: &[Binding]) -> Vec<wgpu::BindGroupLayoutEntry> {
    bindings
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupLayoutEntry {
            binding: i as u32,
            visibility,
            ty: b.ty(),
            count: None,
        })
        .collect()
}

/// The layout of a group declared as `bindings`, visible to the fragment stage (every eye pass's storage and
/// textures are the fragment shader's).
pub fn layout(device: &wgpu::Device, label: &str, bindings: &[Binding]) -> wgpu::BindGroupLayout {
    layout_for(device, label, wgpu::ShaderStages::FRAGMENT, bindings)
}

/// [`layout`] visible to `visibility`.
pub fn layout_for(
    device: &wgpu::Device,
    label: &str,
    visibility: wgpu::ShaderStages,
    bindings: &[Binding],
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries(visibility, bindings),
    })
}

/// A group over `resources` at bindings 0.., in the order the layout declared them.
pub fn group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<_> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A storage buffer of `bytes` (at least 4) that can be cleared and read back.
pub fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A uniform buffer of `bytes` written with `queue.write_buffer`.
pub fn uniform(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_declared_list_numbers_its_bindings_in_order() {
        let e = entries(
            wgpu::ShaderStages::FRAGMENT,
            &[Binding::StorageRw, Binding::StorageRo, Binding::MeshDepth],
        );
        assert_eq!(e.iter().map(|e| e.binding).collect::<Vec<_>>(), [0, 1, 2]);
        assert_eq!(
            e[1].ty,
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            }
        );
        assert!(matches!(
            e[2].ty,
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                ..
            }
        ));
    }
}
