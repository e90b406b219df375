//! The opacity layers' atomic build: the counters' layout in runs, pages and bands ([`CounterLayout`]), the count
//! pipelines, the buffers, and the compute resolve's dispatches (`shaders/layer_resolve.wgsl`) — the second of
//! the two builds the parent module describes.

use super::{LayerBuildUniforms, VALUES_PER_LAYER};
use crate::gpu::{Gpu, GpuError};
use crate::methods::{MethodContext, UniformMirror};
use crate::render::maps::{check_budget, storage_entry, texture_entry, uniform_buffer, uniform_entry};
use crate::render::passes::NullTarget;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// Storage bindings (pages) the atomic build's counters may span in one geometry pass.
pub const COUNTER_PAGES: usize = 4;

/// How the atomic build lays out its counters (4 bytes per entry and texel). The entries of a band (those one
/// geometry pass counts) are cut into runs of `run` entries, one resolve dispatch each; a run holds a texel's
/// counters side by side, texel after texel, so that its resolve reads one contiguous block; a page (one
/// storage binding) holds `runs_per_page` whole runs, and a band at most [`COUNTER_PAGES`] pages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CounterLayout {
    pub run: u32,
    pub runs_per_page: u32,
    pub band: u32,
}

impl CounterLayout {
    /// The layout for `entries` entries at `resolution`² with storage bindings of at most `limit` bytes: runs
    /// of [`RESOLVE_RUN`] entries (or all of them), shorter where a run would not fit one binding (a multiple
    /// of 4); bands of every entry when the runs fit the pages, else of as many whole runs as do. An error
    /// naming the `build` parameter when not even a run of 4 entries fits a binding.
    pub fn new(name: &str, resolution: u32, entries: u32, limit: u64) -> Result<CounterLayout, GpuError> {
        let per_entry = resolution as u64 * resolution as u64 * 4;
        let fitting = limit / per_entry;
        let wanted = entries.min(RESOLVE_RUN);
        let run = if fitting >= wanted as u64 {
            wanted
        } else {
            (fitting / VALUES_PER_LAYER as u64 * VALUES_PER_LAYER as u64) as u32
        };
        if run == 0 {
            let step = VALUES_PER_LAYER.min(entries) as u64;
            return Err(GpuError::Setting(format!(
                "{name}: build = atomic with {entries} entries at a {resolution}² map needs {} bytes of counters \
                 for a run of {step} entries, more than this GPU's storage binding limit of {limit} bytes; use \
                 build = targets or a smaller render.map_resolution",
                step * per_entry
            )));
        }
        let runs_per_page = (limit / (run as u64 * per_entry)).min(u32::MAX as u64) as u32;
        let band = (COUNTER_PAGES as u64 * runs_per_page as u64 * run as u64).min(entries as u64) as u32;
        Ok(CounterLayout {
            run,
            runs_per_page,
            band,
        })
    }

    /// Pages a band's counters take.
    pub fn pages(&self) -> u32 {
        self.band.div_ceil(self.run).div_ceil(self.runs_per_page)
    }

    /// The count pipeline for this layout: 0 for a band of one run, 1 for several runs in one page, 2 for
    /// several pages (the `layer_runs` and `layer_paged` constants of `shaders/common/layer_pass.wgsl`).
    pub(super) fn count_pipeline(&self) -> usize {
        usize::from(self.band > self.run) + usize::from(self.pages() > 1)
    }

    /// Bytes of each page for a band at `resolution`²: the entries of its runs (the band's last run may be
    /// short) times 4 bytes per texel; a page holding no run still binds one counter.
    pub fn page_bytes(&self, resolution: u32) -> [u64; COUNTER_PAGES] {
        let per_entry = resolution as u64 * resolution as u64 * 4;
        let page_entries = self.runs_per_page as u64 * self.run as u64;
        std::array::from_fn(|p| {
            let held = (self.band as u64)
                .saturating_sub(p as u64 * page_entries)
                .min(page_entries);
            (held * per_entry).max(4)
        })
    }
}

