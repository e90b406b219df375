//! Adaptive volumetric shadow maps (Salvi, Vidimče, Lauritzen & Lefohn, EGSR 2010): `N` nodes
//! `(depth, transmittance)` per texel, built by inserting every fragment as a step and removing the node of least
//! area on overflow. The CPU model (the specification, with the curve and the insertion rules) is
//! `visibility::avsm`.
//!
//! GPU: wgpu has no rasteriser-ordered views, so this is the paper's first implementation — per-texel fragment
//! lists, then compression: the method owns an A-buffer (`render::passes::abuffer`: a counting pass sizes it, one
//! geometry pass fills it), and a compute pass (`shaders/avsm.wgsl`, one invocation per texel) walks each list in
//! the model's insertion order and writes the texel's `N` nodes to `hairlab.avsm.nodes`, `N × 8` bytes per texel
//! (two f32), which the lookup (`shaders/methods/avsm.wgsl`) reads. The A-buffer sorts each list in place into
//! the model's insertion order ((depth, segment, alpha, node index) or (segment, depth, alpha, node index);
//! `render::passes::list_sort`, n log n per list) and the pass walks it once (`shaders/common/list_walk.wgsl`), so
//! the nodes equal the CPU model's for every list length. The walk resumes across dispatches (each texel's last
//! fragment, node count and whether its list is done kept in a 32-byte walk state, the nodes in the output slots):
//! one dispatch inserts every fragment, except on a CPU adapter, whose llvmpipe stops a shader's loops after
//! 65,535 iterations in all: there each dispatch takes as many batches of 32 as `list_pages::CPU_ADAPTER_LOOP_BUDGET`
//! allows (`abuffer::WalkSplit`), and as many dispatches follow as the frame's longest list (counted by the
//! A-buffer's counting pass) needs (3 for 1300 fragments), the nodes the same however the walk is split. `N` is
//! any count in
//! 4..=16 (the sample's 4, 8, 12, 16 come from packing nodes into RGBA targets; a storage buffer needs no
//! packing).
//!
//! Memory: [`MethodGpu::memory_bytes`] is the node buffer alone (`N × 8` B per texel), what the lookup reads.
//! The A-buffer is build memory, held only to build the nodes each frame: 4 B per texel (heads) + 16 B per
//! light-space fragment + 16 B of counters + the 1 B per texel null target, reported as
//! [`MethodGpu::build_bytes`], with the 32-byte walk state per texel (`shared_bytes` is 0: nothing is shared with
//! the renderer). Both storage buffers are checked against the
//! device's storage binding size (a `GpuError::TooLarge` naming the map). Geometry passes: 2 (count, fill).

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::maps::{LOOKUP_STAGES, storage_entry, uniform_buffer, uniform_entry};
use crate::render::passes;
use crate::render::passes::abuffer::ABuffer;
use crate::render::passes::list_pages::ListPipeline;
use crate::render::passes::list_sort::ListOrder;
use crate::visibility::TexelModel;
use crate::visibility::avsm::{AvsmParams, InsertionOrder, MAX_NODES, MIN_NODES};
use bytemuck::{Pod, Zeroable};

/// Bytes of one node (depth, transmittance: two f32).
pub const NODE_BYTES: u64 = 8;
/// Bytes of one texel's walk state (`AvsmWalk` in `shaders/avsm.wgsl`).
pub const WALK_BYTES: u64 = 32;
/// Loop iterations of one insertion besides the walk along the list (finding its place, shifting, two rounds
/// of compression over at most `MAX_NODES + 2` nodes: `6 (MAX_NODES + 2) + 1`).
const INSERT_ITERATIONS: u64 = 6 * (MAX_NODES as u64 + 2) + 1;

const NODES: ParamSpec = ParamSpec {
    key: "nodes",
    label: "nodes",
    help: "nodes (depth, transmittance) per texel, N (4..=16; the paper's sample uses 4, 8, 12, 16)",
    kind: ParamKind::Int {
        min: MIN_NODES as i32,
        max: MAX_NODES as i32,
    },
    default: 8.0,
};
const ORDER: ParamSpec = ParamSpec {
    key: "order",
    label: "insertion order",
    help: "order the fragments are inserted in: depth (front to back, deterministic) or submission (primitive \
           order, as a rasteriser-ordered implementation inserts)",
    kind: ParamKind::Choice {
        options: &["depth", "submission"],
    },
    default: 0.0,
};
const PARAMS: &[ParamSpec] = &[NODES, ORDER];

pub struct Avsm;

