//! One per-pixel list type ([`PixelLists`]): the fragment lists of the exact eye reference (Carpenter 1984's
//! A-buffer, built as the linked lists of Yang et al. 2010) and of the fur's typed lists (Andersen et al. 2016
//! §3.3). Four steps, each a method:
//!
//! 1. **count**: the technique's count passes add 1 per fragment to its pixel's count ([`PixelLists::counts`],
//!    the total at `[W·H]`, groups of [`PixelLists::count_group`]);
//! 2. **plan**: the counts read back ([`PixelLists::plan`]) size the node buffer to exactly the frame's
//!    fragments, in horizontal bands of rows when they exceed one storage binding (or the band budget), and pick
//!    the sort size of the deepest pixel — each refusal naming the view, its figures and the key;
//! 3. **fill**: per band ([`PixelLists::begin_band`]) the technique's shaded passes push nodes through
//!    [`PixelLists::fill_group`] (`transparency/sorted.wgsl`'s push, or the fur shell's);
//! 4. **resolve**: per band the technique's resolve (written on `common/list_resolve.wgsl`) gathers each pixel's
//!    nodes into private arrays of the smallest of [`SORT_SIZES`] that holds it, sorts and composites them; one
//!    pipeline per sort size and output format ([`PixelLists::resolve`]).
//!
//! Memory: 4 B/px heads + 4 B/px counts + [`NODE_BYTES`] per fragment of the largest band.

use std::collections::HashMap;

use super::bindings::{self, Binding};
use super::pipelines;
use crate::gpu::readback::copy_out;
use crate::gpu::timing::Phase;
use crate::gpu::{Gpu, GpuError};
use crate::render::method::{ParamKind, ParamSpec};
use crate::render::passes::hair::{EntryDepth, HairDrawPass, HairEntry, HairGeometry};
use crate::render::targets::EyeTargets;
use crate::render::transparency::EyeFrame;

/// Bytes of one list node (`common/eye_node.wgsl`).
pub const NODE_BYTES: u64 = 32;

/// The resolve's private sort sizes; a pixel deeper than the last is refused.
pub const SORT_SIZES: [u32; 6] = [16, 64, 128, 256, 512, 1024];

/// The hair file of a list technique's fill: the shaded fragment pushed onto its pixel's list.
pub const FILL_WGSL: &str = "transparency/sorted.wgsl";

/// The fill's hair entry ([`FILL_WGSL`]'s `fs_main`) over `geometry`: storage writes only, the meshes' depth tested
/// by hand before them.
pub const fn fill_entry(geometry: HairGeometry) -> HairEntry {
    HairEntry {
        entry: "fs_main",
        targets: NULL_TARGET,
        depth: EntryDepth::Manual,
        geometry,
    }
}

const NULL_TARGET: &[wgpu::ColorTargetState] = &[EyeTargets::NULL];

/// A list technique's band budget, `transparency.params.band_kib` (the key the plan's refusals name).
pub const BAND_KIB: ParamSpec = ParamSpec {
    key: "band_kib",
    label: "band budget KiB",
    help: "most KiB of list nodes per band of rows (0: the device's storage binding limit); a smaller budget \
           renders the same image in more bands",
    kind: ParamKind::Int { min: 0, max: 4 << 20 },
    default: 0.0,
};

/// Mirror of `EyeNode` in `common/eye_node.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EyeNode {
    pub depth: f32,
    pub segment: u32,
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub alpha: f32,
    pub next: u32,
    pub kind: u32,
}

/// Group 1 of a count pass: the per-pixel counts and the meshes' depth.
pub const COUNT_GROUP: &[Binding] = &[Binding::StorageRw, Binding::MeshDepth];
/// The fill's group (group 2 of the hair pass): heads, nodes, counters and the meshes' depth.
pub const FILL_GROUP: &[Binding] = &[
    Binding::StorageRw,
    Binding::StorageRw,
    Binding::StorageRw,
    Binding::MeshDepth,
];
/// The first bindings of a resolve's group 1 (`common/list_resolve.wgsl`): heads and nodes; a technique's own
/// bindings follow.
pub const RESOLVE_GROUP: &[Binding] = &[Binding::StorageRo, Binding::StorageRo];

