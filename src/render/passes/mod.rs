//! One file per pass: each holds its pipeline(s) and records itself into an encoder.

pub mod composite;
pub mod hair;
pub mod light_depth;
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
