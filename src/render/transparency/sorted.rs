//! The exact eye transparency reference: per-pixel fragment lists (Carpenter 1984's A-buffer, built as the
//! linked lists of Yang et al. 2010), sorted on (depth, segment) so that depth ties keep a total order, and
//! composited back to front onto the opaque image. Three passes: a count pass (the fragments per pixel, read
//! back so the node buffer holds exactly the frame's fragments), the shaded fill pass, and the resolve, which
//! gathers each pixel's nodes into private arrays of the smallest of [`SORT_SIZES`] that holds its list (the sort
//! instantiated for every size up to the frame's deepest pixel, [`resolve_source`]) and merge-sorts them. When the nodes exceed the storage binding limit the
//! frame is filled and resolved in horizontal bands of rows; a single row over the limit is an error naming the
//! viewport. Memory: 4 B/px heads + 4 B/px counts + 32 B per fragment of the largest band.

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, PREMULTIPLIED_OVER,
    TechniqueInfo, TransparencyGpu,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::geometry::HairVertex;
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role};
use crate::render::passes::abuffer::copy_out;
use crate::render::targets::EyeTargets;
use crate::transparency::{Compositor, EyeFragment, ModelContext};
use std::collections::HashMap;

/// Bytes of one list node (`common/eye_node.wgsl`).
pub const NODE_BYTES: u64 = 32;

/// The resolve's private sort sizes; a pixel deeper than the last is refused.
pub const SORT_SIZES: [u32; 6] = [16, 64, 128, 256, 512, 1024];

static FILL: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[EyeTargets::NULL],
    depth: EntryDepth::Manual,
    geometry: super::HairGeometry::Lines,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "sorted",
    label: "Sorted (exact)",
    paper: "Carpenter 1984, The A-buffer; lists as Yang et al. 2010, Real-time concurrent linked list construction",
    role: Role::Reference,
    hair_wgsl: "transparency/sorted.wgsl",
    hair_entries: std::slice::from_ref(&FILL),
    pass_wgsl: &[
        "transparency/sorted_count.wgsl",
        "transparency/sorted_resolve.wgsl",
    ],
    params: &[ParamSpec {
        key: "band_kib",
        label: "band budget KiB",
        help: "most KiB of list nodes per band of rows (0: the device's storage binding limit); a smaller budget \
               renders the same image in more bands",
        kind: ParamKind::Int { min: 0, max: 4 << 20 },
        default: 0.0,
    }],
    color: [0, 0, 0],
    // f32 front-to-back sums against the model's back-to-front ones; measured 1.2e-7 on lavapipe.
    gpu_tolerance: 1e-5,
};

pub struct Sorted;

impl EyeTransparency for Sorted {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(SortedGpu::new(setup)?))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::exact::ExactParams)
    }
}

/// The resolve `path` (this one's, or another list technique's written on the same template) with its sort
/// instantiated for each of [`SORT_SIZES`] up to `max`, each pixel dispatched to the smallest that holds its
/// list.
pub fn resolve_source(path: &str, max: u32) -> Result<String, String> {
    let src = crate::shaders::compose(path, None)?;
    let part = |a: &str, b: &str| -> Result<(usize, usize), String> {
        let start = src.find(a).ok_or_else(|| format!("{path}: no '{a}'"))?;
        let end = src[start..].find(b).ok_or_else(|| format!("{path}: no '{b}'"))? + start;
        Ok((start, end))
    };
    let (t0, t1) = part("// template begin", "// template end")?;
    let template = &src[t0 + "// template begin".len()..t1];
    let sizes: Vec<u32> = SORT_SIZES
        .iter()
        .copied()
        .filter(|&s| s <= max.max(SORT_SIZES[0]))
        .collect();
    let sorts: String = sizes
        .iter()
        .map(|s| {
            template
                .replace("_64", &format!("_{s}"))
                .replace("64u", &format!("{s}u"))
        })
        .collect();
    let (d0, d1) = part("return resolve_64(", "// dispatch")?;
    let largest = sizes[sizes.len() - 1];
    let mut dispatch: String = sizes[..sizes.len() - 1]
        .iter()
        .map(|s| format!("if n <= {s}u {{ return resolve_{s}(head, n); }}\n    "))
        .collect();
    dispatch.push_str(&format!("return resolve_{largest}(head, min(n, {largest}u));"));
    Ok(format!(
        "{}{sorts}{}{dispatch}{}",
        &src[..t0],
        &src[t1 + "// template end".len()..d0],
        &src[d1 + "// dispatch".len()..]
    ))
}

pub(crate) fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