static INFO: MethodInfo = MethodInfo {
    name: "avsm",
    label: "Adaptive volumetric shadow maps",
    paper: "Salvi, Vidimče, Lauritzen & Lefohn 2010 (EGSR; Intel's AVSM sample)",
    role: Role::Approximation,
    lookup_wgsl: "methods/avsm.wgsl",
    light_wgsl: &["avsm.wgsl"],
    params: PARAMS,
    color: [0, 128, 128],
    // Measured on lavapipe: max |ΔV| 0 (bit-identical) over 25,810 samples at N = 4, 5, 8, 12, 16 in both orders;
    // the tolerance leaves room for another device's division rounding in `interpolate`.
    gpu_tolerance: 1e-5,
    gpu_outliers: 0.0,
};

fn avsm_params(values: &ParamValues) -> AvsmParams {
    AvsmParams {
        nodes: (value(values, &NODES) as usize).clamp(MIN_NODES, MAX_NODES),
        order: if value(values, &ORDER) == 1.0 {
            InsertionOrder::Submission
        } else {
            InsertionOrder::Depth
        },
    }
}

/// The order the A-buffer's lists are sorted and inserted in.
fn list_order(order: InsertionOrder) -> ListOrder {
    match order {
        InsertionOrder::Depth => ListOrder::Depth,
        InsertionOrder::Submission => ListOrder::Submission,
    }
}

/// Mirrors `AvsmUniforms` in `shaders/common/avsm_uniforms.wgsl` (included by the compute pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct AvsmUniforms {
    /// Texels per side of the map.
    pub resolution: u32,
    /// Nodes per texel `N`.
    pub nodes: u32,
    /// Batches each texel takes per dispatch of the compression pass.
    pub steps: u32,
    /// Fragments per batch of the walk along a list (`abuffer::WalkSplit`).
    pub batch: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
    pub pad3: u32,
}

impl LightMethod for Avsm {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "AvsmUniforms",
            AvsmUniforms {
                resolution,
                nodes,
                steps,
                batch,
                pad0,
                pad1,
                pad2,
                pad3
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        Ok(Box::new(AvsmGpu::create(ctx)?))
    }
}

impl ShadowMethod for Avsm {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(avsm_params(values))
    }
    /// 4, 8, 12 and 16 nodes, depth order.
    fn sweep(&self) -> Vec<SweepPoint> {
        [4.0, 8.0, 12.0, 16.0]
            .map(|n| SweepPoint::fixed(&[(NODES.key, n)]))
            .to_vec()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        [4.0, 8.0, 16.0]
            .map(|n| ParamValues::from([(NODES.key.to_string(), n)]))
            .to_vec()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
}

/// The node buffer, the walk state and the bind groups that name them.
struct NodeMap {
    buffer: wgpu::Buffer,
    walk: wgpu::Buffer,
    resolution: u32,
    nodes: u32,
    compute_bind_group: wgpu::BindGroup,
    lookup_bind_group: wgpu::BindGroup,
}

/// AVSM's GPU state: its A-buffer, the compression pipeline, the node buffer.
pub struct AvsmGpu {
    abuffer: ABuffer,
    compute_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    pipeline: ListPipeline,
    uniforms: wgpu::Buffer,
    map: NodeMap,
    /// Dispatches of the compression pass this frame.
    dispatches: u32,
}

