//! Deep Opacity Maps (Yuksel & Keyser 2008, §3; layer sizes §5): `K` layers (1..=16) follow each texel's
//! nearest strand depth `z0`, layer `k` spanning `z0 + d_(k-1)` to `z0 + d_k`; each stored value is the optical
//! depth accumulated up to a layer's far end, and `V(z)` interpolates linearly between the layer boundaries.
//! The CPU model is `visibility::dom`.
//!
//! GPU: `z0` is the shared near map of the light-depth pass (the paper's first pass), read by texel, not stored
//! again (the paper keeps it in the first channel of its single RGBA target); the far map is read only by the
//! stretch option. The layers live in an RGBA32F array texture of `ceil(K / 4)` layers (4 opacity layers per
//! texel each), all written by ONE geometry pass with `ceil(K / 4)` colour targets and additive blending (the
//! paper's second pass): a fragment adds its optical depth to its layer and every later one. The ends `d_k`
//! are a uniform filled from `visibility::dom::layer_ends`. Memory: 16 bytes per texel per 4 layers, plus the
//! near map it reads (4 bytes) and, for the stretch, the far map (4 bytes): DOM-3 takes 5 MiB at 512².
//!
//! `LayerMapsGpu` is that GPU side for any method whose maps are opacity layers placed per texel between the
//! shared depth maps; Bounding Opacity Maps (`methods::bom`) use it too.

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::passes;
use crate::visibility::dom::{MAX_LAYERS, layer_ends};
use crate::visibility::{BeyondLastLayer, DomParams, LayerSpacing, TexelModel};
use bytemuck::{Pod, Zeroable};

const LAYERS: ParamSpec = ParamSpec {
    key: "layers",
    label: "layers",
    help: "opacity layers K behind each texel's nearest strand (1..=16; the paper uses 3)",
    kind: ParamKind::Int { min: 1, max: 16 },
    default: 3.0,
};
const DEPTH_SPAN: ParamSpec = ParamSpec {
    key: "depth_span",
    label: "depth span",
    help: "total depth d_K of the K layers, in normalised light depth (fraction of the strands' light range)",
    kind: ParamKind::Float {
        min: 1e-4,
        max: 1.0,
        log: true,
    },
    default: 0.25,
};
const SPACING: ParamSpec = ParamSpec {
    key: "spacing",
    label: "spacing",
    help: "layer sizes: linear = linearly increasing (size of layer k proportional to k, the paper's), \
           uniform = all the same",
    kind: ParamKind::Choice {
        options: &["linear", "uniform"],
    },
    default: 0.0,
};
const BEYOND: ParamSpec = ParamSpec {
    key: "beyond",
    label: "beyond last layer",
    help: "fragments beyond the last layer: ignore them, add them to the last layer (the paper's choice), or \
           stretch each texel's layers to reach its furthest strand",
    kind: ParamKind::Choice {
        options: &["ignore", "add-to-last", "stretch"],
    },
    default: 1.0,
};
const PARAMS: &[ParamSpec] = &[LAYERS, DEPTH_SPAN, SPACING, BEYOND];

/// Layers one RGBA32F target holds.
const LAYERS_PER_TARGET: u32 = 4;

pub struct Dom;

fn dom_params(values: &ParamValues) -> DomParams {
    DomParams {
        layers: value(values, &LAYERS) as u32,
        depth_span: value(values, &DEPTH_SPAN),
        spacing: match value(values, &SPACING) as i32 {
            1 => LayerSpacing::Uniform,
            _ => LayerSpacing::LinearlyIncreasing,
        },
        beyond: match value(values, &BEYOND) as i32 {
            0 => BeyondLastLayer::Ignore,
            2 => BeyondLastLayer::Stretch,
            _ => BeyondLastLayer::AddToLast,
        },
    }
}

/// The layer count, the depth maps read and the uniforms for `values`.
fn dom_setup(values: &ParamValues) -> LayerSetup<DomUniforms> {
    let p = dom_params(values);
    let mut ends = [[0.0; 4]; (MAX_LAYERS / LAYERS_PER_TARGET) as usize];
    for (i, e) in layer_ends(&p).into_iter().enumerate() {
        ends[i / 4][i % 4] = e;
    }
    let beyond = match p.beyond {
        BeyondLastLayer::Ignore => 0,
        BeyondLastLayer::AddToLast => 1,
        BeyondLastLayer::Stretch => 2,
    };
    let layers = p.layer_count() as u32;
    LayerSetup {
        layers,
        // z0, and the far depth for the stretch.
        depth_maps: if p.beyond == BeyondLastLayer::Stretch {
            2
        } else {
            1
        },
        uniforms: DomUniforms {
            ends,
            layers,
            beyond,
            ..Zeroable::zeroed()
        },
    }
}

