//! Helpers shared by the integration tests: small scenes and image comparison with a tolerance.

#![allow(dead_code)]

pub mod cli;

use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, ShadowMethod, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::visibility::{Fragment, metrics, optical_depth};
use std::path::{Path, PathBuf};

/// Environment variable that rewrites snapshot images instead of comparing.
pub const UPDATE_ENV: &str = "HAIRLAB_UPDATE_SNAPSHOTS";

/// The light fit the still-scene figures of these tests were measured and their snapshots taken under:
/// `per-frame`, the default before issue 35 made it `stable` (fitted to the scene's bounding sphere, so each
/// texel covers more hair and the figures move). The motion claims and the fit's own tests use the default.
pub const MEASURED_FIT: &str = "light.fit=per-frame";

/// `Settings::load_preset(name, overrides)` under [`MEASURED_FIT`] (an override may still name another fit).
pub fn measured_preset(name: &str, overrides: &[String]) -> Settings {
    let mut all = vec![MEASURED_FIT.to_string()];
    all.extend_from_slice(overrides);
    Settings::load_preset(name, &all).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}

/// The workbench on `settings` in a `size`-point window on the software adapter, in snapshot mode (no timings on
/// screen), after its first frames.
pub fn snapshot_harness(
    settings: Settings,
    size: [f32; 2],
) -> egui_kittest::Harness<'static, hairlab::app::HairlabApp> {
    let mut harness = egui_kittest::Harness::builder()
        .with_size(size)
        .wgpu_setup(hairlab::app::wgpu_setup(
            hairlab::gpu::AdapterPreference::Software,
        ))
        .build_eframe(move |cc| {
            let mut app = hairlab::app::HairlabApp::new(cc, Some(settings));
            app.set_snapshot_mode(true);
            app
        });
    harness.run();
    harness
}

/// Opens the Bench window with only OSM's sweep checked (the other methods unchecked).
pub fn bench_window_on_osm(harness: &mut egui_kittest::Harness<'_, hairlab::app::HairlabApp>) {
    use egui_kittest::kittest::Queryable;
    harness.get_by_label("Bench").click();
    harness.run();
    for m in hairlab::bench::sweep_methods()
        .into_iter()
        .filter(|m| *m != "osm")
    {
        harness.get_by_label(m).click();
    }
    harness.run();
}

/// The default preset shrunk to a test-sized scene and image, under [`MEASURED_FIT`].
pub fn small_settings(width: u32, height: u32) -> Settings {
    measured_preset(
        "default",
        &[
            "scene.generator.strands=600".into(),
            "scene.generator.segments=12".into(),
            format!("render.width={width}"),
            format!("render.height={height}"),
            "render.map_resolution=256".into(),
        ],
    )
}

pub fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots")
}

/// Compares `img` with `tests/snapshots/<name>.png`: fails when more than `max_bad_fraction` of the pixels differ
/// by more than `channel_tolerance` in any channel. On failure writes `<name>.new.png` and `<name>.diff.png`
/// under `target/snapshot-failures/`. With `HAIRLAB_UPDATE_SNAPSHOTS=1` it rewrites the snapshot instead.
pub fn compare_snapshot(name: &str, img: &image::RgbaImage, channel_tolerance: u8, max_bad_fraction: f64) {
    let path = snapshot_dir().join(format!("{name}.png"));
    if std::env::var(UPDATE_ENV).is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        eprintln!("snapshot {} rewritten", path.display());
        return;
    }
    let expected = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with {UPDATE_ENV}=1 to create it", path.display()))
        .to_rgba8();
    assert_eq!(
        expected.dimensions(),
        img.dimensions(),
        "{name}: size differs from the snapshot"
    );
    let mut diff = image::RgbaImage::new(img.width(), img.height());
    let mut bad = 0usize;
    for (x, y, p) in img.enumerate_pixels() {
        let q = expected.get_pixel(x, y);
        let d =
            p.0.iter()
                .zip(q.0.iter())
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap_or(0);
        if d > channel_tolerance {
            bad += 1;
        }
        diff.put_pixel(x, y, image::Rgba([d.saturating_mul(4), 0, 0, 255]));
    }
    let fraction = bad as f64 / (img.width() * img.height()) as f64;
    if fraction > max_bad_fraction {
        let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/snapshot-failures");
        std::fs::create_dir_all(&out).unwrap();
        img.save(out.join(format!("{name}.new.png"))).unwrap();
        diff.save(out.join(format!("{name}.diff.png"))).unwrap();
        panic!(
            "{name}: {:.3}% of pixels differ by more than {channel_tolerance} (allowed {:.3}%); see {}",
            fraction * 100.0,
            max_bad_fraction * 100.0,
            out.display()
        );
    }
}

