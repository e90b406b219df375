//! Compressed deep shadow maps (Lokovic & Veach, "Deep Shadow Maps", SIGGRAPH 2000, §4): each texel's exact
//! visibility compressed by the paper's greedy algorithm into a piecewise-linear function within `epsilon` of it
//! at every depth. The CPU model (and the vertex layout, the vertical steps and the lookup) is `visibility::dsm`.
//!
//! GPU: the method owns an A-buffer (`render::passes::abuffer`) that sorts each list in place into (depth,
//! segment) order after each fill (`render::passes::list_sort`, n log n per list); a compute pipeline
//! (`shaders/dsm.wgsl`, 8×8 workgroups, one invocation per texel) walks it once (`shaders/common/list_walk.wgsl`)
//! and compresses, resuming across dispatches (each texel's walk and compressor state, 80 bytes, kept between
//! them): one dispatch per pass, except on a CPU adapter, whose llvmpipe stops a shader's loops after 65,535
//! iterations in all, where each dispatch takes as many batches as `list_pages::CPU_ADAPTER_LOOP_BUDGET` allows
//! and as many follow as the frame's longest list needs (`abuffer::ABuffer::walk_split`). `prepare` runs the
//! A-buffer's counting pass, then its filling pass, the sort and `cs_count` (each texel's vertex count into its
//! header, the total read back, blocking) and sizes the vertex buffer to exactly that total; `record` walks the
//! same sorted lists again, and `cs_compress` allocates each texel its counted vertices from an atomic counter,
//! writes them and the header `(offset, count)`. A texel whose vertices would not match its allocation is marked,
//! and the lookup answers -1 there, which every GPU test rejects (never seen). Two geometry passes per frame.
//!
//! Memory (`memory_bytes`, what the lookup reads): the headers, 8 bytes per texel, and the vertices, 8 bytes
//! (`z`, `V` as f32) each, as many as the compressor keeps (at most 2 per fragment: 16 bytes per fragment at
//! `epsilon = 0`); both within the device's storage binding size (else `GpuError::TooLarge` naming the map) and
//! hairlab's map budget. The A-buffer it builds from (16 bytes per fragment, 4 bytes per texel and the 1-byte
//! null target) is build memory (`MethodGpu::build_bytes`) with the walk state (80 bytes per texel), as is the
//! 8-byte allocator (not counted).

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::readback::copy_out;
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::maps::{LOOKUP_STAGES, check_budget, storage_entry, uniform_buffer, uniform_entry};
use crate::render::passes;
use crate::render::passes::abuffer::ABuffer;
use crate::render::passes::list_pages::ListPipeline;
use crate::render::passes::list_sort::ListOrder;
use crate::visibility::TexelModel;
use crate::visibility::dsm::DsmParams;
use bytemuck::{Pod, Zeroable};

const EPSILON: ParamSpec = ParamSpec {
    key: "epsilon",
    label: "error tolerance ε",
    help: "largest |V - V_ref| the compressor allows at any depth (0: the exact visibility, two vertices per \
           distinct depth)",
    kind: ParamKind::Float {
        min: 0.0,
        max: 0.5,
        log: false,
    },
    default: 0.01,
};
const PARAMS: &[ParamSpec] = &[EPSILON];

/// The bench's tolerances.
const SWEEP_EPSILON: &[f32] = &[0.0, 0.01, 0.05, 0.1];

/// Bytes of one vertex (`z`, `V`) and of one texel header (offset, count).
pub const VERTEX_BYTES: u64 = 8;
pub const HEADER_BYTES: u64 = 8;
/// Bytes of one texel's walk state (`DsmWalk` in `shaders/dsm.wgsl`).
pub const WALK_BYTES: u64 = 80;
/// Loop iterations of one fragment besides the walk along the list (at most two offers of two attempts).
const TAKE_ITERATIONS: u64 = 8;

pub struct Dsm;

