//! Fur that shows the hybrid (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): the guard hairs' base darkening
//! (`shaders/common/guard_darkening.wgsl`) and their environment of lights (`shaders/common/env_lights.wgsl`)
//! against their CPU models through probe compute passes, and the reading of
//! the paper's Fig. 9 measured on the `fur-hat` preset at 160×120: (a) implicit fur is a soft undercoat with no
//! strand above it, (b) explicit fur is distinct strands with the skin showing between them, (c) hybrid fur is
//! both — the undercoat of (a) where no guard hair crosses it and the guard hairs of (b) standing above it.

use glam::Vec3;
use hairlab::fur::blend;
use hairlab::fur::darkening;
use hairlab::fur::environment::{self, Sky};
use hairlab::fur::settings::{FurMode, FurScene, FurSettings};
use hairlab::gpu::Gpu;
use hairlab::render::method::ParamValues;
use hairlab::render::transparency::registry as techniques;
use hairlab::render::uniforms::FrameUniforms;
use hairlab::render::{FrameInput, Renderer};
use hairlab::rng::SplitMix64;
use hairlab::scene::Scene;
use hairlab::settings::Settings;
use hairlab::shading::ShadingModel;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// GPU = CPU tolerance on each darkening factor `d ∈ [0, 1]`: `|d_gpu − d_cpu| ≤ DARK_TOL · max(d_cpu, 1e-3)`.
/// Vulkan allows `exp(x)` 3 + 2|x| ulps; the exponents reach −16 (35 ulps ≈ 4.2e-6 relative). Measured on
/// lavapipe (printed by the test): max relative 9.1e-7 over 4099 rows.
const DARK_TOL: f32 = 1e-5;

const PROBE: &str = r#"
alias Row = vec4<f32>;
alias Out = vec4<f32>;

fn probe(i: u32, r: Row) {
    out[i] = vec4<f32>(guard_darkening(r.x, r.y, r.z), 0.0, 0.0, 0.0);
}
"#;

#[test]
fn wgsl_guard_darkening_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut rng = SplitMix64::new(9);
    // (height, shell height, σ): random heights up to 3 h_0 under σ h_0 up to 16, and the edges by hand.
    let mut rows: Vec<[f32; 4]> = (0..4096)
        .map(|_| {
            let h0 = rng.range(0.001, 0.05);
            [rng.range(0.0, 3.0) * h0, h0, rng.range(0.0, 16.0) / h0, 0.0]
        })
        .collect();
    rows.extend([
        [0.0, 0.01, 800.0, 0.0],
        [0.01, 0.01, 800.0, 0.0],
        [0.0, 0.01, 0.0, 0.0],
    ]);
    let out: Vec<[f32; 4]> = crate::common::run_probe_rows(
        &gpu,
        ("common/guard_darkening.wgsl", PROBE, "guard_darkening.probe"),
        &rows,
    );
    let mut worst = 0.0f32;
    for (r, o) in rows.iter().zip(&out) {
        let cpu = darkening::darkening(r[0], r[1], r[2]);
        let rel = (o[0] - cpu).abs() / cpu.max(1e-3);
        worst = worst.max(rel);
        assert!(rel <= DARK_TOL, "row {r:?}: gpu {} cpu {cpu}", o[0]);
    }
    eprintln!(
        "guard darkening GPU = CPU: max relative {worst:.2e} over {} rows",
        rows.len()
    );
}

/// GPU = CPU tolerance on each channel `c` of the environment's shading: `|c_gpu − c_cpu| ≤ ENV_ABS + ENV_REL ·
/// |c_cpu|`: 16 lights' sums of the models' lobes, each within the Marschner probe's 2e-6 + 1e-5 relative
/// (tests/it/shading.rs): 16 × (2e-6 + 1e-5 · 2) radiance-weighted stays below 3e-5. Measured on lavapipe
/// (printed by the test): max |Δ| 9.5e-7 (Kajiya–Kay) and 3.6e-7 (Marschner) over 1024 rows each.
const ENV_ABS: f32 = 3e-5;
const ENV_REL: f32 = 1e-4;

const ENV_PROBE: &str = r#"
struct Row {
    tangent: vec4<f32>,
    to_eye: vec4<f32>,
    colour: vec4<f32>,
}
alias Out = vec4<f32>;

fn probe(i: u32, r: Row) {
    out[i] = vec4<f32>(env_shading(r.tangent.xyz, r.to_eye.xyz, r.colour.rgb), 0.0);
}
"#;

