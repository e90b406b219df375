//! Sorts an A-buffer's per-texel lists in place, on the GPU, so that the compressors that build maps from them
//! (AVSM, compressed deep shadow maps) walk each list once, front to back: `shaders/list_sort.wgsl`, one
//! invocation per texel, the bottom-up merge sort of a linked list (as in S. Tatham's "Mergesort for linked
//! lists"): it relinks the nodes' `next` and the texel's head, needs no memory besides a 40-byte state per texel,
//! and takes O(n log n) steps for an n-fragment list (the select-next walk it replaces took O(n²)). The order is
//! [`crate::visibility::avsm::insertion_cmp`]'s, (depth, segment, alpha) or (segment, depth, alpha), on the GPU's
//! `<`: a total order up to identical fragments, so the GPU walks what the CPU models sort.
//!
//! One dispatch sorts every list, except on a CPU adapter, where llvmpipe stops a shader's loops after 65,535
//! iterations in all: there each dispatch takes [`abuffer::CPU_ADAPTER_LOOP_BUDGET`] iterations per texel and
//! keeps where each texel's sort stands, and as many dispatches follow as the frame's longest list needs
//! ([`sort_split`]).

use super::abuffer::{self, ABuffer, WalkSplit};
use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError};
use crate::render::maps::{storage_entry, uniform_buffer, uniform_entry};
use crate::visibility::avsm::InsertionOrder;
use bytemuck::{Pod, Zeroable};

/// Bytes of one texel's sort state (`ListSortState` in `shaders/list_sort.wgsl`).
pub const STATE_BYTES: u64 = 40;

/// Mirrors `ListSortUniforms` in `shaders/list_sort.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ListSortUniforms {
    /// Texels per side of the map.
    pub resolution: u32,
    /// 0: (depth, segment, alpha), 1: (segment, depth, alpha).
    pub order: u32,
    /// Loop iterations per texel and dispatch.
    pub steps: u32,
    pub pad: u32,
}

/// Loop iterations of `cs_sort` for an `n`-fragment list: ⌈log₂ n⌉ passes (one at least), each at most `3n + 1`
/// (a step per node of each first run to find the second, one per node merged, one to start each of at most `n`
/// merges, one to end the pass), and one of margin.
pub fn sort_iterations(n: u64) -> u64 {
    let passes = u64::from(n.max(2).next_power_of_two().trailing_zeros());
    passes * (3 * n + 1) + 1
}

/// How the sort of lists of at most `longest` fragments is split over dispatches: every iteration in one
/// dispatch, unless `budget` (iterations per invocation and dispatch) asks for more.
pub fn sort_split(longest: u64, budget: Option<u64>) -> WalkSplit {
    let all = sort_iterations(longest);
    let steps = budget.map_or(all, |b| b.min(all));
    WalkSplit {
        steps: u32::try_from(steps).unwrap_or(u32::MAX),
        dispatches: all.div_ceil(steps) as u32,
    }
}

/// The sort pass of one A-buffer: its pipeline, uniforms and per-texel state.
pub struct ListSort {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    state: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    resolution: u32,
    dispatches: u32,
    /// The pass's name in GPU timings.
    label: &'static str,
}