/// The largest storage binding the atomic build's counters may take on `gpu`.
pub(super) fn storage_limit(gpu: &Gpu) -> u64 {
    let limits = gpu.device.limits();
    limits.max_storage_buffer_binding_size.min(limits.max_buffer_size)
}

/// The resolve pipeline for one map format, with the layout of its storage-texture group.
pub(super) struct ResolvePipeline {
    pub(super) format: wgpu::TextureFormat,
    pub(super) map_layout: wgpu::BindGroupLayout,
    pub(super) pipeline: wgpu::ComputePipeline,
}

/// The atomic build's pipelines, made on first use.
pub(super) struct AtomicPipelines {
    pub(super) pass_layout: wgpu::BindGroupLayout,
    /// The count pipelines by [`CounterLayout::count_pipeline`].
    pub(super) count: [wgpu::RenderPipeline; 3],
    pub(super) resolve_layout: wgpu::BindGroupLayout,
    pub(super) resolve_module: wgpu::ShaderModule,
    /// Resolve pipelines by map format.
    pub(super) resolve: Vec<ResolvePipeline>,
    pub(super) uniforms: wgpu::Buffer,
}

/// The atomic build's buffers for one resolution, entry count and counter layout.
pub(super) struct AtomicBuffers {
    pub(super) resolution: u32,
    pub(super) entries: u32,
    pub(super) layout: CounterLayout,
    /// The band's counters in pages ([`CounterLayout`]).
    pub(super) counters: [wgpu::Buffer; COUNTER_PAGES],
    pub(super) carry: wgpu::Buffer,
    /// One u32 per texel: how many leading layers of the map are all zero.
    pub(super) zeros: wgpu::Buffer,
    /// Three u32 per texel: where the map's flat tail begins, the sum it holds, and this frame's so far
    /// (`layer_tails` in `shaders/layer_resolve.wgsl`).
    pub(super) tails: wgpu::Buffer,
    /// Whether the map was made after the tails were written (cleared before the next resolve: nothing known).
    pub(super) tails_stale: bool,
    /// The resolve's dispatches ([`resolve_dispatches`]), in order.
    pub(super) dispatches: Vec<ResolveDispatch>,
    /// Each dispatch's [`ResolvePart`], one per dynamic-offset step of `part_stride` bytes.
    pub(super) parts: wgpu::Buffer,
    pub(super) part_stride: u32,
    pub(super) null_target: NullTarget,
    pub(super) near: wgpu::TextureView,
    pub(super) far: wgpu::TextureView,
    pub(super) pass_bind_group: wgpu::BindGroup,
    /// The resolve's group 0 for each page.
    pub(super) resolve_bind_groups: Vec<wgpu::BindGroup>,
}

/// Mirrors `ResolvePart` in `shaders/layer_resolve.wgsl`: what one resolve dispatch covers, a run: the entries
/// `first..end` (whole layers; `end` at most the entry count), whose counters start at `offset` in their page.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ResolvePart {
    pub first: u32,
    pub end: u32,
    pub offset: u32,
    pub pad: u32,
}

/// Entries one resolve dispatch takes at most (16 layers). On lavapipe the dispatches of a 128-entry band
/// cost about 10 % less in runs of 64 than in one (docs/design.md); the running sum crosses runs as it crosses
/// bands.
pub const RESOLVE_RUN: u32 = 64;
/// Bytes per texel of the resolve's flat tails (`layer_tails` in `shaders/layer_resolve.wgsl`: three u32).
pub const TAIL_BYTES: u64 = 12;

/// One resolve dispatch: the band it belongs to (its first entry), the page its counters are in, and its part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolveDispatch {
    pub band_first: u32,
    pub page: usize,
    pub part: ResolvePart,
}