pub(crate) fn layout_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(crate) const MESH_DEPTH: wgpu::BindingType = wgpu::BindingType::Texture {
    sample_type: wgpu::TextureSampleType::Depth,
    view_dimension: wgpu::TextureViewDimension::D2,
    multisampled: false,
};

/// A bind group over `buffers` at bindings 0.., and the meshes' depth after them when given.
pub(crate) fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
    mesh_depth: Option<&wgpu::TextureView>,
) -> wgpu::BindGroup {
    let mut entries: Vec<_> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    if let Some(view) = mesh_depth {
        entries.push(wgpu::BindGroupEntry {
            binding: buffers.len() as u32,
            resource: wgpu::BindingResource::TextureView(view),
        });
    }
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// Group 1 of the count pass: the per-pixel counts and the meshes' depth.
pub(crate) fn count_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hairlab.sorted.count_layout"),
        entries: &[
            layout_entry(0, fragment, false),
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: fragment,
                ty: MESH_DEPTH,
                count: None,
            },
        ],
    })
}

/// Group 2 of the fill pass (`sorted.wgsl`): heads, nodes, counters and the meshes' depth.
pub(crate) fn fill_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hairlab.sorted.fill_layout"),
        entries: &[
            layout_entry(0, fragment, false),
            layout_entry(1, fragment, false),
            layout_entry(2, fragment, false),
            wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: fragment,
                ty: MESH_DEPTH,
                count: None,
            },
        ],
    })
}