/// The scene and map of a GPU = CPU comparison.
#[derive(Clone, Copy, Debug)]
pub struct Setup {
    pub strands: u32,
    pub resolution: u32,
    /// `None`: the preset's hair alpha.
    pub hair_alpha: Option<f32>,
}

impl Setup {
    pub fn new(strands: u32, resolution: u32) -> Setup {
        Setup {
            strands,
            resolution,
            hair_alpha: None,
        }
    }
}

/// Renders `method` with `params` on the small test scene at `resolution`²; returns the largest
/// |V_gpu - V_cpu| and the sample count. See [`gpu_cpu_difference`].
pub fn max_gpu_cpu_difference(
    gpu: &Gpu,
    method: &str,
    params: &[(&str, f32)],
    resolution: u32,
) -> (f32, usize) {
    let (worst, n) = gpu_cpu_difference(gpu, method, params, Setup::new(300, resolution));
    (worst, n)
}

/// Renders the reference and `method` (light passes and a full frame) on the test scene of `setup`, evaluates
/// the method's GPU lookup at every fragment depth and a 16-point grid of every occupied texel, and at five
/// depths of an empty texel (lit everywhere), and compares with the CPU model fed each texel's exact fragment
/// list. Returns the largest |V_gpu - V_cpu| and the sample count. Fails on any V not finite or outside [0, 1];
/// on a scene of 100 strands or more also when no texel is deep enough to fall below V = 1/2.
pub fn gpu_cpu_difference(gpu: &Gpu, method: &str, params: &[(&str, f32)], setup: Setup) -> (f32, usize) {
    let d = gpu_cpu_differences(gpu, method, params, setup);
    (d.iter().copied().fold(0.0f32, f32::max), d.len())
}

/// The scenes at the light-map resolution extremes every per-method GPU test covers: (strands, resolution) —
/// every fragment of 300 strands in one texel, and 20 strands over 2048².
pub const EXTREME_SETUPS: [(u32, u32); 2] = [(300, 1), (20, 2048)];

/// The settings of `setup`'s test scene: the small head, 10 segments per strand, and the scene itself, with the
/// camera framed on it.
pub fn setup_scene(setup: Setup) -> (Settings, hairlab::scene::Scene) {
    let mut s: Settings = small_settings(8, 8);
    s.scene.generator.strands = setup.strands;
    s.scene.generator.segments = 10;
    s.render.map_resolution = setup.resolution;
    if let Some(a) = setup.hair_alpha {
        s.render.hair_alpha = a;
    }
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    (s, scene)
}

/// A frame (8×8 eye image) of `method` with `values` under `s`.
pub fn light_frame<'a>(
    s: &'a Settings,
    method: &'static dyn ShadowMethod,
    values: &'a ParamValues,
) -> FrameInput<'a> {
    FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: values,
        technique: s.transparency.technique().unwrap(),
        technique_params: &s.transparency.params,
        width: 8,
        height: 8,
    }
}

/// A frame of `method` with the preset's parameters, technique and image size under `s`.
pub fn frame_input<'a>(s: &'a Settings, method: &'a dyn ShadowMethod) -> FrameInput<'a> {
    FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: &s.method.params,
        technique: s.transparency.technique().unwrap(),
        technique_params: &s.transparency.params,
        width: s.render.width,
        height: s.render.height,
    }
}

