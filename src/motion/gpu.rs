//! The strand simulation as a GPU compute pass (`shaders/motion/simulate.wgsl`), one thread per strand, equal
//! to the CPU model ([`super::sim`]) up to floating-point rounding: the substep's time-dependent values (root
//! frame, sweep, wind per strand phase class, damping factor) are computed on the CPU by the same functions
//! the CPU model calls; the per-point arithmetic runs on the GPU in the CPU model's order. The test
//! `motion_gpu` states the tolerance and the measured difference. The collider (`shaders/motion/collide.wgsl`,
//! group 1 of both passes) is the head ellipsoid or a mesh's signed distance grid uploaded as a storage buffer. A frame's substeps are timed as one entry of
//! the phase [`Phase::Simulation`] (from the first substep's beginning to the last one's end).

use super::pose::Collider;
use super::sim::{Simulation, WIND_CLASSES};
use crate::gpu::timing::{GpuTimer, PassTime, Phase};
use crate::gpu::{Gpu, GpuError, readback::copy_out};
use crate::render::pipelines::{self, ComputePass};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// One substep's values as `shaders/motion/simulate.wgsl` reads them (`Params`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Params {
    head_rot: [f32; 4],
    pivot: [f32; 4],
    sweep: [f32; 4],
    /// Gravity, the local stiffness as applied (`0.5 · min(k, 0.95)`), the global stiffness and its range.
    stiffness: [f32; 4],
    /// x: the follow-the-leader damping.
    damping: [f32; 4],
    counts: [u32; 4],
    wind: [[f32; 4]; WIND_CLASSES],
}

/// The root frame's pose for the guide-and-follow pass (`shaders/motion/follow.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct FollowParams {
    head_rot: [f32; 4],
    pivot: [f32; 4],
    translation: [f32; 4],
    counts: [u32; 4],
}

/// [`Params`]' field names and byte offsets, for the layout test against the WGSL struct.
pub const PARAMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("head_rot", offset_of!(Params, head_rot)),
        ("pivot", offset_of!(Params, pivot)),
        ("sweep", offset_of!(Params, sweep)),
        ("stiffness", offset_of!(Params, stiffness)),
        ("damping", offset_of!(Params, damping)),
        ("counts", offset_of!(Params, counts)),
        ("wind", offset_of!(Params, wind)),
    ]
};

/// [`FollowParams`]' field names and byte offsets, for the layout test against the WGSL struct.
pub const FOLLOW_PARAMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("head_rot", offset_of!(FollowParams, head_rot)),
        ("pivot", offset_of!(FollowParams, pivot)),
        ("translation", offset_of!(FollowParams, translation)),
        ("counts", offset_of!(FollowParams, counts)),
    ]
};

/// The collider as `shaders/motion/collide.wgsl` reads it (`ColliderParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ColliderParams {
    /// x: 0 none, 1 ellipsoid, 2 distance grid; yzw: the grid's nodes per axis.
    pub kind: [u32; 4],
    /// Ellipsoid: centre; grid: origin (xyz) and cell (w).
    pub center: [f32; 4],
    /// Ellipsoid: radii; grid: x the margin.
    pub radii: [f32; 4],
}

/// [`ColliderParams`]' field names and byte offsets, for the layout test against the WGSL struct.
pub const COLLIDER_PARAMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("kind", offset_of!(ColliderParams, kind)),
        ("center", offset_of!(ColliderParams, center)),
        ("radii", offset_of!(ColliderParams, radii)),
    ]
};

impl ColliderParams {
    /// The uniforms and the grid's values (one zero when there is no grid) for `collider`.
    pub fn of(collider: Option<&Collider>) -> (ColliderParams, Vec<f32>) {
        match collider {
            None => (ColliderParams::default(), vec![0.0]),
            Some(Collider::Ellipsoid(e)) => (
                ColliderParams {
                    kind: [1, 0, 0, 0],
                    center: e.center.extend(0.0).to_array(),
                    radii: e.radii.extend(0.0).to_array(),
                },
                vec![0.0],
            ),
            Some(Collider::Sdf(g)) => (
                ColliderParams {
                    kind: [2, g.dims[0], g.dims[1], g.dims[2]],
                    center: g.origin.extend(g.cell).to_array(),
                    radii: [g.margin, 0.0, 0.0, 0.0],
                },
                g.values.clone(),
            ),
        }
    }
}

