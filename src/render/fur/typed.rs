//! Hybrid fur's typed per-pixel lists (Andersen et al. 2016 §3.3 and §4; spec B.7): the guard hairs' shaded
//! fragments (explicit) and the shell pass's ray-marched fragments (shell, or virtual: one per group of march
//! steps) pushed onto the eye lists of the exact reference, then sorted and blended back to front by the
//! typed resolve (`shaders/fur/resolve.wgsl`, CPU model [`crate::fur::blend`]). The meshes are not stored:
//! they are drawn first, every list pass tests their depth by hand and their colour is what the resolve
//! blends onto (B.7; the paper stores base-mesh fragments, Table 1 row 5).
//!
//! Passes: the shell's count (the march run once to count what it emits) and the strands' count, one
//! readback, the node buffer sized to exactly the frame's fragments (bands of rows when they exceed a
//! binding), then per band the strands' fill, the shell's fill and the resolve. The renderer uses this
//! technique whenever the scene's fur is on; it is not one of the eye transparency registry's techniques
//! (none of those knows a shell), and with no shell fragments it equals the exact reference.

use std::collections::HashMap;

use crate::fur::blend::{self, Typed};
use crate::fur::march::MarchParams;
use crate::fur::settings::{Blending, FurSettings, FurView};
use crate::gpu::{Gpu, GpuError};
use crate::render::geometry::RIBBON_GROUP;
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role};
use crate::render::passes::abuffer::copy_out;
use crate::render::targets::EyeTargets;
use crate::render::transparency::sorted::{
    self, EyeNode, ListNames, NODE_BYTES, bind_group, layout_entry, plan_lists, record_resolve, storage,
};
use crate::render::transparency::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry, TechniqueInfo,
    TransparencyGpu,
};
use crate::transparency::{Compositor, ModelContext};

use super::shell_gpu::ShellGpu;

/// The guard hairs' fill: the exact reference's list push, on camera-facing ribbons (B.6).
static FILL: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[EyeTargets::NULL],
    depth: EntryDepth::Manual,
    geometry: HairGeometry::Ribbons,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "fur",
    label: "Fur: typed lists",
    paper: "Andersen, Falster, Frisvad, Christensen 2016, Hybrid fur rendering: combining volumetric fur with \
            explicit hair strands (§3.3, §4)",
    role: Role::Reference,
    hair_wgsl: "transparency/sorted.wgsl",
    hair_entries: std::slice::from_ref(&FILL),
    pass_wgsl: &["fur/ribbon_count.wgsl", "fur/resolve.wgsl"],
    params: &[ParamSpec {
        key: "band_kib",
        label: "band budget KiB",
        help: "most KiB of list nodes per band of rows (0: the device's storage binding limit)",
        kind: ParamKind::Int { min: 0, max: 4 << 20 },
        default: 0.0,
    }],
    color: [150, 95, 60],
    // f32 front-to-back sums in both; measured in tests/it/fur_typed.rs.
    gpu_tolerance: 1e-5,
};

/// The technique the renderer draws fur scenes with.
pub struct FurTechnique;

pub static FUR: FurTechnique = FurTechnique;

impl EyeTransparency for FurTechnique {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(FurGpu::new(setup)?))
    }

    /// Without a shell the typed lists hold strand fragments only and every blending is the exact composite.
    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::exact::ExactParams)
    }
}

/// What a fur frame adds to an [`EyeFrame`]: the shell's GPU state, the settings and the march of this frame.
pub struct FurFrame<'a> {
    pub shell: &'a ShellGpu,
    pub settings: &'a FurSettings,
    pub march: MarchParams,
}

/// Mirrors `FurResolveUniforms` in `shaders/fur/resolve.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable, PartialEq)]
pub struct FurResolveUniforms {
    pub blending: u32,
    pub attenuation: f32,
    pub view: u32,
    pub deepest: u32,
}