impl ListSort {
    /// The sort of `abuffer`'s lists, timed as `label`.
    pub fn new(gpu: &Gpu, abuffer: &ABuffer, label: &'static str) -> ListSort {
        let device = &gpu.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        // Binding numbers are those of shaders/list_sort.wgsl: 0 uniforms, 1 the state.
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.list_sort.layout"),
            entries: &[uniform_entry(0, cs), storage_entry(1, cs, false)],
        });
        let module = super::shader_module(device, "hairlab.list_sort.shader", "list_sort.wgsl", None);
        // Group 1: the lists as the fill pass binds them (counters, heads, pages; read-write).
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.list_sort.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(abuffer.pass_layout())],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("hairlab.list_sort.pipeline"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("cs_sort"),
            compilation_options: Default::default(),
            cache: None,
        });
        let uniforms = uniform_buffer::<ListSortUniforms>(device, "list_sort.uniforms");
        let state = Self::state_buffer(gpu, STATE_BYTES);
        let bind_group = Self::bind_group(gpu, &layout, &uniforms, &state);
        ListSort {
            pipeline,
            layout,
            uniforms,
            state,
            bind_group,
            resolution: 1,
            dispatches: 1,
            label,
        }
    }

    fn state_buffer(gpu: &Gpu, size: u64) -> wgpu::Buffer {
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.list_sort.state"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn bind_group(
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        uniforms: &wgpu::Buffer,
        state: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.list_sort.bind_group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: state.as_entire_binding(),
                },
            ],
        })
    }

    /// Sizes the state for `abuffer`'s resolution and splits the sort for its longest list (after
    /// [`ABuffer::prepare`] for this frame); `what` names the owner in errors.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        abuffer: &ABuffer,
        order: InsertionOrder,
        what: &str,
    ) -> Result<(), GpuError> {
        let resolution = abuffer.resolution();
        if resolution != self.resolution {
            let bytes = resolution as u64 * resolution as u64 * STATE_BYTES;
            let limit = gpu.device.limits().max_storage_buffer_binding_size;
            if bytes > limit {
                return Err(GpuError::TooLarge {
                    what: format!(
                        "{what}'s list sort state hairlab.list_sort.state ({STATE_BYTES} B at {resolution}² \
                         texels; lower the map resolution)"
                    ),
                    bytes,
                    limit,
                });
            }
            self.resolution = resolution;
            self.state = Self::state_buffer(gpu, bytes);
            self.bind_group = Self::bind_group(gpu, &self.layout, &self.uniforms, &self.state);
        }
        let split = sort_split(abuffer.longest_list, abuffer::loop_budget(gpu));
        self.dispatches = split.dispatches;
        gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&ListSortUniforms {
                resolution,
                order: (order == InsertionOrder::Submission) as u32,
                steps: split.steps,
                pad: 0,
            }),
        );
        Ok(())
    }

    /// Records the sort of the lists `abuffer` filled (after its fill pass in `encoder`).
    pub fn record(
        &self,
        abuffer: &ABuffer,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        self.record_as(self.label, abuffer, encoder, timer);
    }

    /// [`ListSort::record`] timed as `label` (a second sort in one frame needs a name of its own).
    pub fn record_as(
        &self,
        label: &str,
        abuffer: &ABuffer,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        encoder.clear_buffer(&self.state, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.list_sort"),
            timestamp_writes: timer.as_mut().and_then(|t| t.compute_pass(Phase::Method, label)),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, abuffer.pass_bind_group(), &[]);
        let groups = self.resolution.div_ceil(8);
        // Each dispatch resumes the sorts where the one before stopped.
        for _ in 0..self.dispatches {
            pass.dispatch_workgroups(groups, groups, 1);
        }
    }

    /// The per-texel state.
    pub fn memory_bytes(&self) -> u64 {
        self.state.size()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sort_iterations_bound_the_passes() {
        // Empty and one-node lists: one pass that ends at once, then the check.
        assert_eq!(sort_iterations(0), 2);
        assert_eq!(sort_iterations(1), 5);
        // 700 fragments: 10 passes of at most 2101 iterations.
        assert_eq!(sort_iterations(700), 10 * 2101 + 1);
        assert_eq!(sort_iterations(1024), 10 * 3073 + 1);
        assert_eq!(sort_iterations(1025), 11 * 3076 + 1);
    }

    #[test]
    fn sorts_split_to_fit_the_budget() {
        assert_eq!(
            sort_split(30_000, None),
            WalkSplit {
                steps: 1_350_016,
                dispatches: 1
            }
        );
        // 15 passes of 90,001: 23 dispatches of 60,000.
        assert_eq!(
            sort_split(30_000, Some(60_000)),
            WalkSplit {
                steps: 60_000,
                dispatches: 23
            }
        );
        assert_eq!(
            sort_split(100, Some(60_000)),
            WalkSplit {
                steps: 2108,
                dispatches: 1
            }
        );
    }
}