/// The sort sizes a resolve of a frame whose deepest pixel has `max` fragments instantiates.
pub fn sort_sizes(max: u32) -> Vec<u32> {
    SORT_SIZES
        .iter()
        .copied()
        .filter(|&s| s <= max.max(SORT_SIZES[0]))
        .collect()
}

/// The list resolve `path` with its sort instantiated for every size up to `max` ([`sort_sizes`]).
pub fn resolve_source(path: &str, max: u32) -> Result<String, crate::shaders::ShaderError> {
    crate::shaders::compose_sorts(path, &sort_sizes(max))
}

/// How a list technique's errors name it: the key and owner of a too-deep pixel (`"<key>: the <owner>"`), the
/// owner of a row over the band budget, and what was drawn (appended to the row's figures).
pub struct ListNames {
    pub deep: &'static str,
    pub rows: &'static str,
    pub drawn: String,
}

/// A frame's lists as its counts size them: the sort size of its deepest pixel, its bands of rows, the nodes of
/// the largest band, the deepest pixel and the fragments in all.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ListPlan {
    pub size: u32,
    pub bands: Vec<(u32, u32)>,
    pub needed: u64,
    pub deepest: u32,
    pub fragments: u64,
}

/// Plans a `width`×`height` frame's lists from its per-pixel `counts` (the total at `[W·H]`): refuses a pixel
/// deeper than the last of [`SORT_SIZES`] and a row over the band budget (`budget` bytes, 0: the device's
/// binding), each naming the view, the figures and the key.
pub fn plan_lists(
    gpu: &Gpu,
    counts: &[u32],
    (width, height): (u32, u32),
    budget: u64,
    names: &ListNames,
) -> Result<ListPlan, GpuError> {
    let pixels = width as usize * height as usize;
    let deepest = counts[..pixels].iter().copied().max().unwrap_or(0);
    let Some(&size) = SORT_SIZES.iter().find(|&&s| s >= deepest) else {
        return Err(GpuError::Setting(format!(
            "{} sorts at most {} fragments per pixel, and a pixel of this {width}x{height} view has {deepest}",
            names.deep,
            SORT_SIZES[SORT_SIZES.len() - 1],
        )));
    };
    // Size the nodes from the count: bands when the frame's fragments exceed one binding.
    let limit = gpu.device.limits();
    let device_limit = limit.max_storage_buffer_binding_size.min(limit.max_buffer_size);
    let binding = if budget == 0 {
        device_limit
    } else {
        budget.min(device_limit)
    };
    let row_counts: Vec<u64> = counts[..pixels]
        .chunks(width as usize)
        .map(|r| r.iter().map(|&c| c as u64).sum())
        .collect();
    let bands = bands(&row_counts, binding / NODE_BYTES).map_err(|row| {
        let what = format!(
            "{} row {row} of a {width}x{height} view ({} fragments{})",
            names.rows, row_counts[row], names.drawn
        );
        let bytes = row_counts[row] * NODE_BYTES;
        if binding < device_limit {
            GpuError::Setting(format!(
                "transparency.params.band_kib: {what} needs {bytes} bytes, more than the band budget of {binding} \
                 bytes"
            ))
        } else {
            GpuError::TooLarge {
                what,
                bytes,
                limit: binding,
            }
        }
    })?;
    let needed = bands
        .iter()
        .map(|&(y0, y1)| row_counts[y0 as usize..y1 as usize].iter().sum::<u64>())
        .max()
        .unwrap_or(0)
        .max(1);
    Ok(ListPlan {
        size,
        bands,
        needed,
        deepest,
        fragments: u64::from(counts[pixels]),
    })
}

/// Rows `[y0, y1)` whose fragments fit in `capacity` nodes, greedily from the top; an error when one row alone
/// does not fit.
pub fn bands(row_counts: &[u64], capacity: u64) -> Result<Vec<(u32, u32)>, usize> {
    let mut out = Vec::new();
    let (mut start, mut sum) = (0usize, 0u64);
    for (y, &n) in row_counts.iter().enumerate() {
        if n > capacity {
            return Err(y);
        }
        if sum + n > capacity {
            out.push((start as u32, y as u32));
            (start, sum) = (y, 0);
        }
        sum += n;
    }
    out.push((start as u32, row_counts.len() as u32));
    Ok(out)
}

