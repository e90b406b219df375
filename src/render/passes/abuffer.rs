//! Reference A-buffer pass: a counting pass sizes the node buffer from the scene, then one geometry pass links
//! every light-space fragment into its texel's list (storage-buffer atomics in the fragment shader). The lists,
//! read back and sorted, are the exact per-texel fragment lists of the reference; the eye passes can also walk
//! them to shade with exact visibility.
//!
//! The nodes live in up to [`NODE_PAGES`] pages, each one storage binding of at most the device's binding size:
//! node `i` is node `i mod P` of page `i div P`, `P` the first page's length (`shaders/common/list_pages.wgsl`
//! reads them, `abuffer.wgsl` writes them). Pages rather than bands of texel rows because every reader walks
//! any texel's list at any time (the reference's lookup in the eye passes and in `evaluate`, the compressors in
//! one dispatch), so all lists stay resident and the single fill pass, the heads and the walks are unchanged;
//! one page (the whole buffer in one binding) whenever the frame's fragments fit it.

use crate::gpu::readback::copy_out;
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError, readback};
use crate::render::caster::{LightCaster, LightStage, draw_casters};
use crate::render::maps::storage_entry;
use crate::render::passes::list_pages::CPU_ADAPTER_LOOP_BUDGET;
use crate::render::passes::list_sort::{ListOrder, ListSort};
use crate::visibility::Fragment;

/// Bytes of one list node (depth, alpha, segment, next).
pub const NODE_BYTES: u64 = 16;

pub use super::list_pages::NODE_PAGES;

/// Bytes of the counters: `[fragments counted, nodes allocated, dropped, longest list, node capacity]` and
/// padding. The fill clears the first four; the capacity is written when the pages are sized.
const COUNTER_BYTES: u64 = 32;
/// Bytes of the counters each pass clears (the capacity after them is kept).
const CLEARED_COUNTER_BYTES: u64 = 16;

/// One light-space fragment as the reference keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefFragment {
    pub depth: f32,
    pub alpha: f32,
    /// Index of the segment's first point: with the depth, it orders fragments totally.
    pub segment: u32,
}

impl RefFragment {
    /// The fragment as the CPU models take it (depth, alpha and segment).
    pub fn fragment(&self) -> Fragment {
        Fragment {
            segment: self.segment,
            ..Fragment::new(self.depth, self.alpha)
        }
    }
}

/// Sorts a texel's fragments by (depth, segment), the order the depth peel produces.
pub fn sort_fragments(list: &mut [RefFragment]) {
    list.sort_by(|a, b| a.depth.total_cmp(&b.depth).then(a.segment.cmp(&b.segment)));
}

/// The largest batch of a walk along the lists (`LIST_BATCH_MAX` in `shaders/common/list_walk.wgsl`).
pub const WALK_BATCH_MAX: u32 = 32;

/// How a walk along the sorted lists (`shaders/common/list_walk.wgsl`) is split: `batch` fragments taken at a
/// time, `steps` batches per texel in each of `dispatches`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WalkSplit {
    pub batch: u32,
    pub steps: u32,
    pub dispatches: u32,
}

impl WalkSplit {
    /// The split for lists of at most `longest` fragments when a batch of `b` costs `b` loop iterations along
    /// the list plus `per_fragment` for each fragment taken; a list of `n` fragments takes `n / b + 1` batches
    /// (the last one finds the end). Without a budget (loop iterations per invocation and dispatch): the largest
    /// batch, every batch in one dispatch. With one: the largest batch (a power of two) of which one fits, as
    /// many per dispatch as fit; `None` when not even a batch of one fits.
    pub fn new(longest: u64, per_fragment: u64, budget: Option<u64>) -> Option<WalkSplit> {
        let needed = |batch: u64| longest / batch + 1;
        let Some(budget) = budget else {
            return Some(WalkSplit {
                batch: WALK_BATCH_MAX,
                steps: needed(WALK_BATCH_MAX as u64) as u32,
                dispatches: 1,
            });
        };
        let mut batch = WALK_BATCH_MAX as u64;
        loop {
            let per_batch = batch * (1 + per_fragment);
            let fit = budget / per_batch;
            if fit > 0 {
                let steps = fit.min(needed(batch));
                return Some(WalkSplit {
                    batch: batch as u32,
                    steps: steps as u32,
                    dispatches: needed(batch).div_ceil(steps) as u32,
                });
            }
            if batch == 1 {
                return None;
            }
            batch /= 2;
        }
    }
}