impl AvsmGpu {
    fn create(ctx: &MethodContext) -> Result<AvsmGpu, GpuError> {
        let device = &ctx.gpu.device;
        let order = list_order(avsm_params(ctx.values).order);
        let abuffer = ABuffer::new(ctx.gpu, ctx.frame_layout, ctx.light)
            .named("avsm: A-buffer", "AVSM A-buffer")
            .sorted(ctx.gpu, order);
        // Binding numbers are those of shaders/avsm.wgsl and shaders/methods/avsm.wgsl: 0 nodes, 1 uniforms, 2
        // the walk state (compression only).
        let cs = wgpu::ShaderStages::COMPUTE;
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.avsm.compute_layout"),
            entries: &[
                storage_entry(0, cs, false),
                uniform_entry(1, cs),
                storage_entry(2, cs, false),
            ],
        });
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.avsm.lookup_layout"),
            entries: &[
                storage_entry(0, LOOKUP_STAGES, true),
                uniform_entry(1, LOOKUP_STAGES),
            ],
        });
        let module = passes::shader_module(device, "hairlab.avsm.shader", "avsm.wgsl", None);
        // Group 0: the node buffer and the uniforms; group 1: the A-buffer's lists (heads, node pages).
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.avsm.compute_pipeline_layout"),
            bind_group_layouts: &[Some(&compute_layout), Some(&abuffer.lookup_layout)],
            immediate_size: 0,
        });
        let pipeline = ListPipeline::new(
            "hairlab.avsm.compress_pipeline",
            &pipeline_layout,
            &module,
            "cs_compress",
        );
        let uniforms = uniform_buffer::<AvsmUniforms>(device, "avsm.uniforms");
        let p = avsm_params(ctx.values);
        let map = Self::make_map(
            ctx.gpu,
            &compute_layout,
            &lookup_layout,
            &uniforms,
            ctx.map_resolution(),
            p.nodes as u32,
        )?;
        Ok(AvsmGpu {
            abuffer,
            compute_layout,
            lookup_layout,
            pipeline,
            uniforms,
            map,
            dispatches: 1,
        })
    }

    fn make_map(
        gpu: &Gpu,
        compute_layout: &wgpu::BindGroupLayout,
        lookup_layout: &wgpu::BindGroupLayout,
        uniforms: &wgpu::Buffer,
        resolution: u32,
        nodes: u32,
    ) -> Result<NodeMap, GpuError> {
        let device = &gpu.device;
        let bytes = resolution as u64 * resolution as u64 * nodes as u64 * NODE_BYTES;
        let limit = device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the AVSM node buffer hairlab.avsm.nodes ({nodes} nodes of {NODE_BYTES} B at {resolution}² \
                     texels; lower the map resolution or the node count)"
                ),
                bytes,
                limit,
            });
        }
        let walk_bytes = resolution as u64 * resolution as u64 * WALK_BYTES;
        if walk_bytes > limit {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the AVSM walk state hairlab.avsm.walk ({WALK_BYTES} B at {resolution}² texels; lower the map \
                     resolution)"
                ),
                bytes: walk_bytes,
                limit,
            });
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.avsm.nodes"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let walk = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.avsm.walk"),
            size: walk_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let compute_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.avsm.compute_bind_group"),
            layout: compute_layout,
            entries: &[entry(0, &buffer), entry(1, uniforms), entry(2, &walk)],
        });
        let lookup_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.avsm.lookup_bind_group"),
            layout: lookup_layout,
            entries: &[entry(0, &buffer), entry(1, uniforms)],
        });
        Ok(NodeMap {
            buffer,
            walk,
            resolution,
            nodes,
            compute_bind_group,
            lookup_bind_group,
        })
    }
}

impl MethodGpu for AvsmGpu {
    fn prepare(&mut self, ctx: &MethodContext, timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let resolution = ctx.map_resolution();
        let p = avsm_params(ctx.values);
        let nodes = p.nodes as u32;
        if self.map.resolution != resolution || self.map.nodes != nodes {
            self.map = Self::make_map(
                ctx.gpu,
                &self.compute_layout,
                &self.lookup_layout,
                &self.uniforms,
                resolution,
                nodes,
            )?;
        }
        self.abuffer.set_sort_order(list_order(p.order));
        self.abuffer
            .prepare(ctx.gpu, ctx.frame_bind_group, ctx.casters, resolution, timer)?;
        self.pipeline.prepare(&ctx.gpu.device, self.abuffer.pages_used());
        let split = self.abuffer.walk_split(ctx.gpu, "AVSM", INSERT_ITERATIONS)?;
        self.dispatches = split.dispatches;
        ctx.gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&AvsmUniforms {
                resolution,
                nodes,
                steps: split.steps,
                batch: split.batch,
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
        self.abuffer
            .record(ctx.frame_bind_group, ctx.casters, encoder, timer);
        encoder.clear_buffer(&self.map.walk, 0, None);
        let timestamps = timer
            .as_mut()
            .and_then(|t| t.compute_pass(encoder, crate::gpu::timing::Phase::Method, "avsm: compress"));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.avsm.compress"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(self.pipeline.for_pages(self.abuffer.pages_used()));
        pass.set_bind_group(0, &self.map.compute_bind_group, &[]);
        pass.set_bind_group(1, &self.abuffer.lookup_bind_group, &[]);
        let groups = self.map.resolution.div_ceil(8);
        // Each dispatch resumes the walks where the one before stopped.
        for _ in 0..self.dispatches {
            pass.dispatch_workgroups(groups, groups, 1);
        }
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.map.lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.map.buffer.size()
    }
    /// The A-buffer the compression pass reads and the walk state.
    fn build_bytes(&self) -> u64 {
        self.abuffer.memory_bytes() + self.map.walk.size()
    }
    fn geometry_passes(&self) -> u32 {
        2
    }
}