#[test]
fn wgsl_environment_shading_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let sky = Sky {
        to_sun: Vec3::new(0.5, 0.7, 0.3).normalize(),
        radiance: Vec3::new(2.0, 1.8, 1.5),
    };
    let lights = sky.lights(16);
    let mut frame: FrameUniforms = bytemuck::Zeroable::zeroed();
    frame.env_count = lights.len() as u32;
    for (i, l) in lights.iter().enumerate() {
        frame.env_to_light[i] = l.to_light.extend(0.0).to_array();
        frame.env_radiance[i] = l.radiance.extend(0.0).to_array();
    }
    let mut rng = SplitMix64::new(23);
    let unit = |rng: &mut SplitMix64| {
        Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::Y)
    };
    let rows: Vec<[Vec3; 3]> = (0..1024)
        .map(|_| {
            let c = Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            [unit(&mut rng), unit(&mut rng), c]
        })
        .collect();
    let packed: Vec<[f32; 4]> = rows.iter().flatten().map(|v| v.extend(0.0).to_array()).collect();
    for model in [ShadingModel::KajiyaKay, ShadingModel::Marschner] {
        frame.shading_model = model.uniform();
        let bytes = crate::common::run_probe_with_frame(
            &gpu,
            ("common/env_lights.wgsl", ENV_PROBE, "env_lights.probe"),
            &frame,
            bytemuck::cast_slice(&packed),
            rows.len(),
            16,
        );
        let out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        let mut worst = 0.0f32;
        for ([t, e, c], o) in rows.iter().zip(&out) {
            let cpu = environment::shade(model, &lights, *t, *e, *c);
            for k in 0..3 {
                let d = (o[k] - cpu[k]).abs();
                worst = worst.max(d);
                assert!(
                    d <= ENV_ABS + ENV_REL * cpu[k].abs(),
                    "{model:?} {t} {e} {c}: gpu {o:?} cpu {cpu}"
                );
            }
        }
        eprintln!(
            "environment shading GPU = CPU, {model:?}: max |Δ| {worst:.2e} over {} rows",
            rows.len()
        );
    }
}

/// The `fur-hat` preset at test size: 600 of its guard hairs and a coarse shell (4 layers, levels ≤ 2).
fn hat() -> (Settings, Scene) {
    let mut s = crate::common::measured_preset(
        "fur-hat",
        &[
            "scene.generator.strands=600".into(),
            format!("render.width={WIDTH}"),
            format!("render.height={HEIGHT}"),
            "render.map_resolution=256".into(),
        ],
    );
    s.fur = FurSettings {
        layers: 4,
        max_level: 2,
        steps_per_thickness: 16,
        max_steps: 96,
        light_steps: 2,
        ..s.fur
    };
    let scene = s.scene.build().expect("fur-hat scene");
    s.camera.frame(&scene.framing_bounds());
    (s, scene)
}

struct Hat {
    settings: Settings,
    renderer: Renderer,
}

impl Hat {
    fn new(gpu: &Gpu) -> Hat {
        let (settings, scene) = hat();
        let fur = FurScene::build(&scene, &settings.fur)
            .unwrap()
            .expect("fur is on");
        let mut renderer = Renderer::new(gpu, &scene, settings.render.map_resolution).unwrap();
        renderer.set_fur(Some((&fur, &settings.fur))).unwrap();
        Hat { settings, renderer }
    }

    /// Per pixel (H, 1 − T) of the fur under `f`.
    fn capture(&mut self, f: &FurSettings) -> Vec<[f32; 4]> {
        let empty = ParamValues::new();
        let s = &self.settings;
        self.renderer.set_fur_rendering(f);
        self.renderer
            .render_capture(&FrameInput {
                camera: &s.camera,
                light: &s.light,
                render: &s.render,
                method: hairlab::methods::registry::find(&s.method.name).unwrap(),
                method_params: &s.method.params,
                technique: techniques::fur(),
                technique_params: &empty,
                width: WIDTH,
                height: HEIGHT,
            })
            .unwrap()
    }

    fn mode(&mut self, mode: FurMode) -> Vec<[f32; 4]> {
        let f = FurSettings {
            mode,
            ..self.settings.fur.clone()
        };
        self.capture(&f)
    }

    /// Per pixel: whether the last frame's typed list holds a guard-hair fragment.
    fn guard_pixels(&self) -> Vec<bool> {
        let state = self.renderer.fur_state().unwrap();
        let lists = state.lists.unwrap().typed_lists(self.renderer.gpu()).unwrap();
        lists
            .iter()
            .map(|l| l.iter().any(|t| t.kind == blend::EXPLICIT))
            .collect()
    }
}

