//! Sorts an A-buffer's lists in place into the CPU models' order (`shaders/list_sort.wgsl`), for the
//! compressors that walk them (AVSM, compressed deep shadow maps): a bottom-up merge sort of each texel's linked
//! list, one invocation per texel, relinking its nodes. Pass 0 sorts each run of [`CHUNK`] consecutive nodes by
//! insertion; pass `k ≥ 1` merges neighbouring runs of `CHUNK · 2^(k−1)` (Tatham's merge sort of a linked list),
//! so a list of `n` fragments costs `n (1 + ⌈log2(n / CHUNK)⌉)` node reads and the walk after it `n`, where a walk
//! that found the order itself (the batched walk this replaced) read about `n² / 32`: the compressors' cost grows
//! as `n log n` per texel, not `n²`.
//!
//! The passes of a frame's longest list run in one dispatch, except on a CPU adapter, whose llvmpipe stops a
//! shader's loops after 65,535 iterations in all: there [`SortSplit`] spreads them over dispatches within
//! `list_pages::CPU_ADAPTER_LOOP_BUDGET`, each dispatch's passes a [`SortPart`] at its own dynamic offset.

use super::list_pages::{CPU_ADAPTER_LOOP_BUDGET, ListPipeline};
use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError};
use crate::render::method::UniformMirror;
use bytemuck::{Pod, Zeroable};
use std::ops::Range;

/// Nodes pass 0 sorts by insertion (`SORT_CHUNK` in `shaders/list_sort.wgsl`).
pub const CHUNK: u64 = 16;
/// Loop iterations per fragment of pass 0: reading it, at most `CHUNK − 1` moves of the others in its chunk
/// (`(CHUNK − 1) / 2` a fragment, rounded up), relinking it, and the chunk loop.
const CHUNK_PASS_ITERATIONS: u64 = 2 + CHUNK.div_ceil(2) + 1;
/// Loop iterations per fragment of a merge pass: the step over the first run of a pair, the merge, the pair loop.
const MERGE_PASS_ITERATIONS: u64 = 3;
/// Dispatches one frame's sort may take (slots of the parts buffer): more than the passes of any list a u32
/// counter can count (1 + 28).
const MAX_DISPATCHES: u64 = 32;

/// The order a list is sorted into (`list_precedes` in `shaders/common/list_key.wgsl`), the node index breaking
/// ties between identical fragments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListOrder {
    /// (depth, segment, alpha): the depth peel's order.
    Depth = 0,
    /// (segment, depth, alpha): the order the strands were submitted in.
    Submission = 1,
}

/// Mirrors `SortPart` in `shaders/list_sort.wgsl`: one dispatch's passes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq, Eq)]
pub struct SortPart {
    /// Texels per side of the lists.
    pub resolution: u32,
    /// [`ListOrder`] as a number.
    pub order: u32,
    /// Passes `first..end`.
    pub first: u32,
    pub end: u32,
}

/// The WGSL mirror of [`SortPart`], for the layout test.
pub fn sort_part_mirror() -> UniformMirror {
    crate::uniform_mirror!(
        "SortPart",
        SortPart {
            resolution,
            order,
            first,
            end
        }
    )
}

/// Passes that sort a list of `longest` fragments: pass 0, then merges until one run covers it.
pub fn passes(longest: u64) -> u32 {
    let runs = longest.div_ceil(CHUNK).max(1);
    1 + runs.next_power_of_two().trailing_zeros()
}

/// The passes of a frame over dispatches.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SortSplit {
    /// Each dispatch's passes, in order.
    pub dispatches: Vec<Range<u32>>,
}

impl SortSplit {
    /// The split for lists of at most `longest` fragments: every pass in one dispatch without a budget (loop
    /// iterations per invocation and dispatch); with one, as many consecutive passes per dispatch as fit; `None`
    /// when one pass alone does not.
    pub fn new(longest: u64, budget: Option<u64>) -> Option<SortSplit> {
        let total = passes(longest);
        let Some(budget) = budget else {
            return Some(SortSplit {
                dispatches: std::iter::once(0..total).collect(),
            });
        };
        let cost = |pass: u32| {
            let per_fragment = if pass == 0 {
                CHUNK_PASS_ITERATIONS
            } else {
                MERGE_PASS_ITERATIONS
            };
            longest * per_fragment + 1
        };
        let mut dispatches = Vec::new();
        let mut first = 0;
        while first < total {
            let mut end = first;
            let mut used = 0;
            while end < total && used + cost(end) <= budget {
                used += cost(end);
                end += 1;
            }
            if end == first {
                return None;
            }
            dispatches.push(first..end);
            first = end;
        }
        Some(SortSplit { dispatches })
    }
}

