//! Reference A-buffer pass: a counting pass sizes the node buffer from the scene, then one geometry pass links
//! every light-space fragment into its texel's list (storage-buffer atomics in the fragment shader). The lists,
//! read back and sorted, are the exact per-texel fragment lists of the reference; the eye passes can also walk
//! them to shade with exact visibility.

use crate::gpu::readback::copy_out;
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError, readback};
use crate::render::caster::{LightCaster, LightStage, draw_casters};
use crate::render::maps::storage_entry;
use crate::visibility::Fragment;

/// Bytes of one list node (depth, alpha, segment, next).
pub const NODE_BYTES: u64 = 16;

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

/// Longest texel list a compute pass that walks each list with an O(n²) select-next (AVSM's and the compressed
/// deep shadow map's compressors) takes on a CPU adapter: llvmpipe (lavapipe) stops a shader's loops after
/// 65,535 iterations in all, which such a walk reaches near 240 fragments in one texel (measured with AVSM at
/// 8 nodes: 220 fragments equal the CPU model, 244 do not).
pub const MAX_WALKED_LIST_ON_CPU_ADAPTER: u64 = 180;

pub struct ABuffer {
    count_pipeline: wgpu::RenderPipeline,
    fill_pipeline: wgpu::RenderPipeline,
    pass_layout: wgpu::BindGroupLayout,
    pub lookup_layout: wgpu::BindGroupLayout,
    counters: wgpu::Buffer,
    heads: wgpu::Buffer,
    nodes: wgpu::Buffer,
    capacity: u64,
    resolution: u32,
    pass_bind_group: wgpu::BindGroup,
    pub lookup_bind_group: wgpu::BindGroup,
    target: super::NullTarget,
    /// Fragments of the last frame.
    pub fragment_count: u64,
    /// Fragments in the longest texel list of the last frame.
    pub longest_list: u64,
    /// The fill pass's name in GPU timings, and the A-buffer's in errors (the owner's).
    pass_label: &'static str,
    what: &'static str,
}

impl ABuffer {
    pub fn new(gpu: &Gpu, frame_layout: &wgpu::BindGroupLayout, light: &LightStage) -> ABuffer {
        let device = &gpu.device;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.abuffer.pass_layout"),
            entries: &[
                storage_entry(0, frag, false),
                storage_entry(1, frag, false),
                storage_entry(2, frag, false),
            ],
        });
        let look = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.abuffer.lookup_layout"),
            entries: &[storage_entry(0, look, true), storage_entry(1, look, true)],
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
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.abuffer.counters"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (heads, nodes) = (
            Self::buffer(gpu, "hairlab.abuffer.heads", 4),
            Self::buffer(gpu, "hairlab.abuffer.nodes", NODE_BYTES),
        );
        let (pass_bind_group, lookup_bind_group) =
            Self::bind_groups(gpu, &pass_layout, &lookup_layout, &counters, &heads, &nodes);
        ABuffer {
            count_pipeline,
            fill_pipeline,
            pass_layout,
            lookup_layout,
            counters,
            heads,
            nodes,
            capacity: 1,
            resolution: 1,
            pass_bind_group,
            lookup_bind_group,
            target: super::NullTarget::new(device, 1),
            fragment_count: 0,
            longest_list: 0,
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

    fn buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn bind_groups(
        gpu: &Gpu,
        pass_layout: &wgpu::BindGroupLayout,
        lookup_layout: &wgpu::BindGroupLayout,
        counters: &wgpu::Buffer,
        heads: &wgpu::Buffer,
        nodes: &wgpu::Buffer,
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let pass = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.abuffer.pass_bind_group"),
            layout: pass_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: counters.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: heads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: nodes.as_entire_binding(),
                },
            ],
        });
        let lookup = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.abuffer.lookup_bind_group"),
            layout: lookup_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: heads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: nodes.as_entire_binding(),
                },
            ],
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
    /// submitted at once and read back,
    /// blocking) and grows the node buffer to fit them; refuses lists beyond the device's storage binding size.
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
        let too_large = |what: &str, count: u64, bytes: u64| GpuError::TooLarge {
            what: format!(
                "the {what} ({count} light-space fragments at {resolution}² texels; lower the map resolution or the \
                 strand count)"
            ),
            bytes,
            limit: max_binding,
        };
        if texels * 4 > max_binding {
            return Err(too_large(self.what, self.fragment_count, texels * 4));
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
        enc.clear_buffer(&self.counters, 0, None);
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
        let node_bytes = count.max(1) * NODE_BYTES;
        if node_bytes > max_binding {
            return Err(too_large(self.what, count, node_bytes));
        }
        if count > self.capacity {
            self.capacity = count;
            self.nodes = Self::buffer(gpu, "hairlab.abuffer.nodes", self.capacity * NODE_BYTES);
            self.rebuild_bind_groups(gpu);
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
            &self.nodes,
        );
    }

    /// Records the pass that fills the lists (after [`ABuffer::prepare`] for this frame).
    pub fn record(
        &self,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        self.record_as(self.pass_label, frame, casters, encoder, timer);
    }

    /// [`ABuffer::record`] timed as `label` (a second fill in one frame needs a name of its own).
    pub fn record_as(
        &self,
        label: &str,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        encoder.clear_buffer(&self.counters, 0, None);
        encoder.clear_buffer(&self.heads, 0, None);
        let ts = timer
            .as_mut()
            .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, label));
        self.draw(encoder, &self.fill_pipeline, frame, casters, ts);
    }

    pub fn memory_bytes(&self) -> u64 {
        self.heads.size() + self.nodes.size() + self.counters.size() + self.target.bytes()
    }

    /// Refuses this frame's lists for `what`'s O(n²) list walk on a CPU adapter when the longest list exceeds
    /// [`MAX_WALKED_LIST_ON_CPU_ADAPTER`] (after [`ABuffer::prepare`]): an error naming the settings to change
    /// rather than a wrong result.
    pub fn check_walk(&self, gpu: &Gpu, what: &str) -> Result<(), GpuError> {
        let longest = self.longest_list;
        if gpu.info.device_type == wgpu::DeviceType::Cpu && longest > MAX_WALKED_LIST_ON_CPU_ADAPTER {
            return Err(GpuError::Setting(format!(
                "{what} on a CPU adapter compresses at most {MAX_WALKED_LIST_ON_CPU_ADAPTER} fragments per texel \
                 (llvmpipe stops shader loops after 65,535 iterations) and a texel holds {longest}: raise \
                 render.map_resolution or lower scene.generator.strands"
            )));
        }
        Ok(())
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
        let nodes: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.nodes)?);
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