/// `(key, value)` pairs as parameter values.
pub fn values(params: &[(&str, f32)]) -> ParamValues {
    params.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// Every sample's |V_gpu - V_cpu| of [`gpu_cpu_difference`] (same scene, samples and checks).
pub fn gpu_cpu_differences(gpu: &Gpu, method: &str, params: &[(&str, f32)], setup: Setup) -> Vec<f32> {
    let (s, scene) = setup_scene(setup);
    gpu_cpu_differences_in(gpu, method, params, &s, &scene, setup.strands >= 100)
}

/// [`gpu_cpu_differences`] on `scene` under `s` (its map resolution, its light casters); `deep`: the scene
/// must shadow some texel below V = 1/2.
pub fn gpu_cpu_differences_in(
    gpu: &Gpu,
    method: &str,
    params: &[(&str, f32)],
    s: &Settings,
    scene: &hairlab::scene::Scene,
    deep: bool,
) -> Vec<f32> {
    let mut r = Renderer::new(gpu, scene, s.render.map_resolution).unwrap();
    gpu_cpu_differences_on(&mut r, method, params, s, deep)
}

/// [`gpu_cpu_differences_in`] with the renderer `r` (made for the scene at `s`'s map resolution), whatever it
/// drew before: what a frame leaves in a method's maps must not reach the next.
pub fn gpu_cpu_differences_on(
    r: &mut Renderer,
    method: &str,
    params: &[(&str, f32)],
    s: &Settings,
    deep: bool,
) -> Vec<f32> {
    let resolution = s.render.map_resolution;
    let values: ParamValues = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let frame = |m: &str, params| light_frame(s, registry::find(m).unwrap(), params);
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let m = registry::find(method).unwrap();
    // A full frame: the eye passes bind the method's maps too.
    r.render(&frame(method, &values)).unwrap();
    r.read_output().unwrap();
    let model = m.model(&values, s.render.hair_alpha);
    let texel = |t: usize| ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
    let (mut samples, mut expected) = (Vec::new(), Vec::new());
    for (t, list) in lists.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        let frags: Vec<Fragment> = list.iter().map(|f| f.fragment()).collect();
        let zs = metrics::sample_depths(&frags, 16);
        let (x, y) = texel(t);
        expected.extend(model.curve(&frags, &zs));
        samples.extend(zs.iter().map(|&z| [x, y, z]));
    }
    if deep {
        let deepest = lists
            .iter()
            .map(|l| l.iter().map(|f| optical_depth(f.alpha)).sum::<f32>())
            .fold(0.0f32, f32::max);
        assert!(
            deepest > 2f32.ln(),
            "{method}: the test scene should shadow some texel below V = 1/2"
        );
    }
    if let Some(t) = lists.iter().position(|l| l.is_empty()) {
        let (x, y) = texel(t);
        samples.extend([-1.0, 0.0, 0.5, 1.0, 2.0].map(|z| [x, y, z]));
        expected.extend([1.0; 5]);
    }
    let got = r.evaluate(m, &samples).unwrap();
    assert!(
        got.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
        "{method}: V outside [0, 1] at {resolution}² with {params:?}"
    );
    got.iter().zip(&expected).map(|(a, b)| (a - b).abs()).collect()
}

/// One light frame of `method` with `params` on the small test head of `strands` strands at `resolution`²: the
/// renderer and what the frame returned (methods that refuse a scene refuse it here).
pub fn render_method_light(
    gpu: &Gpu,
    method: &str,
    params: &[(&str, f32)],
    strands: u32,
    resolution: u32,
) -> (Renderer, Result<(), hairlab::gpu::GpuError>) {
    let (s, scene) = setup_scene(Setup::new(strands, resolution));
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let values = values(params);
    let result = r.render_light(&light_frame(&s, registry::find(method).unwrap(), &values));
    (r, result)
}

/// Runs `probe` (WGSL declaring the input item type `Row`, the output element type `Out` and `fn probe(i: u32,
/// row: Row)`, which writes `out`), appended to the shared shader file `shared` with the bindings `rows` (0) and
/// `out` (1) and the entry point ([`probe_entry`]), over `items` items of `input`, and reads back `out_bytes`
/// bytes per item: how a test evaluates a shared WGSL function against its CPU model. A probe that reads the
/// Chiang shading's table (`chiang_table`, group 0, binding 5, as the scene group binds it) gets the renderer's
/// texture of `shading::chiang::table`.
pub fn run_probe(gpu: &Gpu, spec: (&str, &str, &str), input: &[u8], items: usize, out_bytes: u64) -> Vec<u8> {
    probe_pass(gpu, spec, None, input, items, out_bytes)
}

