//! Camera-facing ribbons (spec B.6; Andersen et al. 2016's "camera-facing geometry" for guard hairs) on
//! lavapipe, through a test-only technique: a count pass drawing `eye_ribbon_point` (`common/eye_vertex.wgsl`)
//! the way a technique's own pass would, and a shaded hair pass of a `HairGeometry::Ribbons` entry (the exact
//! reference's list fill, `transparency/sorted.wgsl`, drawn through `vs_ribbon`) pushing every fragment onto
//! per-pixel lists. Both must see exactly the same fragments per pixel; a segment of a known width must cover
//! the hand-computed pixel span, a thinner one one pixel with its alpha scaled by the covered fraction.

use crate::common::small_settings;
use crate::transparency_gpu::eye_frame;
use glam::Vec3;
use hairlab::gpu::readback::copy_out;
use hairlab::gpu::{Gpu, GpuError};
use hairlab::render::Renderer;
use hairlab::render::geometry::RIBBON_GROUP;
use hairlab::render::method::{ParamValues, Role};
use hairlab::render::targets::EyeTargets;
use hairlab::render::transparency::sorted::EyeNode;
use hairlab::render::transparency::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry, TechniqueInfo,
    TransparencyGpu, registry,
};
use hairlab::scene::{Scene, Strands};
use hairlab::settings::Settings;
use hairlab::transparency::{Compositor, ModelContext};
use std::any::Any;

static FILL: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[EyeTargets::NULL],
    depth: EntryDepth::Manual,
    geometry: HairGeometry::Ribbons,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "ribbon-probe",
    label: "Ribbon probe (test only)",
    paper: "Andersen et al. 2016, Hybrid fur rendering (camera-facing strands)",
    role: Role::Reference,
    hair_wgsl: "transparency/sorted.wgsl",
    hair_entries: std::slice::from_ref(&FILL),
    pass_wgsl: &["transparency/sorted_count.wgsl"],
    params: &[],
    color: [1, 2, 3],
    gpu_tolerance: 0.0,
};

/// The count pass's vertex entry, appended to the exact reference's count pass: what a technique's own ribbon
/// pass writes.
const COUNT_VERTEX: &str = "
@vertex
fn vs_ribbon_count(@builtin(vertex_index) index: u32) -> EyePoint {
    return eye_ribbon_point(index);
}
";

struct Probe;

impl EyeTransparency for Probe {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(ProbeGpu::new(setup)))
    }

    fn model(&self, values: &ParamValues, ctx: &ModelContext) -> Box<dyn Compositor> {
        registry::reference().model(values, ctx)
    }
}

static PROBE: Probe = Probe;

fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A layout of `buffers` read-write storage buffers and the meshes' depth after them (the sorted passes').
fn layout(device: &wgpu::Device, buffers: u32) -> wgpu::BindGroupLayout {
    let mut entries: Vec<_> = (0..buffers)
        .map(|binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: buffers,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    });
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &entries,
    })
}