/// What a list technique's [`PixelLists`] are made for.
pub struct ListSpec {
    /// Buffer and pipeline labels: `hairlab.<label>.counts`, ….
    pub label: &'static str,
    /// How errors name the lists, e.g. "eye lists".
    pub what: &'static str,
    /// The resolve shader, written on `common/list_resolve.wgsl`.
    pub resolve_wgsl: &'static str,
    /// The resolve group's bindings after [`RESOLVE_GROUP`]'s.
    pub resolve_extra: &'static [Binding],
}

/// The viewport-sized buffers.
struct Buffers {
    width: u32,
    height: u32,
    /// Per-pixel counts, and the total at [W·H].
    counts: wgpu::Buffer,
    heads: wgpu::Buffer,
    nodes: wgpu::Buffer,
    capacity: u64,
    /// [0] nodes used, [1] fragments that did not fit.
    counters: wgpu::Buffer,
}

impl Buffers {
    fn new(
        gpu: &Gpu,
        spec: &ListSpec,
        (width, height): (u32, u32),
        capacity: u64,
    ) -> Result<Buffers, GpuError> {
        let device = &gpu.device;
        let pixels = width as u64 * height as u64;
        let what = spec.what;
        gpu.check_buffer_size(&format!("{what}' pixel heads at {width}x{height}"), pixels * 4)?;
        gpu.check_buffer_size(
            &format!("{what}' nodes at {width}x{height}"),
            capacity * NODE_BYTES,
        )?;
        let label = |part: &str| format!("hairlab.{}.{part}", spec.label);
        Ok(Buffers {
            width,
            height,
            counts: bindings::storage(device, &label("counts"), (pixels + 1) * 4),
            heads: bindings::storage(device, &label("heads"), pixels * 4),
            nodes: bindings::storage(device, &label("nodes"), capacity.max(1) * NODE_BYTES),
            capacity: capacity.max(1),
            counters: bindings::storage(device, &label("counters"), 8),
        })
    }
}

/// A technique's per-pixel lists: the buffers, the layouts of the count, fill and resolve groups, and the resolve
/// pipelines by (sort size, output format).
pub struct PixelLists {
    spec: ListSpec,
    frame_layout: wgpu::BindGroupLayout,
    count_layout: wgpu::BindGroupLayout,
    fill_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
    resolves: HashMap<(u32, wgpu::TextureFormat), wgpu::RenderPipeline>,
    buffers: Buffers,
    /// The last frame's plan.
    plan: ListPlan,
}

impl PixelLists {
    /// Lists for a `width`×`height` view; `frame_layout` is group 0 of the resolve.
    pub fn new(
        gpu: &Gpu,
        frame_layout: &wgpu::BindGroupLayout,
        (width, height): (u32, u32),
        spec: ListSpec,
    ) -> Result<PixelLists, GpuError> {
        let device = &gpu.device;
        let label = |part: &str| format!("hairlab.{}.{part}", spec.label);
        let resolve_bindings: Vec<Binding> =
            RESOLVE_GROUP.iter().chain(spec.resolve_extra).copied().collect();
        Ok(PixelLists {
            count_layout: bindings::layout(device, &label("count_layout"), COUNT_GROUP),
            fill_layout: bindings::layout(device, &label("fill_layout"), FILL_GROUP),
            resolve_layout: bindings::layout(device, &label("resolve_layout"), &resolve_bindings),
            frame_layout: frame_layout.clone(),
            resolves: HashMap::new(),
            buffers: Buffers::new(gpu, &spec, (width, height), 1)?,
            spec,
            plan: ListPlan::default(),
        })
    }

