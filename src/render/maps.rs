//! The light-map toolkit the shadow methods compose: array maps with one view per layer and one size budget,
//! additive light pipelines cached by colour-target count, and the bind-group layout entries every method
//! writes. A method's GPU file keeps only what is its own (its shader, uniforms and pass structure).

use crate::gpu::{Gpu, GpuError};
use crate::render::caster::stage::LightStage;

/// hairlab's budget for one method's light maps, in bytes: a limit of this workbench (it keeps a method from
/// taking the whole GPU by accident), not of the GPU.
pub const MAP_BUDGET_BYTES: u64 = 2 << 30;

/// Checks `bytes` of `what` against [`MAP_BUDGET_BYTES`].
pub fn check_budget(what: impl FnOnce() -> String, bytes: u64) -> Result<(), GpuError> {
    if bytes > MAP_BUDGET_BYTES {
        return Err(GpuError::OverBudget {
            what: what(),
            bytes,
            budget: MAP_BUDGET_BYTES,
        });
    }
    Ok(())
}

/// Bytes of one RGBA32F texel.
pub const RGBA32F_BYTES: u64 = 16;

/// An array texture of `layers` square layers (RGBA32F unless made [`ArrayMap::with_format`]): one 2D view per
/// layer (the colour targets of the light passes) and one array view (what the lookup reads).
pub struct ArrayMap {
    pub texture: wgpu::Texture,
    pub layer_views: Vec<wgpu::TextureView>,
    pub array_view: wgpu::TextureView,
    pub resolution: u32,
    pub layers: u32,
    pub format: wgpu::TextureFormat,
}

impl ArrayMap {
    /// Allocates an RGBA32F map (`hairlab.<label>`), within [`MAP_BUDGET_BYTES`].
    pub fn new(gpu: &Gpu, label: &str, resolution: u32, layers: u32) -> Result<ArrayMap, GpuError> {
        Self::with_format(gpu, label, resolution, layers, wgpu::TextureFormat::Rgba32Float)
    }

    /// Allocates a map of `format` (a colour format whose texels read as float and may be written as a storage
    /// texture: RGBA32F, RGBA16F, RGBA8 unorm), within [`MAP_BUDGET_BYTES`].
    pub fn with_format(
        gpu: &Gpu,
        label: &str,
        resolution: u32,
        layers: u32,
        format: wgpu::TextureFormat,
    ) -> Result<ArrayMap, GpuError> {
        let bytes = Self::bytes_of(resolution, layers, format);
        check_budget(
            || {
                format!(
                    "{label} of {layers} {} layers at {resolution}²",
                    format_name(format)
                )
            },
            bytes,
        )?;
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(&format!("hairlab.{label}")),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        let layer_views = (0..layers)
            .map(|l| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("hairlab.{label}.layer")),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: l,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(&format!("hairlab.{label}.array")),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        Ok(ArrayMap {
            texture,
            layer_views,
            array_view,
            resolution,
            layers,
            format,
        })
    }

    /// Bytes an RGBA32F map of `layers` layers at `resolution`² takes.
    pub fn bytes_for(resolution: u32, layers: u32) -> u64 {
        resolution as u64 * resolution as u64 * layers as u64 * RGBA32F_BYTES
    }

    /// Bytes a map of `format` takes.
    pub fn bytes_of(resolution: u32, layers: u32, format: wgpu::TextureFormat) -> u64 {
        let texel = format.block_copy_size(None).map_or(RGBA32F_BYTES, u64::from);
        resolution as u64 * resolution as u64 * layers as u64 * texel
    }

    pub fn bytes(&self) -> u64 {
        Self::bytes_of(self.resolution, self.layers, self.format)
    }

    /// Colour attachments for layers `first..first + count`, cleared to zero.
    pub fn attachments(&self, first: u32, count: u32) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
        cleared_attachments(&self.layer_views[first as usize..(first + count) as usize])
    }
}