/// `FurResolveUniforms`' fields and offsets (a test compares them with the WGSL struct).
pub const FUR_RESOLVE_UNIFORMS_FIELDS: &[(&str, usize)] = &[
    ("blending", std::mem::offset_of!(FurResolveUniforms, blending)),
    (
        "attenuation",
        std::mem::offset_of!(FurResolveUniforms, attenuation),
    ),
    ("view", std::mem::offset_of!(FurResolveUniforms, view)),
    ("deepest", std::mem::offset_of!(FurResolveUniforms, deepest)),
];

fn view_code(v: FurView) -> u32 {
    match v {
        FurView::Shaded => 0,
        FurView::Types => 1,
        FurView::Fragments => 2,
    }
}

fn blending_code(b: Blending) -> u32 {
    match b {
        Blending::Naive => 0,
        Blending::Simplified => 1,
        Blending::Virtual => 2,
    }
}

/// The guard hairs' count pass over their ribbons (`fur/ribbon_count.wgsl`): group 0 the frame, group 1 the
/// counts and the meshes' depth ([`sorted::count_layout`]), [`RIBBON_GROUP`] the strands.
fn ribbon_count_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
    count_layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let module =
        crate::render::passes::shader_module(device, "hairlab.fur.ribbon_count", INFO.pass_wgsl[0], None);
    let ribbons = crate::render::geometry::ribbon_layout(device);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("hairlab.fur.ribbon_count"),
        bind_group_layouts: &[Some(frame_layout), Some(count_layout), None, Some(&ribbons)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("hairlab.fur.ribbon_count"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        // Ribbons face the camera but their winding follows the strand: no culling, as the fill.
        primitive: wgpu::PrimitiveState::default(),
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

/// The last frame's list figures, by fragment type (Table 1 rows 4 and 6).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FurListStats {
    /// Explicit (guard-hair) fragments.
    pub explicit: u64,
    /// Shell or virtual fragments.
    pub shell: u64,
    /// The deepest pixel's list.
    pub deepest: u32,
    /// Bands of rows the frame was filled and resolved in.
    pub bands: u32,
    /// Bytes of the largest band's nodes.
    pub node_bytes: u64,
}

struct Lists {
    width: u32,
    height: u32,
    counts: wgpu::Buffer,
    heads: wgpu::Buffer,
    nodes: wgpu::Buffer,
    capacity: u64,
    counters: wgpu::Buffer,
}

impl Lists {
    fn new(gpu: &Gpu, width: u32, height: u32, capacity: u64) -> Result<Lists, GpuError> {
        let device = &gpu.device;
        let pixels = width as u64 * height as u64;
        gpu.check_buffer_size(&format!("fur lists' pixel heads at {width}x{height}"), pixels * 4)?;
        gpu.check_buffer_size(
            &format!("fur lists' nodes at {width}x{height}"),
            capacity * NODE_BYTES,
        )?;
        Ok(Lists {
            width,
            height,
            counts: storage(device, "hairlab.fur.counts", (pixels + 1) * 4),
            heads: storage(device, "hairlab.fur.heads", pixels * 4),
            nodes: storage(device, "hairlab.fur.nodes", capacity.max(1) * NODE_BYTES),
            capacity: capacity.max(1),
            counters: storage(device, "hairlab.fur.counters", 8),
        })
    }
}

pub struct FurGpu {
    count_layout: wgpu::BindGroupLayout,
    count_pipeline: wgpu::RenderPipeline,
    fill_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
    frame_layout: wgpu::BindGroupLayout,
    resolves: HashMap<(u32, wgpu::TextureFormat), wgpu::RenderPipeline>,
    uniforms: wgpu::Buffer,
    /// The shell count's total, copied before the strands add theirs.
    shell_total: wgpu::Buffer,
    lists: Lists,
    bands: Vec<(u32, u32)>,
    stats: FurListStats,
}

impl FurGpu {
    fn new(setup: &EyeSetup) -> Result<FurGpu, GpuError> {
        let device = &setup.gpu.device;
        let count_layout = sorted::count_layout(device);
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let resolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.fur.resolve_layout"),
            entries: &[
                layout_entry(0, fragment, true),
                layout_entry(1, fragment, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: fragment,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        Ok(FurGpu {
            count_pipeline: ribbon_count_pipeline(device, setup.frame_layout, &count_layout),
            count_layout,
            fill_layout: sorted::fill_layout(device),
            resolve_layout,
            frame_layout: setup.frame_layout.clone(),
            resolves: HashMap::new(),
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("hairlab.fur.resolve_uniforms"),
                size: std::mem::size_of::<FurResolveUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            shell_total: storage(device, "hairlab.fur.shell_total", 4),
            lists: Lists::new(setup.gpu, setup.width, setup.height, 1)?,
            bands: Vec::new(),
            stats: FurListStats::default(),
        })
    }

    /// The last frame's list figures.
    pub fn stats(&self) -> FurListStats {
        self.stats
    }

    /// The last frame's typed lists (row-major, each front to back in the resolve's order).
    pub fn typed_lists(&self, gpu: &Gpu) -> Result<Vec<Vec<Typed>>, GpuError> {
        if self.bands.len() > 1 {
            return Err(GpuError::Readback(format!(
                "the fur lists of this frame were built in {} bands; only one band can be read back",
                self.bands.len()
            )));
        }
        let l = &self.lists;
        let counters: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.counters)?);
        if counters[1] > 0 {
            return Err(GpuError::Readback(format!(
                "fur lists overflow: {} fragments did not fit in {} nodes",
                counters[1], l.capacity
            )));
        }
        let heads: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.heads)?);
        let nodes: Vec<EyeNode> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &l.nodes)?);
        let used = (counters[0] as usize).min(nodes.len());
        Ok(heads
            .iter()
            .map(|&head| {
                let mut out = Vec::new();
                let mut i = head as usize;
                while i != 0 && i <= used && out.len() <= used {
                    let n = nodes[i - 1];
                    out.push(Typed {
                        depth: n.depth,
                        id: n.segment,
                        kind: n.kind,
                        colour: glam::Vec3::new(n.r, n.g, n.b),
                        alpha: n.alpha,
                    });
                    i = n.next as usize;
                }
                blend::front_to_back(&mut out);
                out
            })
            .collect())
    }

    fn resolve_pipeline(&mut self, device: &wgpu::Device, size: u32, format: wgpu::TextureFormat) {
        let layouts = [&self.frame_layout, &self.resolve_layout];
        self.resolves.entry((size, format)).or_insert_with(|| {
            sorted::list_resolve_pipeline(device, INFO.pass_wgsl[1], size, &layouts, format)
        });
    }
}