/// Mean over `pixels` of the mean absolute (H, 1 − T) difference.
fn mean_diff(a: &[[f32; 4]], b: &[[f32; 4]], pixels: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for ((x, y), _) in a.iter().zip(b).zip(pixels).filter(|(_, p)| **p) {
        sum += (0..4).map(|c| f64::from((x[c] - y[c]).abs())).sum::<f64>() / 4.0;
        n += 1;
    }
    sum / n.max(1) as f64
}

/// Fig. 9 a/b/c on the `fur-hat` preset. Above the shell (pixels the implicit fur leaves empty) the hybrid shows
/// the guard hairs as the explicit fur does; over the undercoat it is the implicit fur wherever no guard hair
/// crosses the pixel, and guard hairs cross a visible share of it; the explicit fur alone shows the skin.
/// Measured on lavapipe (printed by the test), each beside its threshold: 2693 undercoat pixels (> 1500); 176
/// more, 0.065 of them, beyond the undercoat in the hybrid (> 0.03), equal to the explicit fur there (0, < 1e-4);
/// guard hairs cross 0.475 of the undercoat (> 0.25), the hybrid differs from the implicit by 0.0118 there
/// (> 0.008) and by 0 elsewhere (< 1e-6); bare skin 0.525 of the undercoat's pixels in the explicit fur (> 0.3),
/// 0 in the hybrid (< 0.01).
#[test]
fn fig_9_hybrid_is_the_undercoat_with_guard_hairs_standing_above_it() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut hat = Hat::new(&gpu);
    let implicit = hat.mode(FurMode::Implicit);
    let explicit = hat.mode(FurMode::Explicit);
    let hybrid = hat.mode(FurMode::Hybrid);
    let guard = hat.guard_pixels();
    let covered = |c: &[f32; 4]| c[3] > 2.0 / 255.0;
    let undercoat: Vec<bool> = implicit.iter().map(covered).collect();
    let n_undercoat = undercoat.iter().filter(|&&u| u).count();
    assert!(n_undercoat > 1500, "{n_undercoat} undercoat pixels");
    // (c) against (a) above the shell: hybrid pixels the undercoat leaves empty.
    let above: Vec<bool> = hybrid
        .iter()
        .zip(&undercoat)
        .map(|(h, &u)| !u && covered(h))
        .collect();
    let n_above = above.iter().filter(|&&a| a).count();
    let above_share = n_above as f64 / n_undercoat as f64;
    // (c) against (b) there: the same guard hairs, nothing behind them.
    let above_vs_explicit = mean_diff(&hybrid, &explicit, &above);
    // (c) against (a) over the undercoat, apart and where guard hairs cross it.
    let bare: Vec<bool> = undercoat.iter().zip(&guard).map(|(&u, &g)| u && !g).collect();
    let crossed: Vec<bool> = undercoat.iter().zip(&guard).map(|(&u, &g)| u && g).collect();
    let crossed_share = crossed.iter().filter(|&&c| c).count() as f64 / n_undercoat as f64;
    let apart = mean_diff(&hybrid, &implicit, &bare);
    let crossing = mean_diff(&hybrid, &implicit, &crossed);
    // (b): the skin between the strands, over the pixels the undercoat covers.
    let skin = |c: &[[f32; 4]]| {
        c.iter()
            .zip(&undercoat)
            .filter(|(p, u)| **u && !covered(p))
            .count() as f64
            / n_undercoat as f64
    };
    let (skin_explicit, skin_hybrid) = (skin(&explicit), skin(&hybrid));
    eprintln!(
        "Fig. 9: {n_undercoat} undercoat pixels; above the shell {n_above} ({above_share:.3} of them), \
         hybrid vs explicit there {above_vs_explicit:.5}; guard hairs cross {crossed_share:.3} of the undercoat, \
         hybrid vs implicit {crossing:.4} there and {apart:.2e} elsewhere; bare skin explicit {skin_explicit:.3}, \
         hybrid {skin_hybrid:.3}"
    );
    assert!(above_share > 0.03, "above the shell: {above_share}");
    assert!(
        above_vs_explicit < 1e-4,
        "hybrid vs explicit above the shell: {above_vs_explicit}"
    );
    assert!(
        crossed_share > 0.25,
        "guard hairs over the undercoat: {crossed_share}"
    );
    assert!(
        crossing > 0.008,
        "hybrid vs implicit where guard hairs cross: {crossing}"
    );
    assert!(apart < 1e-6, "hybrid vs implicit elsewhere: {apart}");
    assert!(
        skin_explicit > 0.3 && skin_hybrid < 0.01,
        "bare skin: {skin_explicit} vs {skin_hybrid}"
    );
}