static INFO: MethodInfo = MethodInfo {
    name: "dsm",
    label: "Deep shadow maps (compressed)",
    paper: "Lokovic & Veach 2000 (Deep Shadow Maps, §4 compression)",
    role: Role::Approximation,
    lookup_wgsl: "methods/dsm.wgsl",
    // Its A-buffer passes are the reference's (abuffer.wgsl, validated as a pass of its own).
    light_wgsl: &["dsm.wgsl"],
    params: PARAMS,
    color: [106, 61, 154],
    // The compressor and the lookup are the CPU model's f32 expressions in the same order (fragments in (depth,
    // segment) order, as the reference's sorted lists); only `log`, `exp` and division round differently.
    // Measured GPU = CPU max |ΔV| 7.7e-7 over 55,049 samples (ε 0.1, tests/it/gpu_dsm.rs), 6.0e-8 at ε 0; no
    // greedy decision flipped on the test scene (the GPU's vertex count equals the CPU model's).
    gpu_tolerance: 1e-5,
    gpu_outliers: 0.0,
};

fn dsm_params(values: &ParamValues) -> DsmParams {
    DsmParams {
        epsilon: value(values, &EPSILON),
    }
}

impl LightMethod for Dsm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "DsmUniforms",
            DsmUniforms {
                epsilon,
                resolution,
                steps,
                batch
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        Ok(Box::new(DsmGpu::new(ctx)))
    }
}

impl ShadowMethod for Dsm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(dsm_params(values))
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        SWEEP_EPSILON
            .iter()
            .map(|&e| SweepPoint::fixed(&[(EPSILON.key, e)]))
            .collect()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
}

/// Mirrors `DsmUniforms` in `shaders/common/dsm_uniforms.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct DsmUniforms {
    pub epsilon: f32,
    pub resolution: u32,
    /// Batches each texel takes per dispatch of the compressor.
    pub steps: u32,
    /// Fragments per batch of the walk along a list (`abuffer::WalkSplit`).
    pub batch: u32,
}

/// The compressed deep shadow map's GPU state: its A-buffer, the compressor and the compressed map.
pub struct DsmGpu {
    abuffer: ABuffer,
    count_pipeline: ListPipeline,
    compress_pipeline: ListPipeline,
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// `[vertices allocated, texels that did not fit]`, cleared each frame.
    alloc: wgpu::Buffer,
    /// Each texel's walk state ([`WALK_BYTES`]), cleared before each pass of dispatches.
    walks: wgpu::Buffer,
    /// Dispatches of each compressor pass this frame.
    dispatches: u32,
    headers: wgpu::Buffer,
    vertices: wgpu::Buffer,
    /// Vertices the vertex buffer holds (this frame's count), and the resolution the headers are for.
    capacity: u64,
    resolution: u32,
    pass_bind_group: wgpu::BindGroup,
    lookup_bind_group: wgpu::BindGroup,
}

fn storage_buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn buffer_entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

