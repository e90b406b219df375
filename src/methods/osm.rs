//! Opacity Shadow Maps (Kim & Neumann 2001, as described by Yuksel & Keyser 2008 §2 and Voicu's thesis §3):
//! `N` uniform slices (1..=256) across the strands' whole fitted light range; each stored value is the optical
//! depth accumulated up to a slice's far plane, and `V(z)` interpolates linearly between planes. The CPU model
//! is `visibility::osm`.
//!
//! GPU: the slices live in an RGBA32F array texture (4 slices per layer). One geometry pass fills 8 layers
//! (8 colour targets × 4 channels = 32 slices) with additive blending, so `N` slices take `ceil(N / 32)`
//! geometry passes: OSM-256 takes 8.

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::passes;
use crate::visibility::{OsmParams, TexelModel};
use bytemuck::{Pod, Zeroable};

/// Slices one geometry pass fills (8 RGBA32F targets).
pub const SLICES_PER_PASS: u32 = 32;
/// Largest slice map hairlab allocates, in bytes.
pub const MAX_MAP_BYTES: u64 = 2 << 30;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    key: "slices",
    label: "slices",
    help: "uniform slices across the strands' light-depth range (1..=256)",
    kind: ParamKind::Int { min: 1, max: 256 },
    default: 16.0,
}];

pub struct Osm;

fn slices(values: &ParamValues) -> u32 {
    value(values, &PARAMS[0]) as u32
}

static INFO: MethodInfo = MethodInfo {
    name: "osm",
    label: "Opacity shadow maps",
    paper: "Kim & Neumann 2001 (as in Yuksel & Keyser 2008 §2)",
    role: Role::Approximation,
    lookup_wgsl: "methods/osm.wgsl",
    light_wgsl: &["osm.wgsl"],
    params: PARAMS,
    color: [31, 119, 180],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

/// The bench's slice counts.
const SWEEP_SLICES: &[u32] = &[4, 8, 16, 32, 64, 128, 256];

impl LightMethod for Osm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "OsmUniforms",
            OsmUniforms {
                slices,
                pad0,
                pad1,
                pad2
            }
        ))
    }
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu> {
        Box::new(OsmGpu::new(gpu))
    }
}

impl ShadowMethod for Osm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(OsmParams {
            slices: slices(values),
        })
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        SWEEP_SLICES
            .iter()
            .map(|&n| SweepPoint::fixed(&[("slices", n as f32)]))
            .collect()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        [16, 64, 256]
            .map(|n| ParamValues::from([("slices".to_string(), n as f32)]))
            .to_vec()
    }
}

/// Mirrors `OsmUniforms` in `shaders/common/osm_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct OsmUniforms {
    pub slices: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

pub struct OsmGpu {
    module: wgpu::ShaderModule,
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    /// Pipelines by number of targets (1..=8), built on first use.
    pipelines: Vec<Option<wgpu::RenderPipeline>>,
    uniforms: wgpu::Buffer,
    pass_bind_group: wgpu::BindGroup,
    maps: Option<OsmMaps>,
}

struct OsmMaps {
    texture: wgpu::Texture,
    layer_views: Vec<wgpu::TextureView>,
    lookup_bind_group: wgpu::BindGroup,
    resolution: u32,
    layers: u32,
}