/// The resolve's dispatches for `entries` entries at `resolution`² laid out as `layout`, in the order they run:
/// per band, per run.
pub fn resolve_dispatches(entries: u32, resolution: u32, layout: CounterLayout) -> Vec<ResolveDispatch> {
    let texels = resolution as u64 * resolution as u64;
    let mut out = Vec::new();
    for band_first in (0..entries).step_by(layout.band as usize) {
        let band_end = (band_first + layout.band).min(entries);
        for (r, first) in (band_first..band_end).step_by(layout.run as usize).enumerate() {
            let r = r as u32;
            out.push(ResolveDispatch {
                band_first,
                page: (r / layout.runs_per_page) as usize,
                part: ResolvePart {
                    first,
                    end: (first + layout.run).min(band_end),
                    offset: ((r % layout.runs_per_page) as u64 * texels * layout.run as u64) as u32,
                    pad: 0,
                },
            });
        }
    }
    out
}

/// The WGSL mirror of [`ResolvePart`], for the layout test.
pub fn resolve_part_mirror() -> UniformMirror {
    crate::uniform_mirror!(
        "ResolvePart",
        ResolvePart {
            first,
            end,
            offset,
            pad
        }
    )
}

impl AtomicBuffers {
    pub(super) fn bytes(&self) -> u64 {
        self.counters.iter().map(wgpu::Buffer::size).sum::<u64>()
            + self.carry.size()
            + self.zeros.size()
            + self.tails.size()
            + self.parts.size()
            + self.null_target.bytes()
    }
}

/// The atomic build's bind-group layouts, count pipeline and resolve module.
pub(super) fn atomic_pipelines(
    ctx: &MethodContext,
    name: &str,
    module: &wgpu::ShaderModule,
    frame_layout: &wgpu::BindGroupLayout,
) -> AtomicPipelines {
    let device = &ctx.gpu.device;
    let frag = wgpu::ShaderStages::FRAGMENT;
    let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("hairlab.{name}.count_layout")),
        entries: &[
            uniform_entry(0, frag),
            texture_entry(1, frag, wgpu::TextureViewDimension::D2),
            texture_entry(2, frag, wgpu::TextureViewDimension::D2),
            storage_entry(3, frag, false),
            uniform_entry(4, frag),
            storage_entry(5, frag, false),
            storage_entry(6, frag, false),
            storage_entry(7, frag, false),
        ],
    });
    let count = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)].map(|(runs, paged)| {
        ctx.light.pipeline_with_constants(
            device,
            &format!("hairlab.{name}.count_pipeline"),
            &[frame_layout, &pass_layout],
            module,
            ("fs_count", &[("layer_runs", runs), ("layer_paged", paged)]),
            &[NullTarget::target_state()],
        )
    });
    let comp = wgpu::ShaderStages::COMPUTE;
    let part = wgpu::BindGroupLayoutEntry {
        binding: 6,
        visibility: comp,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<ResolvePart>() as u64),
        },
        count: None,
    };
    let resolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("hairlab.{name}.resolve_layout")),
        entries: &[
            uniform_entry(0, comp),
            storage_entry(1, comp, false),
            storage_entry(2, comp, false),
            texture_entry(3, comp, wgpu::TextureViewDimension::D2),
            texture_entry(4, comp, wgpu::TextureViewDimension::D2),
            storage_entry(5, comp, false),
            part,
            storage_entry(7, comp, false),
        ],
    });
    let resolve_module = crate::render::passes::shader_module(
        device,
        &format!("hairlab.{name}.resolve_shader"),
        "layer_resolve.wgsl",
        None,
    );
    AtomicPipelines {
        pass_layout,
        count,
        resolve_layout,
        resolve_module,
        resolve: Vec::new(),
        uniforms: uniform_buffer::<LayerBuildUniforms>(device, &format!("{name}.build_uniforms")),
    }
}

