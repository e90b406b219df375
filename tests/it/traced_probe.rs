//! The traced probe (`render.probe = traced`, `pathtrace::probe`): the renderer and the truth chain hold one
//! probe, and the eye pass's strand shading under it equals its CPU model (`shading::strand_lit`, which shades the
//! direct light alone where the probe holds the fibres' scattered light).

use crate::common;
use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::render::frame::{UniformInputs, uniforms};
use hairlab::render::probe_cache::Answer;
use hairlab::render::scene_gpu::SceneGpu;
use hairlab::render::uniforms::FrameUniforms;
use hairlab::scene::Camera;
use hairlab::settings::Settings;
use hairlab::shading::mesh_bounce::Probe;
use hairlab::shading::{HairModel, ShadingModel, strand_lit};

/// The frame uniforms of `uploaded` under `settings`, seen by `camera` at 64 × 48 with maps of 64².
fn small_frame(uploaded: &SceneGpu, camera: &Camera, settings: &Settings) -> FrameUniforms {
    uniforms(
        uploaded,
        &UniformInputs {
            camera,
            light: &settings.light,
            render: &settings.render,
            size: (64, 48),
            method_params: [0.0; 4],
            light_map_resolution: 64,
            shadow_map_resolution: 64,
        },
    )
}

/// The small `default` scene of 80 strands under the fibres model and the traced probe: its settings, the scene
/// and the ribbon layout a `SceneGpu` is uploaded with.
fn traced_scene(gpu: &Gpu) -> (Settings, hairlab::scene::Scene, wgpu::BindGroupLayout) {
    let settings = crate::truth_decomposition::small(
        "default",
        &[
            "render.hair_model=fibres",
            "render.probe=traced",
            "scene.generator.strands=80",
        ],
    );
    let scene = settings.scene.build().unwrap();
    (
        settings,
        scene,
        hairlab::render::geometry::ribbon_layout(&gpu.device),
    )
}

/// Under `render.probe = traced` the renderer's probe (its frame's lattice, `SceneGpu::mesh_bounce`) and the
/// truth chain's CPU model of the raster (`path_scene::raster_shading`) are one lattice, node for node, and it
/// holds light; the voxel probe of the same scene differs from it.
#[test]
fn the_renderer_and_the_truth_chain_hold_one_traced_probe() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (settings, scene, layout) = traced_scene(&gpu);
    let uploaded = SceneGpu::upload(&gpu, &scene, &layout).unwrap();
    let camera = hairlab::path_scene::camera(&settings, &scene);
    let u = small_frame(&uploaded, &camera, &settings);
    let traced = uploaded.mesh_bounce(&u, Probe::Traced);
    let chain = hairlab::path_scene::raster_shading(&settings, &scene, &scene.bounds())
        .bounce
        .expect("the fibres model has a probe");
    assert_eq!(traced, *chain);
    assert!(traced.values.iter().any(|v| v.mean().max_element() > 0.0));
    assert_ne!(traced, uploaded.mesh_bounce(&u, Probe::Voxels));
}

/// The probe is kept per pose: asked again for the same pose and light, the scene answers without baking; a
/// moved pose bakes a probe of its own, and back at the first pose (a motion's timeline looping) the first answer
/// comes back unbaked; another light bakes again. Counted by `SceneGpu::probe_bakes`.
#[test]
fn a_motion_bakes_each_poses_probe_once() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut settings = crate::truth_decomposition::small(
        "default",
        &["render.hair_model=fibres", "scene.generator.strands=80"],
    );
    let scene = settings.scene.build().unwrap();
    let layout = hairlab::render::geometry::ribbon_layout(&gpu.device);
    let mut uploaded = SceneGpu::upload(&gpu, &scene, &layout).unwrap();
    let camera = hairlab::path_scene::camera(&settings, &scene);
    let frame = |uploaded: &SceneGpu, settings: &Settings| small_frame(uploaded, &camera, settings);
    let u = frame(&uploaded, &settings);
    let first = uploaded.mesh_bounce(&u, Probe::Voxels);
    assert_eq!(uploaded.probe_bakes(), 1);
    assert_eq!(uploaded.mesh_bounce(&u, Probe::Voxels), first);
    assert_eq!(uploaded.probe_bakes(), 1);
    let rest = scene.strands.points.clone();
    let moved: Vec<Vec3> = rest.iter().map(|p| *p + Vec3::new(0.0, 0.0, 0.02)).collect();
    uploaded.update_points(&gpu, &moved).unwrap();
    let second = uploaded.mesh_bounce(&frame(&uploaded, &settings), Probe::Voxels);
    assert_eq!(uploaded.probe_bakes(), 2);
    assert_ne!(second, first);
    uploaded.update_points(&gpu, &rest).unwrap();
    assert_eq!(
        uploaded.mesh_bounce(&frame(&uploaded, &settings), Probe::Voxels),
        first
    );
    assert_eq!(uploaded.probe_bakes(), 2);
    settings.light.intensity *= 2.0;
    let brighter = uploaded.mesh_bounce(&frame(&uploaded, &settings), Probe::Voxels);
    assert_eq!(uploaded.probe_bakes(), 3);
    assert_ne!(brighter, first);
}