fn group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
    depth: &wgpu::TextureView,
) -> wgpu::BindGroup {
    let mut entries: Vec<_> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    entries.push(wgpu::BindGroupEntry {
        binding: buffers.len() as u32,
        resource: wgpu::BindingResource::TextureView(depth),
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

struct ProbeGpu {
    pixels: u64,
    frame_layout: wgpu::BindGroupLayout,
    count_layout: wgpu::BindGroupLayout,
    fill_layout: wgpu::BindGroupLayout,
    count_pipeline: Option<wgpu::RenderPipeline>,
    /// The count pass's fragments per pixel, and the total at [W·H].
    counts: wgpu::Buffer,
    heads: wgpu::Buffer,
    nodes: wgpu::Buffer,
    /// [0] nodes pushed, [1] fragments that did not fit.
    counters: wgpu::Buffer,
}

impl ProbeGpu {
    fn new(setup: &EyeSetup) -> ProbeGpu {
        let device = &setup.gpu.device;
        let pixels = setup.width as u64 * setup.height as u64;
        ProbeGpu {
            pixels,
            frame_layout: setup.frame_layout.clone(),
            count_layout: layout(device, 1),
            fill_layout: layout(device, 3),
            count_pipeline: None,
            counts: storage(device, "probe.counts", (pixels + 1) * 4),
            heads: storage(device, "probe.heads", pixels * 4),
            nodes: storage(device, "probe.nodes", 32),
            counters: storage(device, "probe.counters", 8),
        }
    }

    /// The count pipeline: the reference's count fragment entry behind `vs_ribbon_count`, a non-indexed
    /// TriangleList with the ribbon storage at [`RIBBON_GROUP`].
    fn count_pipeline(
        &self,
        device: &wgpu::Device,
        ribbon_layout: &wgpu::BindGroupLayout,
    ) -> wgpu::RenderPipeline {
        let src = hairlab::shaders::compose(INFO.pass_wgsl[0], None).unwrap() + COUNT_VERTEX;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("probe.count_shader"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let mut layouts = vec![Some(&self.frame_layout), Some(&self.count_layout)];
        layouts.resize(RIBBON_GROUP as usize, None);
        layouts.push(Some(ribbon_layout));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &layouts,
            immediate_size: 0,
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("probe.count_pipeline"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_ribbon_count"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                ..Default::default()
            },
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
}

impl TransparencyGpu for ProbeGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        let pixels = width as u64 * height as u64;
        if pixels != self.pixels {
            self.pixels = pixels;
            self.counts = storage(&gpu.device, "probe.counts", (pixels + 1) * 4);
            self.heads = storage(&gpu.device, "probe.heads", pixels * 4);
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let ribbons = frame.geometry.ribbons()?;
        let device = frame.gpu.device.clone();
        if self.count_pipeline.is_none() {
            self.count_pipeline = Some(self.count_pipeline(&device, &frame.geometry.ribbon_layout));
        }
        let count_group = group(
            &device,
            &self.count_layout,
            &[&self.counts],
            &frame.targets.depth_view,
        );
        frame.encoder.clear_buffer(&self.counts, 0, None);
        {
            let mut pass = frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("probe.count_pass"),
                color_attachments: &[frame.targets.null_attachment()],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(self.count_pipeline.as_ref().unwrap());
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            pass.set_bind_group(1, &count_group, &[]);
            pass.set_bind_group(RIBBON_GROUP, ribbons, &[]);
            pass.draw(0..frame.geometry.ribbon_vertex_count(), 0..1);
        }
        frame.flush();
        let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(frame.gpu, &self.counts)?);
        let total = counts[self.pixels as usize] as u64;
        self.nodes = storage(&device, "probe.nodes", total.max(1) * 32);
        frame.encoder.clear_buffer(&self.heads, 0, None);
        frame.encoder.clear_buffer(&self.counters, 0, None);
        let fill_group = group(
            &device,
            &self.fill_layout,
            &[&self.heads, &self.nodes, &self.counters],
            &frame.targets.depth_view,
        );
        let null = [frame.targets.null_attachment()];
        frame.draw_hair(
            HairDrawPass {
                entry: &FILL,
                attachments: &null,
                depth: None,
                group: Some((&self.fill_layout, &fill_group)),
                rows: None,
            },
            "eye: ribbons",
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.counts.size() + self.heads.size() + self.nodes.size() + self.counters.size()
    }

    fn geometry_passes(&self) -> u32 {
        2
    }
}

/// Per pixel: the count pass's fragment count and the hair pass's list (nodes in push order, newest first).
struct Readback {
    counts: Vec<u32>,
    lists: Vec<Vec<EyeNode>>,
    overflow: u32,
}

fn render_probe(gpu: &Gpu, s: &Settings, r: &mut Renderer) -> Readback {
    let empty = ParamValues::new();
    r.render(&eye_frame(s, &PROBE, &empty)).unwrap();
    let state = r.transparency_gpu().map(|t| t as &dyn Any);
    let probe = state
        .and_then(|t| t.downcast_ref::<ProbeGpu>())
        .expect("the probe's state");
    let words = |b: &wgpu::Buffer| -> Vec<u32> { bytemuck::pod_collect_to_vec(&copy_out(gpu, b).unwrap()) };
    let counts = words(&probe.counts);
    let heads = words(&probe.heads);
    let nodes: Vec<EyeNode> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &probe.nodes).unwrap());
    let counters = words(&probe.counters);
    let pixels = probe.pixels as usize;
    let lists = heads
        .iter()
        .map(|&head| {
            let mut list = Vec::new();
            let mut i = head as usize;
            while i != 0 && list.len() <= nodes.len() {
                list.push(nodes[i - 1]);
                i = nodes[i - 1].next as usize;
            }
            list
        })
        .collect();
    Readback {
        counts: counts[..pixels].to_vec(),
        lists,
        overflow: counters[1],
    }
}

/// The ribbon hair pass (`vs_ribbon`) and the ribbon count function (`eye_ribbon_point`) see the same fragments
/// in every pixel of the small head, with tapered strands from about 3 px at the root to 0.6 px at the tip
/// (both the widened and the true-width regime), and every node's segment id is a segment's first point.
/// Measured on lavapipe at 160×120: 54,925 fragments over 3,620 pixels, equal in every pixel.
#[test]
fn the_ribbon_hair_pass_and_the_ribbon_count_function_see_the_same_fragments() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small_settings(160, 120);
    s.scene.generator.taper = 0.2;
    s.render.strand_width = 1.5e-2;
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let firsts: std::collections::HashSet<u32> = scene
        .strands
        .ranges()
        .flat_map(|(start, n)| (start..start + n - 1).map(|p| p as u32))
        .collect();
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let out = render_probe(&gpu, &s, &mut r);
    assert_eq!(out.overflow, 0);
    let mut fragments = 0u64;
    let mut covered = 0usize;
    for (p, (&count, list)) in out.counts.iter().zip(&out.lists).enumerate() {
        assert_eq!(count as usize, list.len(), "pixel {p}");
        for n in list {
            assert!(firsts.contains(&n.segment), "pixel {p}: segment id {}", n.segment);
            assert!(
                n.alpha > 0.0 && n.alpha <= s.render.hair_alpha + 1e-6,
                "{}",
                n.alpha
            );
        }
        fragments += count as u64;
        covered += usize::from(count > 0);
    }
    let pixel = 2.0 * s.camera.distance * (s.camera.fov_y_deg.to_radians() * 0.5).tan() / 120.0;
    println!(
        "ribbons: {fragments} fragments over {covered} pixels, per-pixel counts equal; widths at the orbit \
         target {:.2} px (root) to {:.2} px (tip)",
        1.5e-2 / pixel,
        3e-3 / pixel
    );
    assert!(covered > 2000, "{covered} pixels hold hair");
    assert!(
        fragments > 5 * covered as u64,
        "{fragments} fragments over {covered} pixels"
    );
}

/// One straight strand along +X through the orbit target, in the plane of view depth `d`, on a 160×120 view
/// with a 40° vertical field: one pixel is `2 d tan 20° / 120` world units there. Its centre line lies
/// `offset_px` pixels below the image's horizontal centre line (y = 60) and it ends at x = 40.25 and 119.75
/// px, four segments of 19.875 px.
fn one_strand(thickness: f32, offset_px: f32) -> (Settings, Scene, f32) {
    let mut s = small_settings(160, 120);
    let d = 0.5f32;
    s.camera.target = [0.0; 3];
    s.camera.yaw_deg = 0.0;
    s.camera.pitch_deg = 0.0;
    s.camera.distance = d;
    s.camera.fov_y_deg = 40.0;
    let pixel = 2.0 * d * 20f32.to_radians().tan() / 120.0;
    let y = -offset_px * pixel;
    let points: Vec<Vec3> = (0..5)
        .map(|k| Vec3::new((-39.75 + 19.875 * k as f32) * pixel, y, 0.0))
        .collect();
    let strands = Strands {
        counts: vec![5],
        thickness: Some(vec![thickness; 5]),
        points,
        alpha: None,
        color: None,
    };
    s.render.strand_width = pixel;
    (s, Scene::new(strands, Vec::new()), pixel)
}

/// Rows and columns holding fragments, and each covered pixel's list.
fn covered(out: &Readback, width: usize) -> (Vec<usize>, Vec<usize>, Vec<&Vec<EyeNode>>) {
    let (mut rows, mut cols, mut lists) = (Vec::new(), Vec::new(), Vec::new());
    for (p, list) in out.lists.iter().enumerate() {
        if !list.is_empty() {
            let (x, y) = (p % width, p / width);
            if !rows.contains(&y) {
                rows.push(y);
            }
            if !cols.contains(&x) {
                cols.push(x);
            }
            lists.push(list);
        }
    }
    rows.sort_unstable();
    cols.sort_unstable();
    (rows, cols, lists)
}

/// A ribbon 4 px wide whose centre line lies on the row boundary y = 60 covers rows 58..62 (pixel centres
/// 58.5 … 61.5 inside 58..62) and columns 40..=119 (centres 40.5 … 119.5 inside 40.25..119.75): 80 × 4 pixels,
/// each once (the segments' shared corners are bitwise equal, so joints neither gap nor overlap), each at the
/// full hair alpha.
#[test]
fn a_four_pixel_ribbon_covers_four_rows_once_each() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, scene, _) = one_strand(4.0, 0.0);
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let out = render_probe(&gpu, &s, &mut r);
    let (rows, cols, lists) = covered(&out, 160);
    assert_eq!(rows, vec![58, 59, 60, 61]);
    assert_eq!(cols, (40..120).collect::<Vec<_>>());
    assert_eq!(lists.len(), 80 * 4);
    for list in &lists {
        assert_eq!(list.len(), 1);
        assert!(
            (list[0].alpha - s.render.hair_alpha).abs() < 1e-6,
            "{}",
            list[0].alpha
        );
    }
    assert_eq!(out.counts.iter().sum::<u32>(), 320, "the count function agrees");
}

/// A ribbon a quarter of a pixel wide, centred on row 60's pixel centres (y = 60.5), is widened to one pixel
/// (60..61 holds only row 60's centres) and its alpha scaled by the covered fraction 0.25: one row of 80
/// pixels at 0.25 × hair alpha (measured |Δα| = 0 on lavapipe; the bound 1e-6 is f32 rounding).
#[test]
fn a_quarter_pixel_ribbon_is_widened_to_one_pixel_at_a_quarter_of_the_alpha() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, scene, _) = one_strand(0.25, 0.5);
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let out = render_probe(&gpu, &s, &mut r);
    let (rows, cols, lists) = covered(&out, 160);
    assert_eq!(rows, vec![60]);
    assert_eq!(cols, (40..120).collect::<Vec<_>>());
    assert_eq!(lists.len(), 80);
    let expected = 0.25 * s.render.hair_alpha;
    let worst = lists
        .iter()
        .map(|l| {
            assert_eq!(l.len(), 1);
            (l[0].alpha - expected).abs()
        })
        .fold(0.0f32, f32::max);
    println!("quarter-pixel ribbon: largest |alpha - 0.25 hair_alpha| = {worst:e}");
    assert!(worst < 1e-6, "{worst}");
}