/// The guide-and-follow pass: after a frame's substeps, the followers rebuilt from their guides.
struct FollowPass {
    uniforms: wgpu::Buffer,
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    followers: u32,
}

/// The collider's bind group (group 1 of both passes) and its layout.
struct ColliderGroup {
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

fn collider_group(gpu: &Gpu, collider: Option<&Collider>) -> Result<ColliderGroup, GpuError> {
    let device = &gpu.device;
    let (params, values) = ColliderParams::of(collider);
    gpu.check_buffer_size("collider distance grid", (values.len() * 4) as u64)?;
    let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hairlab.motion.collider"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let grid = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hairlab.motion.collider.grid"),
        contents: bytemuck::cast_slice(&values),
        usage: wgpu::BufferUsages::STORAGE,
    });
    use crate::render::eye::bindings::{self, Binding::*};
    let layout = bindings::layout_for(
        device,
        "hairlab.motion.collider.layout",
        wgpu::ShaderStages::COMPUTE,
        &[Uniform, StorageRo],
    );
    let group = pipelines::buffer_group(
        device,
        "hairlab.motion.collider.group",
        &layout,
        &[&uniforms, &grid],
    );
    Ok(ColliderGroup { layout, group })
}

/// The simulation's state on the GPU, stepped frame by frame from frame 0.
pub struct GpuSimulation {
    sim: Simulation,
    uniforms: wgpu::Buffer,
    x: wgpu::Buffer,
    prev: wgpu::Buffer,
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    strands: u32,
    points: usize,
    frame: u32,
    timer: Option<GpuTimer>,
    follow: Option<FollowPass>,
    collider: ColliderGroup,
}