/// Waits until `pending` says no more, failing after two minutes.
fn settle(pending: impl Fn() -> bool) {
    let start = std::time::Instant::now();
    while pending() {
        assert!(
            start.elapsed().as_secs() < 120,
            "the probe's bake did not finish in 120 s"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// The window bakes the traced probe on another thread (`Renderer::set_background_probes`): asked for a probe it
/// does not keep, the scene bakes it (`SceneGpu::probe_pending`) with no traced probe yet to stand in; once
/// baked, it answers the lattice a bake on the caller's thread gives, bit for bit, without baking again; a moved
/// pose asks again, the last pose's probe standing in meanwhile, and gets a probe of its own. A renderer drawing in the
/// background draws its first frame with the voxel probe while the bake runs and, drawn again once it is kept,
/// the image a renderer that waits for the bake draws, pixel for pixel.
#[test]
fn the_window_bakes_the_traced_probe_in_the_background() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (settings, scene, layout) = traced_scene(&gpu);
    let mut uploaded = SceneGpu::upload(&gpu, &scene, &layout).unwrap();
    let camera = hairlab::path_scene::camera(&settings, &scene);
    let u = small_frame(&uploaded, &camera, &settings);
    assert_eq!(
        uploaded.mesh_bounce_or_bake(&u, Probe::Traced),
        Answer::Baking(None)
    );
    settle(|| uploaded.probe_pending());
    let Answer::Kept(baked) = uploaded.mesh_bounce_or_bake(&u, Probe::Traced) else {
        panic!("kept once baked")
    };
    assert_eq!(uploaded.probe_bakes(), 1);
    let waited = SceneGpu::upload(&gpu, &scene, &layout).unwrap();
    assert_eq!(waited.mesh_bounce(&u, Probe::Traced), baked);
    let moved: Vec<Vec3> = scene
        .strands
        .points
        .iter()
        .map(|p| *p + Vec3::new(0.0, 0.0, 0.02))
        .collect();
    uploaded.update_points(&gpu, &moved).unwrap();
    let u = small_frame(&uploaded, &camera, &settings);
    assert_eq!(
        uploaded.mesh_bounce_or_bake(&u, Probe::Traced),
        Answer::Baking(Some(baked))
    );
    settle(|| uploaded.probe_pending());
    assert_eq!(uploaded.probe_bakes(), 2);
    let Answer::Kept(second) = uploaded.mesh_bounce_or_bake(&u, Probe::Traced) else {
        panic!("the moved pose's probe kept once baked")
    };
    assert_ne!(second, baked);

    let mut s = settings.clone();
    (s.render.width, s.render.height) = (64, 48);
    s.camera = camera;
    let method = hairlab::methods::registry::reference();
    let mut background = hairlab::render::Renderer::new(&gpu, &scene, 64).unwrap();
    background.set_background_probes(true);
    let early = background
        .render_capture(&common::frame_input(&s, method))
        .unwrap();
    settle(|| background.probe_pending());
    let late = background
        .render_capture(&common::frame_input(&s, method))
        .unwrap();
    assert!(!background.probe_pending());
    let mut waiting = hairlab::render::Renderer::new(&gpu, &scene, 64).unwrap();
    let expected = waiting.render_capture(&common::frame_input(&s, method)).unwrap();
    assert!(
        late == expected,
        "drawn again once baked, the frame is the one that waits for its probe"
    );
    assert!(early != expected, "the first frame is drawn with the voxel probe");
}

/// `strand_lit` on a probe row: `(tangent, V)`, `(to light, count)`, `(to eye, ·)`, `(colour, ·)`.
fn cpu_lit(shading: ShadingModel, hair: HairModel, probe: Probe, r: &[[f32; 4]; 4]) -> Vec3 {
    let v3 = |x: [f32; 4]| Vec3::new(x[0], x[1], x[2]);
    strand_lit(
        shading,
        hair,
        probe,
        v3(r[0]),
        v3(r[1]),
        v3(r[2]),
        v3(r[3]),
        r[0][3],
        r[1][3],
    )
}

/// Per probe `(tangent, V)`, `(to light, count)`, `(to eye, ·)`, `(colour, ·)`: `strand_lit` of
/// `shaders/common/strand_shading.wgsl` under the frame's shading model, hair model and probe flag.
const STRAND_LIT_PROBE: &str = r#"
struct Row {
    t: vec4<f32>,
    l: vec4<f32>,
    e: vec4<f32>,
    c: vec4<f32>,
}
alias Out = vec4<f32>;

fn probe(i: u32, p: Row) {
    out[i] = vec4<f32>(strand_lit(p.t.xyz, p.l.xyz, p.e.xyz, p.c.rgb, p.t.w, p.l.w), 0.0);
}
"#;

/// GPU = CPU: `strand_lit` on the Marschner probe's tangents, lights, eyes and colours (4096 random, and the
/// lobes' peaks), each at a hair count `n` (0, 0.5, 1, 3, 10, cycling) and `V = e^-n`, for every shading model under both hair models and both probes (the flag
/// in `bounce_min.w`), within `|Δ| ≤ 2e-6 + 1e-5 |x|` (the lobes' tolerance); under the fibres model with the
/// traced probe every model is its direct light alone (dual scattering Marschner's), so Marschner and dual
/// scattering agree there and differ with the voxel probe. Measured on lavapipe: max |Δ| = 6.56e-6 over 4270 rows
/// × 12 cases.
#[test]
fn wgsl_strand_lit_equals_the_cpu_model_under_either_probe() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let counts = [0.0f32, 0.5, 1.0, 3.0, 10.0];
    let rows: Vec<[[f32; 4]; 4]> = crate::shading::probe_rows()
        .into_iter()
        .enumerate()
        .map(|(k, [t, l, e, c])| {
            let n = counts[k % counts.len()];
            [
                t.extend((-n).exp()).to_array(),
                l.extend(n).to_array(),
                e.extend(0.0).to_array(),
                c.extend(0.0).to_array(),
            ]
        })
        .collect();
    let mut frame: hairlab::render::uniforms::FrameUniforms = bytemuck::Zeroable::zeroed();
    frame.hair_alpha = 0.35;
    let (mut worst, mut cases) = (0.0f32, 0);
    let mut traced_ds = Vec::new();
    let mut traced_m = Vec::new();
    for shading in ShadingModel::ALL {
        for hair in HairModel::ALL {
            for probe in Probe::ALL {
                frame.shading_model = shading.uniform();
                frame.hair_model = hair.uniform();
                frame.bounce_min[3] = f32::from(u8::from(probe == Probe::Traced));
                let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&common::run_probe_with_frame(
                    &gpu,
                    ("common/strand_shading.wgsl", STRAND_LIT_PROBE, "strand_lit.probe"),
                    &frame,
                    bytemuck::cast_slice(&rows),
                    rows.len(),
                    16,
                ));
                let mut cpu_all = Vec::with_capacity(rows.len());
                for (r, o) in rows.iter().zip(&out) {
                    let cpu = cpu_lit(shading, hair, probe, r);
                    for k in 0..3 {
                        let d = (o[k] - cpu[k]).abs();
                        assert!(
                            d <= 2e-6 + 1e-5 * cpu[k].abs(),
                            "{shading:?} {hair:?} {probe:?} {r:?}: GPU {o:?}, CPU {cpu}"
                        );
                        worst = worst.max(d);
                    }
                    cpu_all.push(cpu);
                }
                cases += 1;
                if hair == HairModel::Fibres && probe == Probe::Traced {
                    match shading {
                        ShadingModel::DualScattering => traced_ds = cpu_all,
                        ShadingModel::Marschner => traced_m = cpu_all,
                        ShadingModel::KajiyaKay | ShadingModel::Chiang => {}
                    }
                }
            }
        }
    }
    println!(
        "strand_lit GPU = CPU: {} rows × {cases} cases, max |Δ| = {worst:.2e}",
        rows.len()
    );
    assert_eq!(traced_ds, traced_m);
    let voxels = |model| cpu_lit(model, HairModel::Fibres, Probe::Voxels, &rows[3]);
    assert_ne!(
        voxels(ShadingModel::Marschner),
        voxels(ShadingModel::DualScattering)
    );
}