/// A map format's name in messages: `RGBA32F`, `RGBA16F`, `RGBA8`, else wgpu's.
fn format_name(format: wgpu::TextureFormat) -> String {
    match format {
        wgpu::TextureFormat::Rgba32Float => "RGBA32F".to_string(),
        wgpu::TextureFormat::Rgba16Float => "RGBA16F".to_string(),
        wgpu::TextureFormat::Rgba8Unorm => "RGBA8".to_string(),
        other => format!("{other:?}"),
    }
}

/// Colour attachments of `views`, each cleared to zero and stored: the targets of an additive light pass.
pub fn cleared_attachments<'a, V: std::borrow::Borrow<wgpu::TextureView>>(
    views: &'a [V],
) -> Vec<Option<wgpu::RenderPassColorAttachment<'a>>> {
    views
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view: view.borrow(),
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect()
}

/// Light pipelines (the shared light vertex stage, built for the casters' stage) whose fragment stage adds into
/// `n` RGBA32F targets (One/One blending), built on first use for each `n` in `1..=8`.
pub struct AdditivePipelines {
    label: String,
    light: LightStage,
    groups: Vec<wgpu::BindGroupLayout>,
    module: wgpu::ShaderModule,
    entry: &'static str,
    pipelines: Vec<Option<wgpu::RenderPipeline>>,
}

impl AdditivePipelines {
    /// Most colour targets a pass writes (8 on every backend hairlab supports, lavapipe included).
    pub const MAX_TARGETS: u32 = 8;

    /// Pipelines of `module`'s fragment `entry` over bind groups `layouts` (group 0 the frame uniforms).
    pub fn new(
        label: &str,
        light: &LightStage,
        layouts: &[&wgpu::BindGroupLayout],
        module: wgpu::ShaderModule,
        entry: &'static str,
    ) -> AdditivePipelines {
        AdditivePipelines {
            label: label.to_string(),
            light: light.clone(),
            groups: layouts.iter().map(|l| (*l).clone()).collect(),
            module,
            entry,
            pipelines: vec![None; Self::MAX_TARGETS as usize],
        }
    }

    /// The pipeline writing `targets` (in `1..=8`) targets.
    pub fn get(&mut self, device: &wgpu::Device, targets: u32) -> &wgpu::RenderPipeline {
        let i = (targets.clamp(1, Self::MAX_TARGETS) - 1) as usize;
        let (label, light, module, entry) = (&self.label, &self.light, &self.module, self.entry);
        let groups: Vec<&wgpu::BindGroupLayout> = self.groups.iter().collect();
        self.pipelines[i].get_or_insert_with(|| {
            let state = Some(additive_target(wgpu::TextureFormat::Rgba32Float));
            light.pipeline(
                device,
                &format!("hairlab.{label}.pipeline"),
                &groups,
                module,
                entry,
                &vec![state; i + 1],
            )
        })
    }
}

/// A colour target of `format` that adds (One/One) colour and alpha.
pub fn additive_target(format: wgpu::TextureFormat) -> wgpu::ColorTargetState {
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState {
            color: add,
            alpha: add,
        }),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// Shader stages a method lookup runs in: the eye passes and the evaluation pass.
pub const LOOKUP_STAGES: wgpu::ShaderStages = wgpu::ShaderStages::FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

/// A uniform-buffer layout entry.
pub fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A non-filterable float texture layout entry of `dimension`.
pub fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A storage-buffer layout entry.
pub fn storage_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform buffer of `T` (`hairlab.<label>`), written with [`wgpu::Queue::write_buffer`].
pub fn uniform_buffer<T>(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(&format!("hairlab.{label}")),
        size: std::mem::size_of::<T>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_says_it_is_hairlabs() {
        assert!(check_budget(|| "x".into(), MAP_BUDGET_BYTES).is_ok());
        let e = check_budget(|| "osm map of 256 slices at 4096²".into(), 4 << 30).unwrap_err();
        assert_eq!(
            e.to_string(),
            "osm map of 256 slices at 4096² needs 4294967296 bytes, more than hairlab's light-map budget of \
             2147483648 bytes (a limit of this workbench, not of the GPU)"
        );
        assert_eq!(ArrayMap::bytes_for(512, 3), 512 * 512 * 3 * 16);
    }
}