impl GpuSimulation {
    /// Uploads `sim`'s rest pose (its frame 0); `sim` gives the parameters and the per-substep values.
    pub fn new(gpu: &Gpu, sim: Simulation) -> Result<GpuSimulation, GpuError> {
        let device = &gpu.device;
        let topo = sim.topology();
        let (rest, ranges, rest_len) = (topo.rest, topo.ranges, topo.rest_len);
        let flat: Vec<f32> = rest.iter().flat_map(|p| p.to_array()).collect();
        let bytes = (flat.len() * 4).max(16) as u64;
        gpu.check_buffer_size("simulation points", bytes)?;
        // A follower is not stepped (its count reads 0); the follow pass rebuilds it.
        let simulated = |s: usize| sim.follow().is_none_or(|f| f.simulated[s]);
        let strands: Vec<u32> = ranges
            .iter()
            .enumerate()
            .flat_map(|(s, &(f, n))| [f as u32, if simulated(s) { n as u32 } else { 0 }])
            .collect();
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            let mut padded = contents.to_vec();
            padded.resize(padded.len().max(16), 0);
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &padded,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let rw = storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.motion.params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let rest_b = init("hairlab.motion.rest", bytemuck::cast_slice(&flat), storage);
        let len_b = init("hairlab.motion.rest_len", bytemuck::cast_slice(rest_len), storage);
        let strands_b = init("hairlab.motion.strands", bytemuck::cast_slice(&strands), storage);
        let x = init("hairlab.motion.x", bytemuck::cast_slice(&flat), rw);
        let prev = init("hairlab.motion.prev", bytemuck::cast_slice(&flat), rw);
        let q = init("hairlab.motion.q", bytemuck::cast_slice(&flat), rw);
        let corr = init("hairlab.motion.corr", bytemuck::cast_slice(&flat), rw);
        use crate::render::eye::bindings::{self, Binding::*};
        let layout = bindings::layout_for(
            device,
            "hairlab.motion.layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                Uniform, StorageRo, StorageRo, StorageRo, StorageRw, StorageRw, StorageRw, StorageRw,
            ],
        );
        let group = pipelines::buffer_group(
            device,
            "hairlab.motion.group",
            &layout,
            &[&uniforms, &rest_b, &len_b, &strands_b, &x, &prev, &q, &corr],
        );
        let collider = collider_group(gpu, sim.collider())?;
        let source = crate::shaders::compose("motion/simulate.wgsl", None)
            .map_err(|e| GpuError::Setting(e.to_string()))?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("hairlab.motion.shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = pipelines::compute(
            device,
            &ComputePass {
                label: "hairlab.motion.pipeline",
                module: &module,
                entry: "substep",
                layouts: &[&layout, &collider.layout],
            },
        );
        let follow = match sim.follow() {
            Some(f) => Some(follow_pass(gpu, f, ranges, &rest_b, &x, &collider.layout)?),
            None => None,
        };
        let (strand_count, points) = (ranges.len() as u32, rest.len());
        Ok(GpuSimulation {
            sim,
            uniforms,
            x,
            prev,
            pipeline,
            group,
            strands: strand_count,
            points,
            frame: 0,
            timer: GpuTimer::new(device, &gpu.queue),
            follow,
            collider,
        })
    }

    /// Replaces the GPU state with a CPU state (frame, positions, previous positions), e.g. to compare one
    /// frame's step from the same start.
    pub fn set_state(&mut self, gpu: &Gpu, state: &super::sim::SimState) {
        let flat = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
        gpu.queue
            .write_buffer(&self.x, 0, bytemuck::cast_slice(&flat(&state.x)));
        gpu.queue
            .write_buffer(&self.prev, 0, bytemuck::cast_slice(&flat(&state.prev)));
        self.frame = state.frame;
    }

    /// The frame the GPU state holds.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// The substep's values, computed as the CPU model computes them.
    fn params(&self, step: u64) -> Params {
        let p = self.sim.params();
        let pivot = self.sim.topology().pivot;
        let h = p.h();
        let t = step as f64 / (f64::from(p.fps) * f64::from(p.substeps));
        let decay = (-p.damping * h * 60.0).exp();
        let pose = p.head_pose(t, pivot);
        let mut wind = [[0.0; 4]; WIND_CLASSES];
        for (s, w) in wind.iter_mut().enumerate() {
            *w = p.wind_at(t, s).extend(0.0).to_array();
        }
        Params {
            head_rot: pose.rotation.to_array(),
            pivot: pivot.extend(h * h).to_array(),
            sweep: p.sweep_offset(t).extend(decay).to_array(),
            stiffness: [
                p.gravity,
                0.5 * p.local_stiffness.min(0.95),
                p.global_stiffness,
                p.global_range,
            ],
            damping: [p.ftl_damping, 0.0, 0.0, 0.0],
            counts: [self.strands, self.sim.first_swept_strand() as u32, 0, 0],
            wind,
        }
    }

    /// Advances one frame (`substeps` dispatches, one submission each), timed when the device has timestamps.
    pub fn step_frame(&mut self, gpu: &Gpu) {
        let substeps = u64::from(self.sim.params().substeps);
        let first = u64::from(self.frame) * substeps;
        let span = self
            .timer
            .as_mut()
            .and_then(|t| t.span(Phase::Simulation, "motion: simulate"));
        if let Some(f) = &self.follow {
            let pose = self.sim.head_pose_at_frame(self.frame + 1);
            let params = FollowParams {
                head_rot: pose.rotation.to_array(),
                pivot: pose.pivot.extend(0.0).to_array(),
                translation: pose.translation.extend(0.0).to_array(),
                counts: [f.followers, 0, 0, 0],
            };
            gpu.queue
                .write_buffer(&f.uniforms, 0, bytemuck::bytes_of(&params));
        }
        for j in 0..substeps {
            gpu.queue
                .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&self.params(first + j + 1)));
            let mut encoder = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("hairlab.motion.encoder"),
                });
            let last = j + 1 == substeps;
            {
                let ends = last && self.follow.is_none();
                let timestamps = span.as_ref().and_then(|s| s.compute(&mut encoder, j == 0, ends));
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("hairlab.motion.substep"),
                    timestamp_writes: timestamps,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.group, &[]);
                pass.set_bind_group(1, &self.collider.group, &[]);
                pass.dispatch_workgroups(self.strands.div_ceil(64), 1, 1);
            }
            if let (true, Some(f)) = (last, &self.follow) {
                let timestamps = span.as_ref().and_then(|s| s.compute(&mut encoder, false, true));
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("hairlab.motion.follow"),
                    timestamp_writes: timestamps,
                });
                pass.set_pipeline(&f.pipeline);
                pass.set_bind_group(0, &f.group, &[]);
                pass.set_bind_group(1, &self.collider.group, &[]);
                pass.dispatch_workgroups(f.followers.div_ceil(64), 1, 1);
            }
            let resolved =
                last && span.is_some() && self.timer.as_mut().is_some_and(|t| t.resolve(&mut encoder));
            gpu.queue.submit([encoder.finish()]);
            if resolved && let Some(t) = self.timer.as_mut() {
                t.after_submit();
            }
        }
        self.frame += 1;
    }

    /// Blocks until the last stepped frame's timing is read back: its [`Phase::Simulation`] entry (`None` when
    /// the device has no timestamp queries).
    pub fn wait_timings(&mut self, gpu: &Gpu) -> Option<Vec<PassTime>> {
        self.timer.as_mut().map(|t| t.wait(&gpu.device).to_vec())
    }

    /// Reads the current points back.
    pub fn read_points(&self, gpu: &Gpu) -> Result<Vec<Vec3>, GpuError> {
        let raw = copy_out(gpu, &self.x)?;
        let floats: &[f32] = bytemuck::cast_slice(&raw);
        Ok(floats
            .chunks_exact(3)
            .take(self.points)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect())
    }
}