/// Texels of a row a resolve workgroup takes (`@workgroup_size(64)` in `shaders/layer_resolve.wgsl`): along the
/// row, so that the invocations of a workgroup write neighbouring texels of each layer (on lavapipe a third
/// faster than 8 × 8 squares).
pub(super) const RESOLVE_WORKGROUP: u32 = 64;

/// The resolve pipeline for maps of `format` (made on first use) and its storage-texture group's layout.
pub(super) fn resolve_pipeline<'a>(
    device: &wgpu::Device,
    name: &str,
    atomic: &'a mut AtomicPipelines,
    format: wgpu::TextureFormat,
) -> &'a ResolvePipeline {
    let i = match atomic.resolve.iter().position(|r| r.format == format) {
        Some(i) => i,
        None => {
            let map_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&format!("hairlab.{name}.resolve_map_layout")),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                }],
            });
            let entry = match format {
                wgpu::TextureFormat::Rgba16Float => "cs_resolve_f16",
                wgpu::TextureFormat::Rgba8Unorm => "cs_resolve_u8",
                _ => "cs_resolve_f32",
            };
            let pipeline = crate::render::pipelines::compute(
                device,
                &crate::render::pipelines::ComputePass {
                    label: &format!("hairlab.{name}.resolve_pipeline"),
                    module: &atomic.resolve_module,
                    entry,
                    layouts: &[&atomic.resolve_layout, &map_layout],
                },
            );
            atomic.resolve.push(ResolvePipeline {
                format,
                map_layout,
                pipeline,
            });
            atomic.resolve.len() - 1
        }
    };
    &atomic.resolve[i]
}

