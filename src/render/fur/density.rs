//! The volume pass of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering:
//! combining volumetric fur with explicit hair strands", The Visual Computer, Table 1 step 2; spec B.1 step 2,
//! B.3 #11–13): `shaders/fur/density.wgsl` evaluates [`Volume::sample`] for every sub-element on the GPU, one
//! invocation each, into the stored volume the shell pass reads (`(τ.xyz, ρ)`, 16 B, global-index order).
//! [`Volume::store`] is its specification; `tests/it/fur_density.rs` compares the two.
//!
//! The shader finds each sub-element's face by a binary search over the faces' offsets. Besides the uploaded
//! prisms it reads each face's corner normals and a per-layer table of `w` and `w^γ` computed here with the
//! CPU's expressions (`f32::powf` has no bit-equal WGSL counterpart, and the shell point's bits key the hashes).
//!
//! [`Volume::sample`]: crate::fur::volume::Volume::sample
//! [`Volume::store`]: crate::fur::volume::Volume::store

use bytemuck::{Pod, Zeroable};

use crate::fur::shell::Shell;
use crate::fur::volume::VolumeParams;
use crate::gpu::{Gpu, GpuError};
use crate::render::pipelines::{self, ComputePass};

/// Bytes of one stored sub-element, `(τ.xyz, ρ)`.
pub const SUB_ELEMENT_BYTES: u64 = 16;
/// The volume pass's WGSL.
pub const DENSITY_WGSL: &str = "fur/density.wgsl";
/// Invocations per workgroup (`@workgroup_size` in the shader).
const WORKGROUP: u32 = 256;

/// The volume parameters, mirrored field for field by `FurDensityUniforms` in `shaders/fur/density.wgsl` (a
/// test compares the layouts).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FurDensityUniforms {
    pub frequency: f32,
    pub threshold: f32,
    pub softness: f32,
    pub jitter: f32,
    pub density_variation: f32,
    pub density_frequency: f32,
    pub length_variation: f32,
    pub length_frequency: f32,
    pub tangent_jitter: f32,
    /// 1 with the clump field, 0 without.
    pub clumps: u32,
    pub faces: u32,
    pub sub_elements: u32,
    /// Invocations per dispatch row.
    pub row: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// Field names and byte offsets of [`FurDensityUniforms`], in declaration order, for the layout test.
pub const FUR_DENSITY_UNIFORMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("frequency", offset_of!(FurDensityUniforms, frequency)),
        ("threshold", offset_of!(FurDensityUniforms, threshold)),
        ("softness", offset_of!(FurDensityUniforms, softness)),
        ("jitter", offset_of!(FurDensityUniforms, jitter)),
        (
            "density_variation",
            offset_of!(FurDensityUniforms, density_variation),
        ),
        (
            "density_frequency",
            offset_of!(FurDensityUniforms, density_frequency),
        ),
        (
            "length_variation",
            offset_of!(FurDensityUniforms, length_variation),
        ),
        (
            "length_frequency",
            offset_of!(FurDensityUniforms, length_frequency),
        ),
        ("tangent_jitter", offset_of!(FurDensityUniforms, tangent_jitter)),
        ("clumps", offset_of!(FurDensityUniforms, clumps)),
        ("faces", offset_of!(FurDensityUniforms, faces)),
        ("sub_elements", offset_of!(FurDensityUniforms, sub_elements)),
        ("row", offset_of!(FurDensityUniforms, row)),
        ("pad0", offset_of!(FurDensityUniforms, pad0)),
        ("pad1", offset_of!(FurDensityUniforms, pad1)),
        ("pad2", offset_of!(FurDensityUniforms, pad2)),
    ]
};

/// The workgroups of a dispatch of `n` invocations: `(x, y)` with `x` within the device's per-dimension limit
/// `max` and `x · y · 256 ≥ n`.
pub fn dispatch_size(n: u64, max: u32) -> (u32, u32) {
    let groups = n.div_ceil(u64::from(WORKGROUP)).max(1);
    let x = groups.min(u64::from(max.max(1)));
    (x as u32, groups.div_ceil(x) as u32)
}

/// The per-layer table `(w, w^γ)` the shader reads: `w = (i_l + ½)/n_l` and `w^γ` as [`f32::powf`] gives it
/// (0 without clumps), the expressions of [`crate::fur::volume::Volume::sample`].
pub fn layer_heights(layers: u32, params: &VolumeParams) -> Vec<[f32; 2]> {
    (0..layers)
        .map(|layer| {
            let w = (layer as f32 + 0.5) / layers as f32;
            [w, params.clumps.map_or(0.0, |c| w.powf(c.jitter_power))]
        })
        .collect()
}