/// The count pass over the strands (`sorted_count.wgsl`): group 0 the frame, group 1 [`count_layout`]'s.
pub(crate) fn count_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
    count_layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let module =
        crate::render::passes::shader_module(device, "hairlab.sorted.count_shader", INFO.pass_wgsl[0], None);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("hairlab.sorted.count_pipeline_layout"),
        bind_group_layouts: &[Some(frame_layout), Some(count_layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("hairlab.sorted.count_pipeline"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(HairVertex::layout())],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::LineList,
            ..Default::default()
        },
        // The meshes are tested by hand (`common/mesh_depth.wgsl`), before the count's side effects.
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(EyeTargets::NULL)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A list resolve `path` (instantiated by [`resolve_source`] up to `size`) drawn full screen and blended
/// premultiplied over `format`'s image; groups 0 and 1 from `layouts`.
pub(crate) fn list_resolve_pipeline(
    device: &wgpu::Device,
    path: &str,
    size: u32,
    layouts: &[&wgpu::BindGroupLayout; 2],
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let src = resolve_source(path, size).unwrap_or_else(|e| panic!("{e}"));
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(path),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(path),
        bind_group_layouts: &layouts.map(Some),
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(path),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: Some(PREMULTIPLIED_OVER),
                write_mask: if format == EyeTargets::COLOR {
                    wgpu::ColorWrites::COLOR
                } else {
                    wgpu::ColorWrites::ALL
                },
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// How a list technique's errors name it: the key and owner of a too-deep pixel (`"<key>: the <owner>"`), the
/// owner of a row over the band budget, and what was drawn (appended to the row's figures).
pub(crate) struct ListNames {
    pub deep: &'static str,
    pub rows: &'static str,
    pub drawn: String,
}

/// A frame's lists as its counts size them: the sort size of its deepest pixel, its bands of rows, the nodes of
/// the largest band, the deepest pixel and the fragments in all.
pub(crate) struct ListPlan {
    pub size: u32,
    pub bands: Vec<(u32, u32)>,
    pub needed: u64,
    pub deepest: u32,
    pub fragments: u64,
}

/// Plans a `width`×`height` frame's lists from its per-pixel `counts` (the total at `[W·H]`): refuses a pixel
/// deeper than the last of [`SORT_SIZES`] and a row over the band budget (`budget` bytes, 0: the device's
/// binding), each naming the view, the figures and the key.
pub(crate) fn plan_lists(
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

/// Records a list resolve over rows `[y0, y1)` of a `width`-wide `output`, loaded and blended onto: groups 0
/// and 1 from `groups`.
pub(crate) fn record_resolve(
    encoder: &mut wgpu::CommandEncoder,
    output: &wgpu::TextureView,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    (width, y0, y1): (u32, u32, u32),
    pipeline: &wgpu::RenderPipeline,
    groups: [&wgpu::BindGroup; 2],
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("hairlab.lists.resolve_pass"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: output,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if y1 > y0 {
        pass.set_scissor_rect(0, y0, width, y1 - y0);
        pass.set_pipeline(pipeline);
        for (i, g) in groups.into_iter().enumerate() {
            pass.set_bind_group(i as u32, g, &[]);
        }
        pass.draw(0..3, 0..1);
    }
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

/// Viewport-sized buffers and the bind groups over them.
struct Lists {
    width: u32,
    height: u32,
    /// Per-pixel counts, and the total at [W·H].
    counts: wgpu::Buffer,
    heads: wgpu::Buffer,
    nodes: wgpu::Buffer,
    capacity: u64,
    counters: wgpu::Buffer,
    resolve_group: wgpu::BindGroup,
}

pub struct SortedGpu {
    count_layout: wgpu::BindGroupLayout,
    fill_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
    count_pipeline: wgpu::RenderPipeline,
    /// Resolve pipelines by (sort size, output format).
    resolves: HashMap<(u32, wgpu::TextureFormat), wgpu::RenderPipeline>,
    frame_layout: wgpu::BindGroupLayout,
    lists: Lists,
    /// The last frame's bands, its deepest pixel and its fragment count.
    bands: Vec<(u32, u32)>,
    deepest: u32,
    fragments: u64,
}

impl SortedGpu {
    fn new(setup: &EyeSetup) -> Result<SortedGpu, GpuError> {
        let device = &setup.gpu.device;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let count_layout = count_layout(device);
        let fill_layout = fill_layout(device);
        let resolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.sorted.resolve_layout"),
            entries: &[layout_entry(0, fragment, true), layout_entry(1, fragment, true)],
        });
        let count_pipeline = count_pipeline(device, setup.frame_layout, &count_layout);
        let mut gpu = SortedGpu {
            lists: Lists::new(setup.gpu, &resolve_layout, setup.width, setup.height, 1)?,
            count_layout,
            fill_layout,
            resolve_layout,
            count_pipeline,
            resolves: HashMap::new(),
            frame_layout: setup.frame_layout.clone(),
            bands: Vec::new(),
            deepest: 0,
            fragments: 0,
        };
        gpu.resize(setup.gpu, setup.width, setup.height)?;
        Ok(gpu)
    }

    fn resolve_pipeline(&mut self, device: &wgpu::Device, size: u32, format: wgpu::TextureFormat) {
        let (frame_layout, resolve_layout) = (&self.frame_layout, &self.resolve_layout);
        self.resolves.entry((size, format)).or_insert_with(|| {
            list_resolve_pipeline(
                device,
                INFO.pass_wgsl[1],
                size,
                &[frame_layout, resolve_layout],
                format,
            )
        });
    }

    fn lists(&self, gpu: &Gpu) -> Result<Vec<Vec<EyeFragment>>, GpuError> {
        if self.bands.len() > 1 {
            return Err(GpuError::Readback(format!(
                "the eye lists of this frame were built in {} bands; only one band can be read back",
                self.bands.len()
            )));
        }
        let l = &self.lists;
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.counters)?);
        if counters[1] > 0 {
            return Err(GpuError::Readback(format!(
                "eye lists overflow: {} fragments did not fit in {} nodes",
                counters[1], l.capacity
            )));
        }
        let heads: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.heads)?);
        let nodes: Vec<EyeNode> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.nodes)?);
        let used = (counters[0] as usize).min(nodes.len());
        let lists = heads
            .iter()
            .map(|&head| {
                let mut out = Vec::new();
                let mut i = head as usize;
                while i != 0 && i <= used && out.len() <= used {
                    let n = nodes[i - 1];
                    out.push(EyeFragment {
                        depth: n.depth,
                        segment: n.segment,
                        color: [n.r, n.g, n.b],
                        alpha: n.alpha,
                    });
                    i = n.next as usize;
                }
                crate::transparency::front_to_back(&out)
            })
            .collect();
        Ok(lists)
    }
}

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

impl Lists {
    fn new(
        gpu: &Gpu,
        resolve_layout: &wgpu::BindGroupLayout,
        width: u32,
        height: u32,
        capacity: u64,
    ) -> Result<Lists, GpuError> {
        let device = &gpu.device;
        let pixels = width as u64 * height as u64;
        gpu.check_buffer_size(&format!("eye lists' pixel heads at {width}x{height}"), pixels * 4)?;
        gpu.check_buffer_size(
            &format!("eye lists' nodes at {width}x{height}"),
            capacity * NODE_BYTES,
        )?;
        let counts = storage(device, "hairlab.sorted.counts", (pixels + 1) * 4);
        let heads = storage(device, "hairlab.sorted.heads", pixels * 4);
        let nodes = storage(device, "hairlab.sorted.nodes", capacity.max(1) * NODE_BYTES);
        let counters = storage(device, "hairlab.sorted.counters", 8);
        Ok(Lists {
            resolve_group: bind_group(
                device,
                "hairlab.sorted.resolve_group",
                resolve_layout,
                &[&heads, &nodes],
                None,
            ),
            width,
            height,
            counts,
            heads,
            nodes,
            capacity: capacity.max(1),
            counters,
        })
    }
}