impl TransparencyGpu for FurGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (self.lists.width, self.lists.height) != (width, height) {
            self.lists = Lists::new(gpu, width, height, self.lists.capacity)?;
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let Some(fur) = frame.fur.take() else {
            return Err(GpuError::Setting(
                "fur.mode: the fur lists were asked for a frame without a fur shell".into(),
            ));
        };
        let (width, height) = (self.lists.width, self.lists.height);
        let pixels = width as u64 * height as u64;
        let mode = fur.settings.mode;
        let strands = mode.strands() && frame.geometry.hair_index_count > 0;
        let shell = mode.shell();
        let gpu = frame.gpu;
        fur.shell.set_params(&gpu.queue, &fur.march);
        // Counts: the shell's first (its total copied aside), then the strands'.
        frame.encoder.clear_buffer(&self.lists.counts, 0, None);
        fur.shell.reset_stats(&mut frame.encoder);
        if shell {
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::FurShell, "fur: shell count"));
            fur.shell.record_count(
                gpu,
                &mut frame.encoder,
                frame.frame_bind_group,
                &self.lists.counts,
                &frame.targets.depth_view,
                &frame.targets.null_view,
                timestamps,
                None,
            );
        }
        frame
            .encoder
            .copy_buffer_to_buffer(&self.lists.counts, pixels * 4, &self.shell_total, 0, 4);
        if strands {
            let ribbons = frame.geometry.ribbons()?;
            let count_group = bind_group(
                &gpu.device,
                "hairlab.fur.count_group",
                &self.count_layout,
                &[&self.lists.counts],
                Some(&frame.targets.depth_view),
            );
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::EyeHair, "fur: explicit count"));
            let mut pass = frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlab.fur.count_pass"),
                color_attachments: &[frame.targets.null_attachment()],
                depth_stencil_attachment: None,
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.count_pipeline);
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            pass.set_bind_group(1, &count_group, &[]);
            pass.set_bind_group(RIBBON_GROUP, ribbons, &[]);
            pass.draw(0..frame.geometry.ribbon_vertex_count(), 0..1);
        }
        frame.flush();
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.lists.counts)?);
        let shell_total: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.shell_total)?);
        let plan = plan_lists(
            gpu,
            &counts,
            (width, height),
            crate::render::method::value(frame.values, &INFO.params[0]) as u64 * 1024,
            &ListNames {
                deep: "fur.group_steps: the fur lists",
                rows: "the fur lists'",
                drawn: String::new(),
            },
        )?;
        let (size, needed, deepest, total) = (plan.size, plan.needed, plan.deepest, plan.fragments);
        self.bands = plan.bands;
        if needed > self.lists.capacity || needed < self.lists.capacity / 2 {
            self.lists = Lists::new(gpu, width, height, needed)?;
        }
        gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&FurResolveUniforms {
                blending: blending_code(fur.settings.blending),
                attenuation: fur.settings.attenuation_per_unit(),
                view: view_code(fur.settings.view),
                deepest,
            }),
        );
        self.stats = FurListStats {
            explicit: total - u64::from(shell_total[0]),
            shell: u64::from(shell_total[0]),
            deepest,
            bands: self.bands.len() as u32,
            node_bytes: needed * NODE_BYTES,
        };
        let l = &self.lists;
        let fill_group = bind_group(
            &gpu.device,
            "hairlab.fur.fill_group",
            &self.fill_layout,
            &[&l.heads, &l.nodes, &l.counters],
            Some(&frame.targets.depth_view),
        );
        let resolve_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.fur.resolve_group"),
            layout: &self.resolve_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: l.heads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: l.nodes.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.uniforms.as_entire_binding(),
                },
            ],
        });
        let format = frame.output.1;
        self.resolve_pipeline(&gpu.device, size, format);
        let resolve = &self.resolves[&(size, format)];
        for &(y0, y1) in &self.bands {
            frame.encoder.clear_buffer(&self.lists.heads, 0, None);
            frame.encoder.clear_buffer(&self.lists.counters, 0, None);
            if strands {
                let null = [frame.targets.null_attachment()];
                frame.draw_hair(
                    HairDrawPass {
                        entry: &FILL,
                        attachments: &null,
                        depth: None,
                        group: Some((&self.fill_layout, &fill_group)),
                        rows: Some((y0, y1)),
                    },
                    "fur: explicit fill",
                );
            }
            if shell {
                let timestamps = frame
                    .timer
                    .as_mut()
                    .and_then(|t| t.pass(crate::gpu::timing::Phase::FurShell, "fur: shell fill"));
                fur.shell.record_fill(
                    gpu,
                    &mut frame.encoder,
                    frame.frame_bind_group,
                    &self.lists.heads,
                    &self.lists.nodes,
                    &self.lists.counters,
                    &frame.targets.depth_view,
                    &frame.targets.null_view,
                    timestamps,
                    Some((y0, y1)),
                );
            }
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::Resolve, "fur: resolve"));
            record_resolve(
                &mut frame.encoder,
                frame.output.0,
                timestamps,
                (width, y0, y1),
                resolve,
                [frame.frame_bind_group, &resolve_group],
            );
        }
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let l = &self.lists;
        l.counts.size() + l.heads.size() + l.nodes.size() + l.counters.size() + self.uniforms.size()
    }

    fn geometry_passes(&self) -> u32 {
        1 + self.bands.len().max(1) as u32
    }

    fn depth_complexity(&self) -> Option<(u32, u64)> {
        Some((self.stats.deepest, self.stats.explicit + self.stats.shell))
    }
}