/// Refuses a stored volume over the device's storage binding limit, naming the mesh, the sub-element count
/// and the limit.
pub fn check_volume_fits(gpu: &Gpu, shell: &Shell) -> Result<(), GpuError> {
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    let bytes = shell.sub_elements * SUB_ELEMENT_BYTES;
    if bytes > limit {
        return Err(GpuError::TooLarge {
            what: format!(
                "the stored fur volume of mesh '{}' ({} sub-elements of {SUB_ELEMENT_BYTES} B; the storage \
                 binding limit holds {})",
                shell.mesh.name,
                shell.sub_elements,
                limit / SUB_ELEMENT_BYTES
            ),
            bytes,
            limit,
        });
    }
    Ok(())
}

/// The stored volume of `shell` under `params`, computed on the GPU: a new buffer (`STORAGE | COPY_SRC`) of
/// 16 B per sub-element, `faces` the shell's uploaded [`super::shell_gpu::faces`]. The pass is submitted to
/// the queue (later submissions see its result); a volume over the binding limit is refused first
/// ([`check_volume_fits`]).
pub fn compute_volume(
    gpu: &Gpu,
    shell: &Shell,
    faces: &wgpu::Buffer,
    params: &VolumeParams,
) -> Result<wgpu::Buffer, GpuError> {
    use wgpu::util::DeviceExt;
    check_volume_fits(gpu, shell)?;
    let device = &gpu.device;
    let (x, y) = dispatch_size(
        shell.sub_elements,
        device.limits().max_compute_workgroups_per_dimension,
    );
    let c = params.clumps;
    let uniforms = FurDensityUniforms {
        frequency: c.map_or(0.0, |c| c.frequency),
        threshold: c.map_or(0.0, |c| c.threshold),
        softness: c.map_or(0.0, |c| c.softness),
        jitter: c.map_or(0.0, |c| c.jitter),
        density_variation: params.density_variation,
        density_frequency: params.density_frequency,
        length_variation: params.length_variation,
        length_frequency: params.length_frequency,
        tangent_jitter: params.tangent_jitter,
        clumps: u32::from(c.is_some()),
        faces: shell.mesh.faces.len() as u32,
        sub_elements: shell.sub_elements as u32,
        row: x * WORKGROUP,
        pad0: 0,
        pad1: 0,
        pad2: 0,
    };
    let normals: Vec<[[f32; 4]; 3]> = shell
        .mesh
        .faces
        .iter()
        .map(|face| face.map(|v| shell.mesh.normals[v as usize].extend(0.0).to_array()))
        .collect();
    let init = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let storage = wgpu::BufferUsages::STORAGE;
    let uniforms = init(
        "hairlab.fur.density.uniforms",
        bytemuck::bytes_of(&uniforms),
        wgpu::BufferUsages::UNIFORM,
    );
    let normals = init(
        "hairlab.fur.density.normals",
        bytemuck::cast_slice(&normals),
        storage,
    );
    let heights = init(
        "hairlab.fur.density.heights",
        bytemuck::cast_slice(&layer_heights(shell.layers, params)),
        storage,
    );
    let volume = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hairlab.fur.shell.volume"),
        size: shell.sub_elements * SUB_ELEMENT_BYTES,
        usage: storage | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    use crate::render::eye::bindings::{self, Binding::*};
    let layout = bindings::layout_for(
        device,
        "hairlab.fur.density.layout",
        wgpu::ShaderStages::COMPUTE,
        &[Uniform, StorageRo, StorageRo, StorageRo, StorageRw],
    );
    let group = pipelines::buffer_group(
        device,
        "hairlab.fur.density.group",
        &layout,
        &[&uniforms, faces, &normals, &heights, &volume],
    );
    let module =
        crate::render::passes::shader_module(device, "hairlab.fur.density.shader", DENSITY_WGSL, None);
    let pipeline = pipelines::compute(
        device,
        &ComputePass {
            label: "hairlab.fur.density.pipeline",
            module: &module,
            entry: "cs_volume",
            layouts: &[&layout],
        },
    );
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("hairlab.fur.density.encoder"),
    });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.fur.density.pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    Ok(volume)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatches_cover_every_invocation_within_the_limit() {
        assert_eq!(dispatch_size(1, 65535), (1, 1));
        assert_eq!(dispatch_size(256, 65535), (1, 1));
        assert_eq!(dispatch_size(257, 65535), (2, 1));
        // 1.84 M sub-elements: 7188 groups in one row.
        assert_eq!(dispatch_size(1_840_128, 65535), (7188, 1));
        // 2^30 sub-elements: 2^22 groups, 65535 a row, 65 rows (65 · 65535 ≥ 4 194 304 > 64 · 65535).
        assert_eq!(dispatch_size(1 << 30, 65535), (65535, 65));
    }

    #[test]
    fn layer_heights_are_the_layer_centres() {
        let h = layer_heights(4, &VolumeParams::default());
        assert_eq!(
            h.iter().map(|x| x[0]).collect::<Vec<_>>(),
            [0.125, 0.375, 0.625, 0.875]
        );
        // γ = 2 by default: w².
        assert_eq!(h[1][1], 0.140625);
        assert!(
            layer_heights(2, &VolumeParams::uniform())
                .iter()
                .all(|x| x[1] == 0.0)
        );
    }
}