/// The follow pass for `follow`'s followers over the strands `ranges`, reading the rest points `rest` and writing
/// the points `x`, colliding through a group of `collider_layout`.
fn follow_pass(
    gpu: &Gpu,
    follow: &super::follow::Follow,
    ranges: &[(usize, usize)],
    rest: &wgpu::Buffer,
    x: &wgpu::Buffer,
    collider_layout: &wgpu::BindGroupLayout,
) -> Result<FollowPass, GpuError> {
    let device = &gpu.device;
    let mut table: Vec<u32> = Vec::with_capacity(follow.followers.len() * 8);
    let mut weights: Vec<f32> = Vec::with_capacity(follow.followers.len() * 4);
    for (f, guides) in &follow.followers {
        let (first, n) = ranges[*f];
        table.extend([first as u32, n as u32]);
        for g in 0..super::follow::NEIGHBOURS {
            let (range, w) = guides.get(g).map_or(((0, 0), 0.0), |&(s, w)| (ranges[s], w));
            table.extend([range.0 as u32, range.1 as u32]);
            weights.push(w);
        }
        weights.push(0.0);
    }
    let bytes = |v: &[u8]| {
        let mut padded = v.to_vec();
        padded.resize(padded.len().max(16), 0);
        padded
    };
    gpu.check_buffer_size("follower table", (table.len() * 4) as u64)?;
    let init = |label: &str, contents: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &bytes(contents),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let table_b = init("hairlab.motion.follow.table", bytemuck::cast_slice(&table));
    let weights_b = init("hairlab.motion.follow.weights", bytemuck::cast_slice(&weights));
    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hairlab.motion.follow.params"),
        size: std::mem::size_of::<FollowParams>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    use crate::render::eye::bindings::{self, Binding::*};
    let layout = bindings::layout_for(
        device,
        "hairlab.motion.follow.layout",
        wgpu::ShaderStages::COMPUTE,
        &[Uniform, StorageRo, StorageRo, StorageRo, StorageRw],
    );
    let group = pipelines::buffer_group(
        device,
        "hairlab.motion.follow.group",
        &layout,
        &[&uniforms, rest, &table_b, &weights_b, x],
    );
    let source =
        crate::shaders::compose("motion/follow.wgsl", None).map_err(|e| GpuError::Setting(e.to_string()))?;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("hairlab.motion.follow.shader"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = pipelines::compute(
        device,
        &ComputePass {
            label: "hairlab.motion.follow.pipeline",
            module: &module,
            entry: "follow",
            layouts: &[&layout, collider_layout],
        },
    );
    Ok(FollowPass {
        uniforms,
        pipeline,
        group,
        followers: follow.followers.len() as u32,
    })
}