impl DsmGpu {
    fn new(ctx: &MethodContext) -> DsmGpu {
        let gpu = ctx.gpu;
        let device = &gpu.device;
        let abuffer = ABuffer::new(gpu, ctx.frame_layout, ctx.light)
            .named("dsm: A-buffer", "compressed deep shadow map A-buffer")
            .sorted(gpu, ListOrder::Depth);
        let cs = wgpu::ShaderStages::COMPUTE;
        // Binding numbers are those of shaders/dsm.wgsl (group 0) and shaders/methods/dsm.wgsl.
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.dsm.pass_layout"),
            entries: &[
                storage_entry(0, cs, false),
                storage_entry(1, cs, false),
                uniform_entry(2, cs),
                storage_entry(3, cs, false),
                storage_entry(4, cs, false),
            ],
        });
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.dsm.lookup_layout"),
            entries: &[
                storage_entry(0, LOOKUP_STAGES, true),
                storage_entry(1, LOOKUP_STAGES, true),
                uniform_entry(2, LOOKUP_STAGES),
            ],
        });
        let module = passes::shader_module(device, "hairlab.dsm.shader", "dsm.wgsl", None);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.dsm.compress_layout"),
            bind_group_layouts: &[Some(&pass_layout), Some(&abuffer.lookup_layout)],
            immediate_size: 0,
        });
        let pipeline =
            |entry: &str| ListPipeline::new("hairlab.dsm.compress_pipeline", &layout, &module, entry);
        let (count_pipeline, compress_pipeline) = (pipeline("cs_count"), pipeline("cs_compress"));
        let uniforms = uniform_buffer::<DsmUniforms>(device, "dsm.uniforms");
        let alloc = storage_buffer(gpu, "hairlab.dsm.alloc", 8);
        let headers = storage_buffer(gpu, "hairlab.dsm.headers", HEADER_BYTES);
        let vertices = storage_buffer(gpu, "hairlab.dsm.vertices", VERTEX_BYTES);
        let walks = storage_buffer(gpu, "hairlab.dsm.walks", WALK_BYTES);
        let (pass_bind_group, lookup_bind_group) = bind_groups(
            gpu,
            &pass_layout,
            &lookup_layout,
            [&headers, &vertices, &uniforms, &alloc, &walks],
        );
        DsmGpu {
            abuffer,
            count_pipeline,
            compress_pipeline,
            pass_layout,
            lookup_layout,
            uniforms,
            alloc,
            walks,
            dispatches: 1,
            headers,
            vertices,
            capacity: 1,
            resolution: 1,
            pass_bind_group,
            lookup_bind_group,
        }
    }
}

/// The compressor's group 0 and the lookup's group 1 over `[headers, vertices, uniforms, alloc, walks]`.
fn bind_groups(
    gpu: &Gpu,
    pass_layout: &wgpu::BindGroupLayout,
    lookup_layout: &wgpu::BindGroupLayout,
    [headers, vertices, uniforms, alloc, walks]: [&wgpu::Buffer; 5],
) -> (wgpu::BindGroup, wgpu::BindGroup) {
    let pass = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hairlab.dsm.pass_bind_group"),
        layout: pass_layout,
        entries: &[
            buffer_entry(0, headers),
            buffer_entry(1, vertices),
            buffer_entry(2, uniforms),
            buffer_entry(3, alloc),
            buffer_entry(4, walks),
        ],
    });
    let lookup = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hairlab.dsm.lookup_bind_group"),
        layout: lookup_layout,
        entries: &[
            buffer_entry(0, headers),
            buffer_entry(1, vertices),
            buffer_entry(2, uniforms),
        ],
    });
    (pass, lookup)
}

impl DsmGpu {
    /// Records `pipeline` over every texel, [`DsmGpu::dispatches`] times from fresh walk states (each dispatch
    /// resumes the walks where the one before stopped).
    fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &ListPipeline,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        encoder.clear_buffer(&self.walks, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.dsm.compress"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(pipeline.for_pages(self.abuffer.pages_used()));
        pass.set_bind_group(0, &self.pass_bind_group, &[]);
        pass.set_bind_group(1, &self.abuffer.lookup_bind_group, &[]);
        let groups = self.resolution.div_ceil(8);
        for _ in 0..self.dispatches {
            pass.dispatch_workgroups(groups, groups, 1);
        }
    }

    fn rebind(&mut self, gpu: &Gpu) {
        (self.pass_bind_group, self.lookup_bind_group) = bind_groups(
            gpu,
            &self.pass_layout,
            &self.lookup_layout,
            [
                &self.headers,
                &self.vertices,
                &self.uniforms,
                &self.alloc,
                &self.walks,
            ],
        );
    }
}