static INFO: MethodInfo = MethodInfo {
    name: "dom",
    label: "Deep opacity maps",
    paper: "Yuksel & Keyser 2008",
    role: Role::Approximation,
    lookup_wgsl: "methods/dom.wgsl",
    light_wgsl: &["dom.wgsl"],
    params: PARAMS,
    color: [255, 127, 14],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

/// The bench's layer counts; each is swept with both spacings.
const SWEEP_LAYERS: &[u32] = &[1, 2, 3, 4, 5, 7, 10, 15];

impl LightMethod for Dom {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "DomUniforms",
            DomUniforms {
                ends,
                layers,
                beyond,
                pad0,
                pad1
            }
        ))
    }
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu> {
        Box::new(LayerMapsGpu::new(
            gpu,
            LayerMethod {
                name: "dom",
                shader: "dom.wgsl",
                max_layers: MAX_LAYERS,
                setup: dom_setup,
            },
        ))
    }
}

impl ShadowMethod for Dom {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(dom_params(values))
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        let spacings = SPACING.options().len();
        SWEEP_LAYERS
            .iter()
            .flat_map(|&k| {
                (0..spacings).map(move |s| SweepPoint::fixed(&[("layers", k as f32), ("spacing", s as f32)]))
            })
            .collect()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        [3, 7]
            .map(|k| ParamValues::from([("layers".to_string(), k as f32)]))
            .to_vec()
    }
}

/// Mirrors `DomUniforms` in `shaders/common/dom_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct DomUniforms {
    /// `d_1..d_K` (layer `k` at `ends[k / 4][k % 4]`, 0-based), the rest 0.
    pub ends: [[f32; 4]; 4],
    pub layers: u32,
    /// 0 ignore, 1 add to the last layer, 2 stretch (the `beyond` parameter).
    pub beyond: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// What tells one layered opacity method's GPU side from another's.
pub(crate) struct LayerMethod<U> {
    /// Method name, for labels (`hairlab.<name>.<resource>`) and timings.
    pub name: &'static str,
    /// The light-pass shader: `vs_main`, `fs_main` writing `ceil(max_layers / 4)` RGBA32F outputs; group 1 its
    /// uniform (binding 0), the near (1) and far (2) maps.
    pub shader: &'static str,
    pub max_layers: u32,
    pub setup: fn(&ParamValues) -> LayerSetup<U>,
}

/// What a layered opacity method needs for some parameter values.
pub(crate) struct LayerSetup<U> {
    /// In `1..=max_layers`.
    pub layers: u32,
    /// Shared light-depth maps (4 bytes per texel each) the method reads: counted in its memory.
    pub depth_maps: u32,
    /// Read by both the light pass and the lookup.
    pub uniforms: U,
}

/// GPU side of a method storing `K` opacity layers per texel, placed per texel from the shared near/far maps:
/// an RGBA32F array texture of `ceil(K / 4)` layers filled by one geometry pass with additive blending. The
/// lookup's group 1 is the array texture (binding 0) and the uniform (binding 1).
pub(crate) struct LayerMapsGpu<U> {
    method: LayerMethod<U>,
    module: wgpu::ShaderModule,
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    /// Pipelines by number of targets, built on first use.
    pipelines: Vec<Option<wgpu::RenderPipeline>>,
    uniforms: wgpu::Buffer,
    pass_bind_group: Option<PassBindGroup>,
    maps: Option<LayerMaps>,
}

/// The light pass's group 1, for the light-depth maps it was made with.
struct PassBindGroup {
    near: wgpu::TextureView,
    far: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
}

struct LayerMaps {
    texture: wgpu::Texture,
    target_views: Vec<wgpu::TextureView>,
    lookup_bind_group: wgpu::BindGroup,
    resolution: u32,
    targets: u32,
    /// Of the last frame's parameters.
    depth_maps: u32,
}