pub struct ABuffer {
    count_pipeline: wgpu::RenderPipeline,
    fill_pipeline: wgpu::RenderPipeline,
    pass_layout: wgpu::BindGroupLayout,
    pub lookup_layout: wgpu::BindGroupLayout,
    counters: wgpu::Buffer,
    heads: wgpu::Buffer,
    /// [`NODE_PAGES`] pages: the first `used` hold the nodes, the rest are 16-byte placeholders.
    pages: Vec<wgpu::Buffer>,
    /// Nodes the pages hold.
    capacity: u64,
    resolution: u32,
    pass_bind_group: wgpu::BindGroup,
    pub lookup_bind_group: wgpu::BindGroup,
    target: super::NullTarget,
    /// Fragments of the last frame.
    pub fragment_count: u64,
    /// Fragments in the longest texel list of the last frame.
    pub longest_list: u64,
    /// The sort of the lists after each fill, for owners that walk them in order ([`ABuffer::sorted`]).
    sort: Option<ListSort>,
    /// The fill pass's name in GPU timings, and the A-buffer's in errors (the owner's).
    pass_label: &'static str,
    what: &'static str,
}

impl ABuffer {
    pub fn new(gpu: &Gpu, frame_layout: &wgpu::BindGroupLayout, light: &LightStage) -> ABuffer {
        let device = &gpu.device;
        let write = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        // Binding numbers are those of common/list_pages_rw.wgsl (counters, heads, pages: the fill and the sort)
        // and common/list_pages.wgsl (heads, pages).
        let pass_entries: Vec<wgpu::BindGroupLayoutEntry> = (0..2 + NODE_PAGES as u32)
            .map(|b| storage_entry(b, write, false))
            .collect();
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.abuffer.pass_layout"),
            entries: &pass_entries,
        });
        let look = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let lookup_entries: Vec<wgpu::BindGroupLayoutEntry> = (0..1 + NODE_PAGES as u32)
            .map(|b| storage_entry(b, look, true))
            .collect();
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.abuffer.lookup_layout"),
            entries: &lookup_entries,
        });
        let module = light.module(device, "hairlab.abuffer.shader", "abuffer.wgsl");
        let targets = [super::NullTarget::target_state()];
        let pipeline = |entry: &str| {
            light.pipeline(
                device,
                "hairlab.abuffer.pipeline",
                &[frame_layout, &pass_layout],
                &module,
                entry,
                &targets,
            )
        };
        let count_pipeline = pipeline("fs_count");
        let fill_pipeline = pipeline("fs_fill");
        let counters = Self::buffer(gpu, "hairlab.abuffer.counters", COUNTER_BYTES);
        let heads = Self::buffer(gpu, "hairlab.abuffer.heads", 4);
        let pages = Self::pages(gpu, 1, 1);
        let (pass_bind_group, lookup_bind_group) =
            Self::bind_groups(gpu, &pass_layout, &lookup_layout, &counters, &heads, &pages);
        gpu.queue
            .write_buffer(&counters, CLEARED_COUNTER_BYTES, bytemuck::bytes_of(&1u32));
        ABuffer {
            count_pipeline,
            fill_pipeline,
            pass_layout,
            lookup_layout,
            counters,
            heads,
            pages,
            capacity: 1,
            resolution: 1,
            pass_bind_group,
            lookup_bind_group,
            target: super::NullTarget::new(device, 1),
            fragment_count: 0,
            longest_list: 0,
            sort: None,
            pass_label: "reference: A-buffer",
            what: "reference A-buffer",
        }
    }

    /// The A-buffer with its owner's names: `pass_label` for the fill pass in GPU timings, `what` in errors
    /// (default: the reference's).
    pub fn named(self, pass_label: &'static str, what: &'static str) -> ABuffer {
        ABuffer {
            pass_label,
            what,
            ..self
        }
    }

    /// The A-buffer with its lists sorted into `order` after each fill ([`crate::render::passes::list_sort`]),
    /// for the owners that walk them in that order.
    pub fn sorted(self, gpu: &Gpu, order: ListOrder) -> ABuffer {
        let sort = ListSort::new(gpu, &self.pass_layout, order);
        ABuffer {
            sort: Some(sort),
            ..self
        }
    }

    /// The order the lists are sorted into from the next frame (an A-buffer made [`ABuffer::sorted`]).
    pub fn set_sort_order(&mut self, order: ListOrder) {
        if let Some(sort) = &mut self.sort {
            sort.set_order(order);
        }
    }

    fn buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// [`NODE_PAGES`] pages for `nodes` nodes, `page_nodes` in each but the last used one, 16-byte placeholders
    /// after it.
    fn pages(gpu: &Gpu, nodes: u64, page_nodes: u64) -> Vec<wgpu::Buffer> {
        (0..NODE_PAGES as u64)
            .map(|p| {
                let held = nodes.saturating_sub(p * page_nodes).min(page_nodes).max(1);
                Self::buffer(gpu, "hairlab.abuffer.nodes", held * NODE_BYTES)
            })
            .collect()
    }

    fn bind_groups(
        gpu: &Gpu,
        pass_layout: &wgpu::BindGroupLayout,
        lookup_layout: &wgpu::BindGroupLayout,
        counters: &wgpu::Buffer,
        heads: &wgpu::Buffer,
        pages: &[wgpu::Buffer],
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        fn entries<'a>(buffers: Vec<&'a wgpu::Buffer>) -> Vec<wgpu::BindGroupEntry<'a>> {
            buffers
                .into_iter()
                .enumerate()
                .map(|(b, buffer)| wgpu::BindGroupEntry {
                    binding: b as u32,
                    resource: buffer.as_entire_binding(),
                })
                .collect()
        }
        let pass = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.abuffer.pass_bind_group"),
            layout: pass_layout,
            entries: &entries([counters, heads].into_iter().chain(pages).collect()),
        });
        let lookup = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.abuffer.lookup_bind_group"),
            layout: lookup_layout,
            entries: &entries(std::iter::once(heads).chain(pages).collect()),
        });
        (pass, lookup)
    }

    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::RenderPipeline,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.abuffer.pass"),
            color_attachments: &[self.target.attachment()],
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw_casters(
            &mut pass,
            pipeline,
            frame,
            Some(&self.pass_bind_group),
            casters,
            0..1,
        );
    }

    /// Counts this frame's fragments and the longest texel list (a counting pass, timed as `<pass label> count`,
    /// submitted at once and read back, blocking) and grows the node pages to fit them; refuses lists beyond
    /// [`NODE_PAGES`] × the device's storage binding size.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        resolution: u32,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let device = &gpu.device;
        self.target.ensure(device, resolution);
        let texels = resolution as u64 * resolution as u64;
        let max_binding = device.limits().max_storage_buffer_binding_size;
        if texels * 4 > max_binding {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the {} heads ({resolution}² texels of 4 B; lower the map resolution)",
                    self.what
                ),
                bytes: texels * 4,
                limit: max_binding,
            });
        }
        // The counting pass counts each texel's list in the heads (cleared again before the fill).
        if resolution != self.resolution {
            self.resolution = resolution;
            self.heads = Self::buffer(gpu, "hairlab.abuffer.heads", texels * 4);
            self.rebuild_bind_groups(gpu);
        }
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.abuffer.count"),
        });
        enc.clear_buffer(&self.counters, 0, Some(CLEARED_COUNTER_BYTES));
        enc.clear_buffer(&self.heads, 0, None);
        let label = format!("{} count", self.pass_label);
        let ts = timer
            .as_mut()
            .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, label));
        self.draw(&mut enc, &self.count_pipeline, frame, casters, ts);
        let readback_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.abuffer.count_readback"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(&self.counters, 0, &readback_buffer, 0, 16);
        gpu.queue.submit([enc.finish()]);
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&readback::read_buffer(gpu, &readback_buffer)?);
        let count = counts[0] as u64;
        self.fragment_count = count;
        self.longest_list = counts[3] as u64;
        let page_nodes = (max_binding / NODE_BYTES).max(1);
        if count > page_nodes * NODE_PAGES as u64 {
            return Err(GpuError::TooLarge {
                what: format!(
                    "the {} ({count} light-space fragments at {resolution}² texels in {NODE_PAGES} node pages of \
                     one binding each; lower the map resolution or the strand count)",
                    self.what
                ),
                bytes: count * NODE_BYTES,
                limit: max_binding * NODE_PAGES as u64,
            });
        }
        if count > self.capacity {
            self.capacity = count;
            self.pages = Self::pages(gpu, count, page_nodes);
            self.rebuild_bind_groups(gpu);
            // `count` was read from a u32 counter.
            gpu.queue.write_buffer(
                &self.counters,
                CLEARED_COUNTER_BYTES,
                bytemuck::bytes_of(&(count as u32)),
            );
        }
        let (longest, pages) = (self.longest_list, self.pages_used());
        if let Some(sort) = &mut self.sort {
            sort.prepare(gpu, resolution, longest, pages, self.what)?;
        }
        Ok(())
    }

    fn rebuild_bind_groups(&mut self, gpu: &Gpu) {
        (self.pass_bind_group, self.lookup_bind_group) = Self::bind_groups(
            gpu,
            &self.pass_layout,
            &self.lookup_layout,
            &self.counters,
            &self.heads,
            &self.pages,
        );
    }

    /// Node pages holding this frame's nodes (1 when they fit one binding).
    pub fn pages_used(&self) -> usize {
        let first = self.pages[0].size() / NODE_BYTES;
        self.capacity.div_ceil(first) as usize
    }

    /// Records the pass that fills the lists (after [`ABuffer::prepare`] for this frame), and their sort.
    pub fn record(
        &self,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        encoder.clear_buffer(&self.counters, 0, Some(CLEARED_COUNTER_BYTES));
        encoder.clear_buffer(&self.heads, 0, None);
        let label = self.pass_label;
        let ts = timer
            .as_mut()
            .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, label));
        self.draw(encoder, &self.fill_pipeline, frame, casters, ts);
        if let Some(sort) = &self.sort {
            sort.record(
                encoder,
                self.pages_used(),
                &self.pass_bind_group,
                format!("{label} sort"),
                timer,
            );
        }
    }

    pub fn memory_bytes(&self) -> u64 {
        let pages: u64 = self.pages.iter().map(wgpu::Buffer::size).sum();
        let sort = self.sort.as_ref().map_or(0, ListSort::memory_bytes);
        self.heads.size() + pages + self.counters.size() + self.target.bytes() + sort
    }

    /// How `what`'s walk over this frame's lists (after [`ABuffer::prepare`]) is split over dispatches
    /// ([`WalkSplit::new`]; [`CPU_ADAPTER_LOOP_BUDGET`] on a CPU adapter); an error when one fragment is beyond
    /// that budget (a walk of `per_fragment` iterations per fragment or more).
    pub fn walk_split(&self, gpu: &Gpu, what: &str, per_fragment: u64) -> Result<WalkSplit, GpuError> {
        let longest = self.longest_list;
        let budget = (gpu.info.device_type == wgpu::DeviceType::Cpu).then_some(CPU_ADAPTER_LOOP_BUDGET);
        WalkSplit::new(longest, per_fragment, budget).ok_or_else(|| {
            GpuError::Setting(format!(
                "{what} on a CPU adapter: a fragment at {per_fragment} loop iterations is beyond llvmpipe's \
                 {CPU_ADAPTER_LOOP_BUDGET} (it stops shader loops after 65,535 iterations)"
            ))
        })
    }

    /// Reads the lists back: per texel (row-major), its fragments sorted by (depth, segment). Fails if the
    /// node buffer overflowed (it cannot when [`ABuffer::record`] sized it this frame).
    pub fn read_lists(&self, gpu: &Gpu) -> Result<Vec<Vec<RefFragment>>, GpuError> {
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.counters)?);
        if counters[2] > 0 {
            return Err(GpuError::Readback(format!(
                "{} overflow: {} fragments did not fit in {} nodes",
                self.what, counters[2], self.capacity
            )));
        }
        let heads: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.heads)?);
        let mut nodes: Vec<[u32; 4]> = Vec::new();
        for page in &self.pages[..self.pages_used()] {
            nodes.extend(bytemuck::pod_collect_to_vec::<u8, [u32; 4]>(&copy_out(
                gpu, page,
            )?));
        }
        let used = counters[1] as usize;
        let mut lists = vec![Vec::new(); heads.len()];
        for (t, &head) in heads.iter().enumerate() {
            let mut i = head as usize;
            let mut steps = 0;
            while i != 0 && i <= used && steps <= used {
                let n = nodes[i - 1];
                lists[t].push(RefFragment {
                    depth: f32::from_bits(n[0]),
                    alpha: f32::from_bits(n[1]),
                    segment: n[2],
                });
                i = n[3] as usize;
                steps += 1;
            }
            sort_fragments(&mut lists[t]);
        }
        Ok(lists)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_split_to_fit_the_budget() {
        let split = |batch, steps, dispatches| {
            Some(WalkSplit {
                batch,
                steps,
                dispatches,
            })
        };
        // No budget: batches of 32, every one in one dispatch (5000 / 32 + 1 = 157).
        assert_eq!(WalkSplit::new(5000, 100, None), split(32, 157, 1));
        // 179 fragments at 109 more per fragment: a batch of 32 costs 32 × 110 = 3520, 17 fit in 60,000 and six
        // are needed (179 / 32 + 1).
        assert_eq!(WalkSplit::new(179, 109, Some(60_000)), split(32, 6, 1));
        // 1300 fragments: 41 batches needed, 17 a dispatch, three dispatches.
        assert_eq!(WalkSplit::new(1300, 109, Some(60_000)), split(32, 17, 3));
        // 5000: 157 needed.
        assert_eq!(WalkSplit::new(5000, 109, Some(60_000)), split(32, 17, 10));
        // Empty lists still take one dispatch (it writes the empty texels' nodes).
        assert_eq!(WalkSplit::new(0, 109, Some(60_000)), split(32, 1, 1));
        // 3740 more per fragment: a batch of 32 (119,712) does not fit, one of 16 (59,856) does; 100 / 16 + 1.
        assert_eq!(WalkSplit::new(100, 3740, Some(60_000)), split(16, 1, 7));
        // 59,999: only a batch of one (60,000) fits; 60,000: none.
        assert_eq!(WalkSplit::new(100, 59_999, Some(60_000)), split(1, 1, 101));
        assert_eq!(WalkSplit::new(100, 60_000, Some(60_000)), None);
    }
}