    /// Re-creates the per-pixel buffers for `width`×`height` (nothing when the size is unchanged).
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        let b = &self.buffers;
        if (b.width, b.height) != (width, height) {
            self.buffers = Buffers::new(gpu, &self.spec, (width, height), b.capacity)?;
        }
        Ok(())
    }

    pub fn size(&self) -> (u32, u32) {
        (self.buffers.width, self.buffers.height)
    }

    /// Step 1: the counts, cleared in `encoder`; count passes add to them through [`PixelLists::count_group`].
    pub fn clear_counts(&self, encoder: &mut wgpu::CommandEncoder) -> &wgpu::Buffer {
        encoder.clear_buffer(&self.buffers.counts, 0, None);
        &self.buffers.counts
    }

    /// The per-pixel counts (the total at `[W·H]`).
    pub fn counts(&self) -> &wgpu::Buffer {
        &self.buffers.counts
    }

    /// The layout of a count pass's group 1 ([`COUNT_GROUP`]).
    pub fn count_layout(&self) -> &wgpu::BindGroupLayout {
        &self.count_layout
    }

    /// A count pass's group 1: the counts and the meshes' depth.
    pub fn count_group(&self, device: &wgpu::Device, mesh_depth: &wgpu::TextureView) -> wgpu::BindGroup {
        bindings::group(
            device,
            &format!("hairlab.{}.count_group", self.spec.label),
            &self.count_layout,
            &[
                self.buffers.counts.as_entire_binding(),
                wgpu::BindingResource::TextureView(mesh_depth),
            ],
        )
    }

    /// Step 2: reads back the counts (the frame flushed first), plans the frame (`budget` bytes of nodes per band,
    /// 0: the device's binding), sizes the nodes to its largest band and prepares the resolve of its sort size
    /// onto `format`.
    pub fn plan(
        &mut self,
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        budget: u64,
        names: &ListNames,
    ) -> Result<&ListPlan, GpuError> {
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.buffers.counts)?);
        let size = self.size();
        let plan = plan_lists(gpu, &counts, size, budget, names)?;
        let capacity = self.buffers.capacity;
        if plan.needed > capacity || plan.needed < capacity / 2 {
            self.buffers = Buffers::new(gpu, &self.spec, size, plan.needed)?;
        }
        let (frame_layout, resolve_layout, path) =
            (&self.frame_layout, &self.resolve_layout, self.spec.resolve_wgsl);
        self.resolves.entry((plan.size, format)).or_insert_with(|| {
            let module = pipelines::module(&gpu.device, path, resolve_source(path, plan.size));
            pipelines::fullscreen(
                &gpu.device,
                path,
                &module,
                &[frame_layout, resolve_layout],
                &[Some(pipelines::over_target(format))],
            )
        });
        self.plan = plan;
        Ok(&self.plan)
    }

    /// The last frame's plan.
    pub fn last_plan(&self) -> &ListPlan {
        &self.plan
    }

    /// Step 3: the fill's group over the planned buffers: heads, nodes, counters and the meshes' depth.
    pub fn fill_group(&self, device: &wgpu::Device, mesh_depth: &wgpu::TextureView) -> wgpu::BindGroup {
        let b = &self.buffers;
        bindings::group(
            device,
            &format!("hairlab.{}.fill_group", self.spec.label),
            &self.fill_layout,
            &[
                b.heads.as_entire_binding(),
                b.nodes.as_entire_binding(),
                b.counters.as_entire_binding(),
                wgpu::BindingResource::TextureView(mesh_depth),
            ],
        )
    }

    /// Heads, nodes and counters, for a fill that binds them itself (the fur shell's).
    pub fn fill_buffers(&self) -> [&wgpu::Buffer; 3] {
        let b = &self.buffers;
        [&b.heads, &b.nodes, &b.counters]
    }

    /// Clears the heads and counters before a band's fill.
    pub fn begin_band(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.buffers.heads, 0, None);
        encoder.clear_buffer(&self.buffers.counters, 0, None);
    }

    /// The resolve's group 1: heads, nodes and the technique's `extra` resources.
    pub fn resolve_group(
        &self,
        device: &wgpu::Device,
        extra: &[wgpu::BindingResource<'_>],
    ) -> wgpu::BindGroup {
        let b = &self.buffers;
        let mut resources = vec![b.heads.as_entire_binding(), b.nodes.as_entire_binding()];
        resources.extend(extra.iter().cloned());
        bindings::group(
            device,
            &format!("hairlab.{}.resolve_group", self.spec.label),
            &self.resolve_layout,
            &resources,
        )
    }

    /// Step 3 of one band: the shaded hair through `entry` (a [`fill_entry`]) pushed onto the lists over rows
    /// `band` only, with `group` (a [`PixelLists::fill_group`]) as group 2, timed as `timer`.
    pub fn fill(
        &self,
        frame: &mut EyeFrame<'_>,
        entry: &'static HairEntry,
        group: &wgpu::BindGroup,
        band: (u32, u32),
        timer: &str,
    ) {
        let null = [frame.targets.null_attachment()];
        frame.draw_hair(
            HairDrawPass {
                entry,
                attachments: &null,
                depth: None,
                group: Some((&self.fill_layout, group)),
                rows: Some(band),
            },
            timer,
        );
    }

    /// Step 4: the resolve over rows `[y0, y1)` of the frame's output (of the format planned for), loaded and
    /// blended onto; group 0 the frame's, group 1 `group` (a [`PixelLists::resolve_group`]); timed as `timer`.
    pub fn resolve(
        &self,
        frame: &mut EyeFrame<'_>,
        group: &wgpu::BindGroup,
        (y0, y1): (u32, u32),
        timer: &str,
    ) {
        let (output, format) = frame.output;
        let timestamps = frame.timer.as_mut().and_then(|t| t.pass(Phase::Resolve, timer));
        pipelines::record_fullscreen(
            &mut frame.encoder,
            "hairlab.lists.resolve_pass",
            output,
            timestamps,
            Some((self.buffers.width, y0, y1)),
            &self.resolves[&(self.plan.size, format)],
            &[frame.frame_bind_group, group],
        );
    }

    /// The last frame's lists (row-major), each pixel's nodes in list order; an error when the frame was built in
    /// more than one band or its nodes overflowed.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<Vec<EyeNode>>, GpuError> {
        let what = self.spec.what;
        if self.plan.bands.len() > 1 {
            return Err(GpuError::Readback(format!(
                "the {what} of this frame were built in {} bands; only one band can be read back",
                self.plan.bands.len()
            )));
        }
        let b = &self.buffers;
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &b.counters)?);
        if counters[1] > 0 {
            return Err(GpuError::Readback(format!(
                "{what} overflow: {} fragments did not fit in {} nodes",
                counters[1], b.capacity
            )));
        }
        let heads: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &b.heads)?);
        let nodes: Vec<EyeNode> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &b.nodes)?);
        let used = (counters[0] as usize).min(nodes.len());
        Ok(heads
            .iter()
            .map(|&head| {
                let mut out = Vec::new();
                let mut i = head as usize;
                while i != 0 && i <= used && out.len() <= used {
                    let n = nodes[i - 1];
                    out.push(n);
                    i = n.next as usize;
                }
                out
            })
            .collect())
    }

    /// Bytes of the counts, heads, nodes and counters.
    pub fn memory_bytes(&self) -> u64 {
        let b = &self.buffers;
        b.counts.size() + b.heads.size() + b.nodes.size() + b.counters.size()
    }

    /// Geometry passes of the last frame: the count, and one fill per band.
    pub fn geometry_passes(&self) -> u32 {
        1 + self.plan.bands.len().max(1) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_resolve_instantiates_one_sort_per_size_up_to_the_deepest_pixel() {
        let src = resolve_source("transparency/sorted_resolve.wgsl", 256).unwrap();
        for s in [16, 64, 128, 256] {
            assert!(src.contains(&format!("fn resolve_{s}(")), "{s}");
            assert!(src.contains(&format!("array<Key, {s}u>")), "{s}");
        }
        assert!(!src.contains("fn resolve_512("));
        assert!(src.contains("if n <= 128u { return resolve_128(head, n); }"));
        assert!(src.contains("return resolve_256(head, min(n, 256u));"));
        assert!(
            !src.lines().any(|l| l.trim_start().starts_with("#sort")),
            "a directive left"
        );
        let small = resolve_source("transparency/sorted_resolve.wgsl", 1).unwrap();
        assert!(small.contains("return resolve_16(head, min(n, 16u));") && !small.contains("fn resolve_64("));
    }

    #[test]
    fn bands_fill_rows_greedily_and_refuse_a_row_over_capacity() {
        assert_eq!(bands(&[1, 2, 3], 10), Ok(vec![(0, 3)]));
        assert_eq!(bands(&[4, 4, 4, 4], 8), Ok(vec![(0, 2), (2, 4)]));
        assert_eq!(bands(&[4, 5, 4], 8), Ok(vec![(0, 1), (1, 2), (2, 3)]));
        assert_eq!(bands(&[0, 0], 1), Ok(vec![(0, 2)]));
        assert_eq!(bands(&[2, 9, 1], 8), Err(1));
    }
}