impl<U: Pod> LayerMapsGpu<U> {
    pub(crate) fn new(gpu: &Gpu, method: LayerMethod<U>) -> LayerMapsGpu<U> {
        let device = &gpu.device;
        let name = method.name;
        let uniform_entry = |binding, visibility| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let texture_entry = |binding, visibility, view_dimension| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension,
                multisampled: false,
            },
            count: None,
        };
        let frag = wgpu::ShaderStages::FRAGMENT;
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("hairlab.{name}.pass_layout")),
            entries: &[
                uniform_entry(0, frag),
                texture_entry(1, frag, wgpu::TextureViewDimension::D2),
                texture_entry(2, frag, wgpu::TextureViewDimension::D2),
            ],
        });
        let look = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("hairlab.{name}.lookup_layout")),
            entries: &[
                texture_entry(0, look, wgpu::TextureViewDimension::D2Array),
                uniform_entry(1, look),
            ],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(&format!("hairlab.{name}.uniforms")),
            size: std::mem::size_of::<U>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        LayerMapsGpu {
            module: passes::shader_module(device, &format!("hairlab.{name}.shader"), method.shader, None),
            pass_layout,
            lookup_layout,
            pipelines: vec![None; method.max_layers.div_ceil(LAYERS_PER_TARGET) as usize],
            uniforms,
            pass_bind_group: None,
            maps: None,
            method,
        }
    }

    fn ensure_maps(&mut self, gpu: &Gpu, resolution: u32, targets: u32) -> Result<(), GpuError> {
        if self
            .maps
            .as_ref()
            .is_some_and(|m| m.resolution == resolution && m.targets == targets)
        {
            return Ok(());
        }
        let name = self.method.name;
        let bytes = resolution as u64 * resolution as u64 * targets as u64 * 16;
        if bytes > super::osm::MAX_MAP_BYTES {
            return Err(GpuError::TooLarge {
                what: format!(
                    "{name} map of {} layers at {resolution}²",
                    targets * LAYERS_PER_TARGET
                ),
                bytes,
                limit: super::osm::MAX_MAP_BYTES,
            });
        }
        let device = &gpu.device;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(&format!("hairlab.{name}.layers")),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: targets,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let target_views = (0..targets)
            .map(|l| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("hairlab.{name}.target")),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: l,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(&format!("hairlab.{name}.layers_view")),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let lookup_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("hairlab.{name}.lookup_bind_group")),
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
        self.maps = Some(LayerMaps {
            texture,
            target_views,
            lookup_bind_group,
            resolution,
            targets,
            depth_maps: 0,
        });
        Ok(())
    }

    /// (Re)makes the light pass's group 1 when the light-depth maps are new.
    fn ensure_pass_bind_group(&mut self, ctx: &MethodContext) {
        let (near, far) = (&ctx.light_maps.near_view, &ctx.light_maps.far_view);
        if self
            .pass_bind_group
            .as_ref()
            .is_some_and(|p| p.near == *near && p.far == *far)
        {
            return;
        }
        let bind_group = ctx.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("hairlab.{}.pass_bind_group", self.method.name)),
            layout: &self.pass_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(near),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(far),
                },
            ],
        });
        self.pass_bind_group = Some(PassBindGroup {
            near: near.clone(),
            far: far.clone(),
            bind_group,
        });
    }

    fn pipeline(&mut self, device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout, targets: usize) {
        if self.pipelines[targets - 1].is_some() {
            return;
        }
        let name = self.method.name;
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&format!("hairlab.{name}.layout")),
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
        self.pipelines[targets - 1] = Some(passes::light_pipeline(
            device,
            &format!("hairlab.{name}.pipeline"),
            &layout,
            &self.module,
            "fs_main",
            &vec![state; targets],
        ));
    }
}

impl<U: Pod + Send> MethodGpu for LayerMapsGpu<U> {
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let LayerSetup {
            layers,
            depth_maps,
            uniforms,
        } = (self.method.setup)(ctx.values);
        let targets = layers.div_ceil(LAYERS_PER_TARGET);
        self.ensure_maps(ctx.gpu, ctx.map_resolution(), targets)?;
        self.ensure_pass_bind_group(ctx);
        self.pipeline(&ctx.gpu.device, ctx.frame_layout, targets as usize);
        ctx.gpu
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let maps = self.maps.as_mut().expect("maps allocated above");
        maps.depth_maps = depth_maps;
        let attachments: Vec<_> = maps
            .target_views
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
        let name = self.method.name;
        let ts = timer
            .as_mut()
            .and_then(|t| t.pass(format!("{name}: layers 0-{}", layers - 1)));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&format!("hairlab.{name}.pass")),
            color_attachments: &attachments,
            depth_stencil_attachment: None,
            timestamp_writes: ts,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        passes::draw_strands(
            &mut pass,
            self.pipelines[targets as usize - 1]
                .as_ref()
                .expect("pipeline built above"),
            ctx.frame_bind_group,
            self.pass_bind_group.as_ref().map(|p| &p.bind_group),
            ctx.geometry,
        );
        Ok(())
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self
            .maps
            .as_ref()
            .expect("layer maps exist after the first record()")
            .lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.maps.as_ref().map_or(0, |m| {
            let texels = m.texture.width() as u64 * m.texture.height() as u64;
            texels * (m.targets as u64 * 16 + m.depth_maps as u64 * 4)
        })
    }
    fn shared_bytes(&self) -> u64 {
        self.maps.as_ref().map_or(0, |m| {
            m.texture.width() as u64 * m.texture.height() as u64 * m.depth_maps as u64 * 4
        })
    }
    fn geometry_passes(&self) -> u32 {
        1
    }
}