impl OsmGpu {
    fn new(gpu: &Gpu) -> OsmGpu {
        let device = &gpu.device;
        let uniform_entry = |visibility| wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.osm.pass_layout"),
            entries: &[uniform_entry(wgpu::ShaderStages::FRAGMENT)],
        });
        let look = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.osm.lookup_layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: look,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    ..uniform_entry(look)
                },
            ],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.osm.uniforms"),
            size: std::mem::size_of::<OsmUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let pass_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.osm.pass_bind_group"),
            layout: &pass_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        OsmGpu {
            module: passes::shader_module(device, "hairlab.osm.shader", "osm.wgsl", None),
            pass_layout,
            lookup_layout,
            pipelines: vec![None; 8],
            uniforms,
            pass_bind_group,
            maps: None,
        }
    }

    fn ensure_maps(&mut self, gpu: &Gpu, resolution: u32, layers: u32) -> Result<(), GpuError> {
        if self
            .maps
            .as_ref()
            .is_some_and(|m| m.resolution == resolution && m.layers == layers)
        {
            return Ok(());
        }
        let bytes = resolution as u64 * resolution as u64 * layers as u64 * 16;
        if bytes > MAX_MAP_BYTES {
            return Err(GpuError::TooLarge {
                what: format!("opacity shadow map of {} slices at {resolution}²", layers * 4),
                bytes,
                limit: MAX_MAP_BYTES,
            });
        }
        let device = &gpu.device;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("hairlab.osm.slices"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer_views = (0..layers)
            .map(|l| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("hairlab.osm.slice_layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: l,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("hairlab.osm.slices_view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let lookup_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.osm.lookup_bind_group"),
            layout: &self.lookup_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&array_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.uniforms.as_entire_binding(),
                },
            ],
        });
        self.maps = Some(OsmMaps {
            texture,
            layer_views,
            lookup_bind_group,
            resolution,
            layers,
        });
        Ok(())
    }

    fn pipeline(&mut self, device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout, targets: usize) {
        if self.pipelines[targets - 1].is_some() {
            return;
        }
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.osm.layout"),
            bind_group_layouts: &[Some(frame_layout), Some(&self.pass_layout)],
            immediate_size: 0,
        });
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let state = Some(wgpu::ColorTargetState {
            format: wgpu::TextureFormat::Rgba32Float,
            blend: Some(wgpu::BlendState {
                color: add,
                alpha: add,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        });
        let states = vec![state; targets];
        self.pipelines[targets - 1] = Some(passes::light_pipeline(
            device,
            "hairlab.osm.pipeline",
            &layout,
            &self.module,
            "fs_main",
            &states,
        ));
    }
}

impl MethodGpu for OsmGpu {
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let n = slices(ctx.values).clamp(1, 256);
        let layers = n.div_ceil(4);
        self.ensure_maps(ctx.gpu, ctx.map_resolution(), layers)?;
        ctx.gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&OsmUniforms {
                slices: n,
                ..Zeroable::zeroed()
            }),
        );
        let passes_needed = layers.div_ceil(8);
        for p in 0..passes_needed {
            let first = p * 8;
            let count = (layers - first).min(8) as usize;
            self.pipeline(&ctx.gpu.device, ctx.frame_layout, count);
            let maps = self.maps.as_ref().expect("maps allocated above");
            let attachments: Vec<_> = maps.layer_views[first as usize..first as usize + count]
                .iter()
                .map(|view| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                })
                .collect();
            let ts = timer.as_mut().and_then(|t| {
                t.pass(format!(
                    "osm: slices {}-{}",
                    first * 4,
                    (first * 4 + count as u32 * 4).min(n) - 1
                ))
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlab.osm.pass"),
                color_attachments: &attachments,
                depth_stencil_attachment: None,
                timestamp_writes: ts,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let geometry = ctx.geometry;
            if geometry.hair_index_count == 0 {
                continue;
            }
            pass.set_pipeline(self.pipelines[count - 1].as_ref().expect("pipeline built above"));
            pass.set_bind_group(0, ctx.frame_bind_group, &[]);
            pass.set_bind_group(1, &self.pass_bind_group, &[]);
            pass.set_vertex_buffer(0, geometry.hair_vertices.slice(..));
            pass.set_index_buffer(geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
            // The instance index tells the shader which 32 slices this pass writes.
            pass.draw_indexed(0..geometry.hair_index_count, 0, p..p + 1);
        }
        Ok(())
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self
            .maps
            .as_ref()
            .expect("OSM maps exist after the first record()")
            .lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.maps.as_ref().map_or(0, |m| {
            m.texture.width() as u64 * m.texture.height() as u64 * m.layers as u64 * 16
        })
    }
    fn geometry_passes(&self) -> u32 {
        self.maps.as_ref().map_or(0, |m| m.layers.div_ceil(8))
    }
}