/// The sort of one A-buffer's lists: its pipeline, and each dispatch's [`SortPart`] at a dynamic offset.
pub struct ListSort {
    pipeline: ListPipeline,
    parts: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Bytes between the parts (the device's uniform offset alignment).
    stride: u64,
    order: ListOrder,
    /// This frame's dispatches (set by [`ListSort::prepare`]).
    dispatches: u32,
    resolution: u32,
}

impl ListSort {
    /// The sort of the lists bound through `lists_layout` (the A-buffer's read-write layout: counters, heads,
    /// pages) into `order`.
    pub fn new(gpu: &Gpu, lists_layout: &wgpu::BindGroupLayout, order: ListOrder) -> ListSort {
        let device = &gpu.device;
        let size = std::mem::size_of::<SortPart>() as u64;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.list_sort.part_layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(size),
                },
                count: None,
            }],
        });
        let stride = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(size);
        let parts = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.list_sort.parts"),
            size: stride * MAX_DISPATCHES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.list_sort.part_bind_group"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &parts,
                    offset: 0,
                    size: wgpu::BufferSize::new(size),
                }),
            }],
        });
        let module = super::shader_module(device, "hairlab.list_sort.shader", "list_sort.wgsl", None);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.list_sort.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(lists_layout)],
            immediate_size: 0,
        });
        let pipeline = ListPipeline::new("hairlab.list_sort.pipeline", &pipeline_layout, &module, "cs_sort");
        ListSort {
            pipeline,
            parts,
            bind_group,
            stride,
            order,
            dispatches: 0,
            resolution: 0,
        }
    }

    pub fn set_order(&mut self, order: ListOrder) {
        self.order = order;
    }

    /// Splits this frame's passes for lists of at most `longest` fragments at `resolution`² texels over
    /// dispatches ([`SortSplit`]; the budget on a CPU adapter), writes their parts and makes the pipeline for
    /// nodes in `pages` pages; the error names the lists (`what`) when one pass does not fit.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        resolution: u32,
        longest: u64,
        pages: usize,
        what: &str,
    ) -> Result<(), GpuError> {
        let budget = (gpu.info.device_type == wgpu::DeviceType::Cpu).then_some(CPU_ADAPTER_LOOP_BUDGET);
        let split = SortSplit::new(longest, budget).ok_or_else(|| {
            GpuError::Setting(format!(
                "{what} on a CPU adapter sorts at most {} fragments per texel (llvmpipe stops shader loops after \
                 65,535 iterations) and a texel holds {longest}: raise render.map_resolution or lower \
                 scene.generator.strands",
                (CPU_ADAPTER_LOOP_BUDGET - 1) / CHUNK_PASS_ITERATIONS
            ))
        })?;
        let mut bytes = vec![0u8; (self.stride * split.dispatches.len() as u64) as usize];
        for (d, passes) in split.dispatches.iter().enumerate() {
            let part = SortPart {
                resolution,
                order: self.order as u32,
                first: passes.start,
                end: passes.end,
            };
            let at = d * self.stride as usize;
            bytes[at..at + std::mem::size_of::<SortPart>()].copy_from_slice(bytemuck::bytes_of(&part));
        }
        gpu.queue.write_buffer(&self.parts, 0, &bytes);
        self.pipeline.prepare(&gpu.device, pages);
        self.dispatches = split.dispatches.len() as u32;
        self.resolution = resolution;
        Ok(())
    }

    /// Records the sort of the lists in `pages` node pages, bound read-write by `bind_group` (after their fill),
    /// timed as `label`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pages: usize,
        bind_group: &wgpu::BindGroup,
        label: String,
        timer: &mut Option<GpuTimer>,
    ) {
        let timestamps = timer
            .as_mut()
            .and_then(|t| t.compute_pass(encoder, Phase::Method, label));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hairlab.list_sort.pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(self.pipeline.for_pages(pages));
        pass.set_bind_group(1, bind_group, &[]);
        let groups = self.resolution.div_ceil(8);
        for d in 0..self.dispatches {
            pass.set_bind_group(0, &self.bind_group, &[d * self.stride as u32]);
            pass.dispatch_workgroups(groups, groups, 1);
        }
    }

    /// The parts buffer.
    pub fn memory_bytes(&self) -> u64 {
        self.parts.size()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_merge_until_one_run_covers_the_longest_list() {
        // Up to 16 fragments: pass 0 alone; 17..=32: one merge of two runs of 16; 1300: 82 runs of 16, 7 merges.
        assert_eq!(passes(0), 1);
        assert_eq!(passes(16), 1);
        assert_eq!(passes(17), 2);
        assert_eq!(passes(32), 2);
        assert_eq!(passes(33), 3);
        assert_eq!(passes(1300), 8);
    }

    #[test]
    fn sorts_split_to_fit_the_budget() {
        let one = |passes: std::ops::Range<u32>| {
            Some(SortSplit {
                dispatches: std::iter::once(passes).collect(),
            })
        };
        // No budget: one dispatch of every pass.
        assert_eq!(SortSplit::new(1300, None), one(0..8));
        // 1300 fragments: pass 0 costs 1300 × 11 + 1 = 14,301, a merge 3901; 14,301 + 7 × 3901 = 41,608 fits.
        assert_eq!(SortSplit::new(1300, Some(60_000)), one(0..8));
        // 5000 (313 runs, 9 merges): pass 0 55,001, then merges of 15,001, three a dispatch.
        assert_eq!(
            SortSplit::new(5000, Some(60_000)).unwrap().dispatches,
            vec![0..1, 1..4, 4..7, 7..10]
        );
        // 5455 × 11 + 1 = 60,006: pass 0 alone is beyond the budget.
        assert_eq!(SortSplit::new(5454, Some(60_000)).unwrap().dispatches[0], 0..1);
        assert_eq!(SortSplit::new(5455, Some(60_000)), None);
    }
}