/// The counters (one band, in pages), the carry and the bind groups of the atomic build.
pub(super) fn atomic_buffers(
    ctx: &MethodContext,
    name: &str,
    atomic: &AtomicPipelines,
    method_uniforms: &wgpu::Buffer,
    (resolution, entries, layout): (u32, u32, CounterLayout),
) -> Result<AtomicBuffers, GpuError> {
    let gpu: &Gpu = ctx.gpu;
    let device = &gpu.device;
    let texels = resolution as u64 * resolution as u64;
    let pages = layout.page_bytes(resolution);
    let what = || format!("{name} counters of {} entries at {resolution}²", layout.band);
    check_budget(what, pages.iter().sum())?;
    for page in pages {
        gpu.check_buffer_size(&what(), page)?;
    }
    let storage = |label: &str, size: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(&format!("hairlab.{name}.{label}")),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    };
    let counters = pages.map(|bytes| storage("counters", bytes));
    let carry = storage("carry", texels * 4);
    // No texel's leading zero layers known: the first resolve writes whatever the map held before.
    let zeros = storage("zeros", texels * 4);
    // Nor any flat tail.
    let tails = storage("tails", texels * TAIL_BYTES);
    let part_stride = device.limits().min_uniform_buffer_offset_alignment;
    let dispatches = resolve_dispatches(entries, resolution, layout);
    let mut part_bytes = Vec::new();
    for d in &dispatches {
        part_bytes.extend_from_slice(bytemuck::bytes_of(&d.part));
        part_bytes.resize(part_bytes.len().next_multiple_of(part_stride as usize), 0);
    }
    let parts = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(&format!("hairlab.{name}.resolve_parts")),
        contents: &part_bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let (near, far) = (&ctx.light_maps.near_view, &ctx.light_maps.far_view);
    let pass_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(&format!("hairlab.{name}.count_bind_group")),
        layout: &atomic.pass_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: method_uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(near),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(far),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: counters[0].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: atomic.uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: counters[1].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: counters[2].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 7,
                resource: counters[3].as_entire_binding(),
            },
        ],
    });
    let resolve_group = |page: &wgpu::Buffer| {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("hairlab.{name}.resolve_bind_group")),
            layout: &atomic.resolve_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: atomic.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: page.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: carry.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(near),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(far),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: zeros.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &parts,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<ResolvePart>() as u64),
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: tails.as_entire_binding(),
                },
            ],
        })
    };
    let resolve_bind_groups = counters.iter().map(resolve_group).collect();
    Ok(AtomicBuffers {
        resolution,
        entries,
        layout,
        counters,
        carry,
        zeros,
        tails,
        tails_stale: false,
        dispatches,
        parts,
        part_stride,
        null_target: NullTarget::new(device, resolution),
        near: near.clone(),
        far: far.clone(),
        pass_bind_group,
        resolve_bind_groups,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_lie_in_runs_of_64_over_up_to_four_pages() {
        const MIB: u64 = 1 << 20;
        let layout = |res, entries| CounterLayout::new("layers", res, entries, 128 * MIB).unwrap();
        let l = |run, runs_per_page, band| CounterLayout {
            run,
            runs_per_page,
            band,
        };
        // OSM-256 at 512²: 1 MiB of counters per slice; runs of 64 slices (64 MiB), 2 per 128 MiB page, every
        // slice in one band (one geometry pass) over 2 pages.
        assert_eq!(layout(512, 256), l(64, 2, 256));
        assert_eq!(layout(512, 256).page_bytes(512), [128 * MIB, 128 * MIB, 4, 4]);
        // DOM-3: one run of 3 entries.
        assert_eq!(layout(512, 3), l(3, 42, 3));
        assert_eq!(layout(512, 3).page_bytes(512), [3 * MIB, 4, 4, 4]);
        // 100 entries: a run of 64 and one of 36 in one page.
        assert_eq!(layout(512, 100).page_bytes(512), [100 * MIB, 4, 4, 4]);
        // 1024²: 4 MiB per entry, runs of 32 (128 MiB), 4 pages: bands of 128, OSM-256 in two passes.
        assert_eq!(layout(1024, 256), l(32, 1, 128));
        // 2048²: 16 MiB per entry, runs of 8, bands of 32; 2896² the largest with runs of 4.
        assert_eq!(layout(2048, 256), l(8, 1, 32));
        assert_eq!(layout(2896, 16), l(4, 1, 16));
        let e = CounterLayout::new("layers", 4096, 16, 128 * MIB)
            .unwrap_err()
            .to_string();
        assert!(e.contains("build = atomic") && e.contains("4096²"), "{e}");
    }

    #[test]
    fn the_resolve_takes_each_run_from_its_page() {
        const MIB: u64 = 1 << 20;
        let d = |band_first, page, first, end, offset| ResolveDispatch {
            band_first,
            page,
            part: ResolvePart {
                first,
                end,
                offset,
                pad: 0,
            },
        };
        // OSM-256 at 512²: four runs of 64, two per page.
        let run = 512 * 512 * 64;
        let layout = CounterLayout::new("layers", 512, 256, 128 * MIB).unwrap();
        let expected = [
            d(0, 0, 0, 64, 0),
            d(0, 0, 64, 128, run),
            d(0, 1, 128, 192, 0),
            d(0, 1, 192, 256, run),
        ];
        assert_eq!(resolve_dispatches(256, 512, layout), expected);
        // 100 entries in bands of 40 (runs of 20, one per page, two pages): a band's runs, then the next band's.
        let layout = CounterLayout {
            run: 20,
            runs_per_page: 1,
            band: 40,
        };
        let got: Vec<_> = resolve_dispatches(100, 4, layout)
            .iter()
            .map(|d| (d.band_first, d.page, d.part.first, d.part.end, d.part.offset))
            .collect();
        let bands = [
            (0, 0, 0, 20, 0),
            (0, 1, 20, 40, 0),
            (40, 0, 40, 60, 0),
            (40, 1, 60, 80, 0),
        ];
        assert_eq!(got[..4], bands);
        assert_eq!(got[4..], [(80, 0, 80, 100, 0)]);
    }
}