impl TransparencyGpu for SortedGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (self.lists.width, self.lists.height) != (width, height) {
            self.lists = Lists::new(gpu, &self.resolve_layout, width, height, self.lists.capacity)?;
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let (width, height) = (self.lists.width, self.lists.height);
        // Pass 1: count.
        let device = &frame.gpu.device;
        let mesh_depth = Some(&frame.targets.depth_view);
        let count_group = bind_group(
            device,
            "hairlab.sorted.count_group",
            &self.count_layout,
            &[&self.lists.counts],
            mesh_depth,
        );
        frame.encoder.clear_buffer(&self.lists.counts, 0, None);
        {
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::EyeHair, "eye: count"));
            let mut pass = frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlab.sorted.count_pass"),
                color_attachments: &[frame.targets.null_attachment()],
                depth_stencil_attachment: None,
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if frame.geometry.hair_index_count > 0 {
                pass.set_pipeline(&self.count_pipeline);
                pass.set_bind_group(0, frame.frame_bind_group, &[]);
                pass.set_bind_group(1, &count_group, &[]);
                pass.set_vertex_buffer(0, frame.geometry.hair_vertices.slice(..));
                pass.set_index_buffer(frame.geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..frame.geometry.hair_index_count, 0, 0..1);
            }
        }
        frame.flush();
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(frame.gpu, &self.lists.counts)?);
        let plan = plan_lists(
            frame.gpu,
            &counts,
            (width, height),
            crate::render::method::value(frame.values, &INFO.params[0]) as u64 * 1024,
            &ListNames {
                deep: "transparency.name: the exact reference",
                rows: "the exact eye reference's",
                drawn: format!(", {} segments drawn", frame.geometry.hair_index_count / 2),
            },
        )?;
        self.fragments = plan.fragments;
        self.deepest = plan.deepest;
        self.bands = plan.bands;
        let (size, needed) = (plan.size, plan.needed);
        if needed > self.lists.capacity || needed < self.lists.capacity / 2 {
            self.lists = Lists::new(frame.gpu, &self.resolve_layout, width, height, needed)?;
        }
        let l = &self.lists;
        let fill_group = bind_group(
            &frame.gpu.device,
            "hairlab.sorted.fill_group",
            &self.fill_layout,
            &[&l.heads, &l.nodes, &l.counters],
            Some(&frame.targets.depth_view),
        );
        let format = frame.output.1;
        self.resolve_pipeline(&frame.gpu.device, size, format);
        let resolve = &self.resolves[&(size, format)];
        for &(y0, y1) in &self.bands.clone() {
            frame.encoder.clear_buffer(&self.lists.heads, 0, None);
            frame.encoder.clear_buffer(&self.lists.counters, 0, None);
            let null = [frame.targets.null_attachment()];
            frame.draw_hair(
                HairDrawPass {
                    entry: &FILL,
                    attachments: &null,
                    depth: None,
                    group: Some((&self.fill_layout, &fill_group)),
                    rows: Some((y0, y1)),
                },
                "eye: fill",
            );
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::Resolve, "eye: resolve"));
            record_resolve(
                &mut frame.encoder,
                frame.output.0,
                timestamps,
                (width, y0, y1),
                resolve,
                [frame.frame_bind_group, &self.lists.resolve_group],
            );
        }
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let l = &self.lists;
        l.counts.size() + l.heads.size() + l.nodes.size() + l.counters.size()
    }

    fn geometry_passes(&self) -> u32 {
        1 + self.bands.len().max(1) as u32
    }

    fn read_lists(&self, gpu: &Gpu) -> Option<Result<Vec<Vec<EyeFragment>>, GpuError>> {
        Some(self.lists(gpu))
    }

    fn depth_complexity(&self) -> Option<(u32, u64)> {
        Some((self.deepest, self.fragments))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_resolve_instantiates_one_sort_per_size_up_to_the_deepest_pixel() {
        let src = resolve_source(INFO.pass_wgsl[1], 256).unwrap();
        for s in [16, 64, 128, 256] {
            assert!(src.contains(&format!("fn resolve_{s}(")), "{s}");
            assert!(src.contains(&format!("array<Key, {s}u>")), "{s}");
        }
        assert!(!src.contains("fn resolve_512("));
        assert!(src.contains("if n <= 128u { return resolve_128(head, n); }"));
        assert!(src.contains("return resolve_256(head, min(n, 256u));"));
        assert!(!src.contains("// template begin") && !src.contains("// template end"));
        let small = resolve_source(INFO.pass_wgsl[1], 1).unwrap();
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