/// The guard hairs' base darkening on the GPU: with `fur.base_darkening` on, no guard-hair pixel of the explicit
/// fur is brighter than without it, and the image is darker on the whole. Measured on lavapipe: summed H 87.5
/// with it against 183.2 without (< 0.6 of it), no pixel brightened.
#[test]
fn base_darkening_darkens_guard_hairs_and_never_brightens_them() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut hat = Hat::new(&gpu);
    let on = FurSettings {
        mode: FurMode::Explicit,
        base_darkening: 1.0,
        ..hat.settings.fur.clone()
    };
    let off = FurSettings {
        base_darkening: 0.0,
        ..on.clone()
    };
    let dark = hat.capture(&on);
    let plain = hat.capture(&off);
    let luminance = |c: &[f32; 4]| f64::from(c[0] + c[1] + c[2]);
    let (mut brighter, mut sum_dark, mut sum_plain) = (0.0f64, 0.0, 0.0);
    for (d, p) in dark.iter().zip(&plain) {
        assert_eq!(d[3], p[3], "darkening changed coverage");
        brighter = brighter.max(luminance(d) - luminance(p));
        sum_dark += luminance(d);
        sum_plain += luminance(p);
    }
    eprintln!(
        "base darkening: summed H {sum_dark:.3} (on) vs {sum_plain:.3} (off), most brightened pixel {brighter:.2e}"
    );
    assert!(brighter <= 1e-6, "a pixel brightened by {brighter}");
    assert!(sum_dark < 0.6 * sum_plain, "{sum_dark} vs {sum_plain}");
}

/// `fur.env_map`: a user's equirectangular map lights the guard hairs in place of the procedural sky, through the
/// same frame uniforms (`src/fur/env_map.rs`). The explicit fur with 16 lights from a map lit only from above, one
/// lit only from below, and the sky: coverage is the same in all three (lighting moves colour, never coverage);
/// the two maps shade the guard hairs differently, and a missing file is one error naming the key and the file.
/// Measured on lavapipe (printed): 1454 guard pixels (> 500), mean |ΔH| over them between the maps 0.0024 (> 0.0012).
#[test]
fn a_user_map_lights_the_guard_hairs() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let dir = tempfile::tempdir().unwrap();
    let map = |name: &str, upper: u8, lower: u8| {
        let path = dir.path().join(name);
        image::RgbImage::from_fn(64, 32, |_, y| image::Rgb([if y < 16 { upper } else { lower }; 3]))
            .save(&path)
            .unwrap();
        path
    };
    let (above, below) = (map("above.png", 255, 0), map("below.png", 0, 255));
    let (settings, scene) = hat();
    let lit = |env_map: Option<std::path::PathBuf>| -> (Vec<[f32; 4]>, Vec<bool>) {
        let f = FurSettings {
            mode: FurMode::Explicit,
            env_lights: 16,
            env_map,
            ..settings.fur.clone()
        };
        let fur = FurScene::build(&scene, &f).unwrap().expect("fur is on");
        let mut hat = Hat {
            settings: settings.clone(),
            renderer: Renderer::new(&gpu, &scene, settings.render.map_resolution).unwrap(),
        };
        hat.renderer.set_fur(Some((&fur, &f))).unwrap();
        let image = hat.capture(&f);
        (image, hat.guard_pixels())
    };
    let (from_above, guards) = lit(Some(above));
    let (from_below, _) = lit(Some(below));
    let (sky, _) = lit(None);
    for (a, b) in from_above
        .iter()
        .zip(&from_below)
        .chain(from_above.iter().zip(&sky))
    {
        assert_eq!(a[3], b[3], "lighting changed coverage");
    }
    let n = guards.iter().filter(|g| **g).count();
    assert!(n > 500, "{n} guard pixels");
    let between = mean_diff(&from_above, &from_below, &guards);
    eprintln!("env map: {n} guard pixels, mean |ΔH| above vs below {between:.4}");
    assert!(between > 0.0012, "{between}");

    let missing = FurSettings {
        mode: FurMode::Explicit,
        env_map: Some(dir.path().join("missing.hdr")),
        ..settings.fur.clone()
    };
    let e = FurScene::build(&scene, &missing).unwrap_err().to_string();
    assert!(
        e.starts_with("fur.env_map = ") && e.contains("missing.hdr"),
        "{e}"
    );
}
