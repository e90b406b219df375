//! Occupancy Maps (Sintorn & Assarsson, I3D 2009, §3.1-3.3). The CPU model, which this GPU side matches texel for
//! texel, is `visibility::occupancy`.
//!
//! GPU: per texel, the depth range is the shared light-depth maps (`near`, `far`, §3.1 Fig. 7). One geometry pass
//! fills both maps (the paper uses two, one per blend function, and notes that one suffices where the blend
//! functions can differ per target; storage-buffer atomics do that here), two storage buffers of 16 bytes per
//! texel each, texel `t` in the u32 words `[4t, 4t + 4)`:
//! - `hairlab.occupancy.bitmap`: the 128-slice occupancy bitmap, four u32 words (slice `s` = bit `s & 31` of
//!   word `s >> 5`), set with `atomicOr` (wgpu has no logic-op blending);
//! - `hairlab.occupancy.slabs`: the fragment count of each of the 4 slabs (slab map, `atomicAdd`); with the
//!   occupancy-only variant, the texel's total count in word 0.
//!
//! The lookup (`shaders/methods/occupancy.wgsl`) is the order estimate of §3.2 with the interpolation inside
//! the slice, and `V = exp(-o * b)` with `b = -ln(1 - alpha)` from the global hair alpha (`frame.hair_alpha`,
//! the CPU model's `OccupancyParams::alpha` = [`MethodContext::hair_alpha`]); each fragment's own alpha is
//! ignored, as in the paper.
//! In `render.alpha = "coverage"` mode it still takes `render.hair_alpha` (there the material opacity) as that alpha;
//! under `render.hair_model = fibres`, `1 − e^(−1)`, the Boolean model's one fibre crossed per fragment
//! (`RenderSettings::light_opacity`).
//!
//! The half-texel jitter of §3.3 is not a parameter here: it offsets the continuous texture coordinate before
//! the texel is chosen, which happens in the shared `hair_visibility` (`common/method_lookup.wgsl`) before
//! `visibility_at(texel, z)` is called; the lookup only receives the integer texel, and half a texel around
//! its centre never leaves it. The per-texel CPU model cannot specify it either (its doc says so).
//!
//! Memory: 16 + 16 bytes of maps, the 8 bytes of the shared depth-range maps the method reads, and the 1-byte
//! [`NullTarget`](passes::NullTarget) that sets the render area: 41 bytes per texel, 10.25 MiB at 512² (the paper,
//! §4: 10 MB for its depth-range, occupancy and slab maps at 512²). Each buffer must fit the device's storage
//! binding size (128 MiB on lavapipe: up to 2048²); beyond, [`GpuError::TooLarge`].

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::GpuError;
use crate::gpu::timing::GpuTimer;
use crate::render::caster::draw_casters;
use crate::render::passes;
use crate::visibility::{OccupancyParams, OccupancyVariant, TexelModel};
use bytemuck::{Pod, Zeroable};

/// Bytes per texel of each of the two storage buffers (four u32).
pub const BUFFER_BYTES_PER_TEXEL: u64 = 16;
/// Bytes per texel of the shared depth-range maps (two R32Float) the method reads.
pub const DEPTH_RANGE_BYTES_PER_TEXEL: u64 = 8;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    key: "variant",
    label: "variant",
    help: "slab-map: occupancy map + slab map (4 slabs of 32 slices, the paper's method); \
           occupancy-only: occupancy map only (one count for the whole range, the simpler variant of §3)",
    kind: ParamKind::Choice {
        options: &["slab-map", "occupancy-only"],
    },
    default: 0.0,
}];

pub struct Occupancy;

fn variant(values: &ParamValues) -> OccupancyVariant {
    if value(values, &PARAMS[0]) >= 0.5 {
        OccupancyVariant::OccupancyOnly
    } else {
        OccupancyVariant::SlabMap
    }
}

static INFO: MethodInfo = MethodInfo {
    name: "occupancy",
    label: "Occupancy maps",
    paper: "Sintorn & Assarsson 2009 §3",
    role: Role::Approximation,
    lookup_wgsl: "methods/occupancy.wgsl",
    light_wgsl: &["occupancy.wgsl"],
    params: PARAMS,
    color: [148, 103, 189],
    gpu_tolerance: 1e-4,
    gpu_outliers: 0.0,
};

impl LightMethod for Occupancy {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "OccupancyUniforms",
            OccupancyUniforms {
                variant,
                pad0,
                pad1,
                pad2
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        Ok(Box::new(OccupancyGpu::create(ctx)?))
    }
}

impl ShadowMethod for Occupancy {
    fn model(&self, values: &ParamValues, hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(OccupancyParams {
            alpha: hair_alpha,
            variant: variant(values),
        })
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        (0..PARAMS[0].options().len())
            .map(|v| SweepPoint::fixed(&[("variant", v as f32)]))
            .collect()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
}

/// Mirrors `OccupancyUniforms` in `shaders/common/occupancy_uniforms.wgsl` (included by the light pass and the
/// lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct OccupancyUniforms {
    /// 0: slab map, 1: occupancy only.
    pub variant: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// What does not depend on the map resolution: layouts, the pipeline, the uniform buffer.
struct OccupancyResources {
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
}

/// Occupancy maps' GPU state, created with its buffers (so they always exist).
pub struct OccupancyGpu {
    res: OccupancyResources,
    target: passes::NullTarget,
    maps: OccupancyMaps,
}

struct OccupancyMaps {
    bitmap: wgpu::Buffer,
    slabs: wgpu::Buffer,
    /// The light-depth maps the pass bind group reads (re-created with the map resolution).
    near: wgpu::Texture,
    far: wgpu::Texture,
    pass_bind_group: wgpu::BindGroup,
    lookup_bind_group: wgpu::BindGroup,
    resolution: u32,
}

fn entry(binding: u32, visibility: wgpu::ShaderStages, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    }
}

fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

const UNIFORM: wgpu::BindingType = wgpu::BindingType::Buffer {
    ty: wgpu::BufferBindingType::Uniform,
    has_dynamic_offset: false,
    min_binding_size: None,
};

const DEPTH_TEXTURE: wgpu::BindingType = wgpu::BindingType::Texture {
    sample_type: wgpu::TextureSampleType::Float { filterable: false },
    view_dimension: wgpu::TextureViewDimension::D2,
    multisampled: false,
};

impl OccupancyResources {
    fn new(ctx: &MethodContext) -> OccupancyResources {
        let device = &ctx.gpu.device;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.occupancy.pass_layout"),
            entries: &[
                entry(0, frag, DEPTH_TEXTURE),
                entry(1, frag, DEPTH_TEXTURE),
                entry(2, frag, storage(false)),
                entry(3, frag, storage(false)),
                entry(4, frag, UNIFORM),
            ],
        });
        let look = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.occupancy.lookup_layout"),
            entries: &[
                entry(0, look, storage(true)),
                entry(1, look, storage(true)),
                entry(2, look, UNIFORM),
            ],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.occupancy.uniforms"),
            size: std::mem::size_of::<OccupancyUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let module = ctx
            .light
            .module(device, "hairlab.occupancy.shader", "occupancy.wgsl");
        let pipeline = ctx.light.pipeline(
            device,
            "hairlab.occupancy.pipeline",
            &[ctx.frame_layout, &pass_layout],
            &module,
            "fs_main",
            &[passes::NullTarget::target_state()],
        );
        OccupancyResources {
            pass_layout,
            lookup_layout,
            pipeline,
            uniforms,
        }
    }

    /// (Re)allocates the two buffers for `ctx`'s map resolution and binds them with the current light-depth
    /// maps; refuses buffers beyond the device's storage binding size.
    fn make_maps(&self, ctx: &MethodContext) -> Result<OccupancyMaps, GpuError> {
        let resolution = ctx.map_resolution();
        let (near, far) = (&ctx.light_maps.near, &ctx.light_maps.far);
        let device = &ctx.gpu.device;
        let limits = device.limits();
        let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let bytes = resolution as u64 * resolution as u64 * BUFFER_BYTES_PER_TEXEL;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the occupancy bitmap and the slab map at {resolution}² ({BUFFER_BYTES_PER_TEXEL} bytes per \
                     texel each; lower the map resolution)"
                ),
                bytes,
                limit,
            });
        }
        let buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let bitmap = buffer("hairlab.occupancy.bitmap");
        let slabs = buffer("hairlab.occupancy.slabs");
        let near_view = near.create_view(&Default::default());
        let far_view = far.create_view(&Default::default());
        let pass_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.occupancy.pass_bind_group"),
            layout: &self.pass_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&near_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&far_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: bitmap.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: slabs.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: self.uniforms.as_entire_binding(),
                },
            ],
        });
        let lookup_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.occupancy.lookup_bind_group"),
            layout: &self.lookup_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: bitmap.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: slabs.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.uniforms.as_entire_binding(),
                },
            ],
        });
        Ok(OccupancyMaps {
            bitmap,
            slabs,
            near: near.clone(),
            far: far.clone(),
            pass_bind_group,
            lookup_bind_group,
            resolution,
        })
    }
}

impl OccupancyGpu {
    fn create(ctx: &MethodContext) -> Result<OccupancyGpu, GpuError> {
        let res = OccupancyResources::new(ctx);
        let maps = res.make_maps(ctx)?;
        Ok(OccupancyGpu {
            res,
            target: passes::NullTarget::new(&ctx.gpu.device, ctx.map_resolution()),
            maps,
        })
    }
}

impl MethodGpu for OccupancyGpu {
    fn prepare(&mut self, ctx: &MethodContext, _timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let m = &self.maps;
        let light = ctx.light_maps;
        if m.resolution != ctx.map_resolution() || m.near != light.near || m.far != light.far {
            self.maps = self.res.make_maps(ctx)?;
        }
        self.target.ensure(&ctx.gpu.device, ctx.map_resolution());
        ctx.gpu.queue.write_buffer(
            &self.res.uniforms,
            0,
            bytemuck::bytes_of(&OccupancyUniforms {
                variant: match variant(ctx.values) {
                    OccupancyVariant::SlabMap => 0,
                    OccupancyVariant::OccupancyOnly => 1,
                },
                ..Zeroable::zeroed()
            }),
        );
        Ok(())
    }

    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        let maps = &self.maps;
        encoder.clear_buffer(&maps.bitmap, 0, None);
        encoder.clear_buffer(&maps.slabs, 0, None);
        let ts = timer
            .as_mut()
            .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, "occupancy: bitmap + slab map"));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.occupancy.pass"),
            color_attachments: &[self.target.attachment()],
            depth_stencil_attachment: None,
            timestamp_writes: ts,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw_casters(
            &mut pass,
            &self.res.pipeline,
            ctx.frame_bind_group,
            Some(&maps.pass_bind_group),
            ctx.casters,
            0..1,
        );
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.res.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.maps.lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        let m = &self.maps;
        let texels = m.resolution as u64 * m.resolution as u64;
        m.bitmap.size() + m.slabs.size() + texels * DEPTH_RANGE_BYTES_PER_TEXEL + self.target.bytes()
    }
    fn shared_bytes(&self) -> u64 {
        let r = self.maps.resolution as u64;
        r * r * DEPTH_RANGE_BYTES_PER_TEXEL
    }
    fn geometry_passes(&self) -> u32 {
        1
    }
}