/// [`run_probe`] over `rows`, one `Row` each, for a probe that writes one 16-byte `Out` (a `vec4`) per row.
pub fn run_probe_rows<R: bytemuck::Pod, O: bytemuck::Pod>(
    gpu: &Gpu,
    spec: (&str, &str, &str),
    rows: &[R],
) -> Vec<O> {
    bytemuck::pod_collect_to_vec(&run_probe(gpu, spec, bytemuck::cast_slice(rows), rows.len(), 16))
}

/// [`run_probe`] for a shared file that reads the frame uniforms: `frame` bound at group 0 (binding 0, as every
/// pass binds it), the probe's input and output at group 1 (bindings 0 and 1).
pub fn run_probe_with_frame(
    gpu: &Gpu,
    spec: (&str, &str, &str),
    frame: &hairlab::render::uniforms::FrameUniforms,
    input: &[u8],
    items: usize,
    out_bytes: u64,
) -> Vec<u8> {
    probe_pass(
        gpu,
        spec,
        Some(bytemuck::bytes_of(frame)),
        input,
        items,
        out_bytes,
    )
}

/// The bindings and compute entry every probe shares, at bind group `group`: 64 items a workgroup, `probe` called
/// on each item of `rows`.
fn probe_entry(group: u32) -> String {
    format!(
        "
@group({group}) @binding(0) var<storage, read> rows: array<Row>;
@group({group}) @binding(1) var<storage, read_write> out: array<Out>;

@compute @workgroup_size(64)
fn cs_probe(@builtin(global_invocation_id) id: vec3<u32>) {{
    if id.x < arrayLength(&rows) {{
        probe(id.x, rows[id.x]);
    }}
}}
"
    )
}

/// Whether the entry point of `src` reads `chiang_table`.
fn reads_chiang_table(src: &str) -> bool {
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    module
        .global_variables
        .iter()
        .find(|(_, g)| g.name.as_deref() == Some("chiang_table"))
        .is_some_and(|(handle, _)| !info.get_entry_point(0)[handle].is_empty())
}

fn probe_pass(
    gpu: &Gpu,
    (shared, probe, label): (&str, &str, &str),
    frame: Option<&[u8]>,
    input: &[u8],
    items: usize,
    out_bytes: u64,
) -> Vec<u8> {
    use wgpu::util::DeviceExt;
    let device = &gpu.device;
    let src =
        hairlab::shaders::compose(shared, None).unwrap() + probe + &probe_entry(u32::from(frame.is_some()));
    let reads_table = reads_chiang_table(&src);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module: &module,
        entry_point: Some("cs_probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: input,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: items as u64 * out_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let table = reads_table.then(|| hairlab::render::frame_bindings::chiang_table(device, &gpu.queue));
    let table_entry = table.as_ref().map(|t| wgpu::BindGroupEntry {
        binding: 5,
        resource: wgpu::BindingResource::TextureView(t),
    });
    let io_group = u32::from(frame.is_some());
    let mut io_entries = vec![
        wgpu::BindGroupEntry {
            binding: 0,
            resource: input.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 1,
            resource: output.as_entire_binding(),
        },
    ];
    if frame.is_none() {
        io_entries.extend(table_entry.clone());
    }
    let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(io_group),
        entries: &io_entries,
    });
    let frame_group = frame.map(|bytes| {
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: buffer.as_entire_binding(),
        }];
        entries.extend(table_entry);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        })
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        if let Some(g) = &frame_group {
            pass.set_bind_group(0, g, &[]);
        }
        pass.set_bind_group(io_group, &io, &[]);
        pass.dispatch_workgroups((items as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    hairlab::gpu::readback::copy_out(gpu, &output).unwrap()
}