impl MethodGpu for DsmGpu {
    /// Counts the frame's fragments (the A-buffer's counting pass), fills the lists and counts each texel's
    /// vertices (submitted at once and read back, blocking), and sizes the vertex buffer to that count.
    fn prepare(&mut self, ctx: &MethodContext, timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let gpu = ctx.gpu;
        let resolution = ctx.map_resolution();
        self.abuffer
            .prepare(gpu, ctx.frame_bind_group, ctx.casters, resolution, timer)?;
        let split = self
            .abuffer
            .walk_split(gpu, "The compressed deep shadow map", TAKE_ITERATIONS)?;
        self.dispatches = split.dispatches;
        self.count_pipeline
            .prepare(&gpu.device, self.abuffer.pages_used());
        self.compress_pipeline
            .prepare(&gpu.device, self.abuffer.pages_used());
        let fragments = self.abuffer.fragment_count;
        let what = |vertices: Option<u64>| {
            let vertices = vertices.map_or(String::new(), |v| format!("{v} vertices, "));
            format!(
                "the compressed deep shadow map ({vertices}{fragments} light-space fragments at {resolution}² \
                 texels; lower the map resolution or the strand count)"
            )
        };
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        let header_bytes = resolution as u64 * resolution as u64 * HEADER_BYTES;
        if header_bytes > limit {
            return Err(GpuError::TooLarge {
                what: what(None),
                bytes: header_bytes,
                limit,
            });
        }
        gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&DsmUniforms {
                epsilon: dsm_params(ctx.values).epsilon,
                resolution,
                steps: split.steps,
                batch: split.batch,
            }),
        );
        let walk_bytes = resolution as u64 * resolution as u64 * WALK_BYTES;
        if walk_bytes > limit {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the compressed deep shadow map's walk state hairlab.dsm.walks ({WALK_BYTES} B at \
                     {resolution}² texels; lower the map resolution)"
                ),
                bytes: walk_bytes,
                limit,
            });
        }
        if resolution != self.resolution {
            self.resolution = resolution;
            self.headers = storage_buffer(gpu, "hairlab.dsm.headers", header_bytes);
            self.walks = storage_buffer(gpu, "hairlab.dsm.walks", walk_bytes);
            self.rebind(gpu);
        }
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.dsm.count"),
            });
        self.abuffer
            .record(ctx.frame_bind_group, ctx.casters, &mut encoder, timer);
        encoder.clear_buffer(&self.alloc, 0, None);
        let timestamps = timer.as_mut().and_then(|t| {
            t.compute_pass(
                &mut encoder,
                crate::gpu::timing::Phase::Method,
                "dsm: count vertices",
            )
        });
        self.dispatch(&mut encoder, &self.count_pipeline, timestamps);
        gpu.queue.submit([encoder.finish()]);
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.alloc)?);
        let vertices = u64::from(counts[0]);
        let vertex_bytes = vertices.max(1) * VERTEX_BYTES;
        if vertex_bytes > limit {
            return Err(GpuError::TooLarge {
                what: what(Some(vertices)),
                bytes: vertex_bytes,
                limit,
            });
        }
        check_budget(|| what(Some(vertices)), vertex_bytes + header_bytes)?;
        if vertices.max(1) != self.capacity {
            self.capacity = vertices.max(1);
            self.vertices = storage_buffer(gpu, "hairlab.dsm.vertices", vertex_bytes);
            self.rebind(gpu);
        }
        Ok(())
    }

    /// Compresses the lists [`DsmGpu::prepare`] filled and sorted this frame.
    fn record(
        &mut self,
        _ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        encoder.clear_buffer(&self.alloc, 0, None);
        let timestamps = timer
            .as_mut()
            .and_then(|t| t.compute_pass(encoder, crate::gpu::timing::Phase::Method, "dsm: compress"));
        self.dispatch(encoder, &self.compress_pipeline, timestamps);
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.headers.size() + self.vertices.size()
    }
    /// The A-buffer the compressor reads and the walk state.
    fn build_bytes(&self) -> u64 {
        self.abuffer.memory_bytes() + self.walks.size()
    }
    /// The A-buffer's counting pass and its filling pass.
    fn geometry_passes(&self) -> u32 {
        2
    }
}
