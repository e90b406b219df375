//! The fibres model's light side. A light fragment of the `lines` caster stores the strand's coverage of its
//! texel, its width over the texel's at most 1, at material opacity 1 (`strand_alpha` in
//! `shaders/common/frame.wgsl`; the compute rasteriser's twin is in `compute_raster.rs`). A strand does not
//! shadow itself (`fibre_transport::own_strand_offset`, `shaders/hair.wgsl`): the eye pass reads the light map
//! towards the light past the fragment's own strand, as the path tracer's shadow ray leaves its own fibre. The
//! WGSL offset equals its CPU model, and a lone straight strand sloping through the light's depth is lit as if
//! nothing shadowed it, where the absorber model (which keeps the plain read) darkens it by its own fragments.

use crate::common;

use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::{LightStrands, Renderer};
use hairlab::rng::SplitMix64;
use hairlab::scene::{LightFit, Scene, Strands};
use hairlab::settings::Settings;
use hairlab::shading::{HairModel, ShadingModel, fibre_transport};

/// Three combed strands under a light straight above, drawn as lines 0.5 and 1.5 texels wide: every fragment of
/// the reference's lists stores 0.5 and 1 (the width over the texel's, at most 1, whatever `hair_alpha`), within
/// 1e-5.
#[test]
fn line_fragments_store_the_texel_coverage() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = crate::light_ribbons::combed_settings(32);
    s.render.hair_model = HairModel::Fibres;
    s.render.light_strands = LightStrands::Lines;
    let (_, texel) = crate::light_ribbons::lists_of(&gpu, &s, crate::light_ribbons::combed(3, 0.03, 0.0));
    s.render.hair_alpha = 0.35;
    for (rho, expected) in [(0.5f32, 0.5f32), (1.5, 1.0)] {
        s.render.strand_width = rho * texel;
        let (lists, _) = crate::light_ribbons::lists_of(&gpu, &s, crate::light_ribbons::combed(3, 0.03, 0.0));
        let alphas: Vec<f32> = lists.iter().flatten().map(|f| f.alpha).collect();
        assert!(alphas.len() >= 50, "{} fragments", alphas.len());
        let worst = alphas.iter().map(|a| (a - expected).abs()).fold(0.0f32, f32::max);
        println!(
            "rho {rho}: {} fragments, max |alpha - {expected}| = {worst:.1e}",
            alphas.len()
        );
        assert!(worst <= 1e-5, "rho {rho}: alpha off by {worst}");
    }
}

/// Per probe `(tangent xyz, texel)` and `(to_light xyz, ·)`: `fibre_own_strand_offset`.
const OFFSET_PROBE: &str = r#"
struct Row {
    tangent: vec4<f32>,
    to_light: vec4<f32>,
}
alias Out = vec4<f32>;

fn probe(i: u32, p: Row) {
    out[i] = vec4<f32>(fibre_own_strand_offset(p.tangent.w, p.tangent.xyz, p.to_light.xyz), 0.0, 0.0, 0.0);
}
"#;

/// The offset by hand: none across the light, `√½` texel at 45°, the cap of 4 texels along it.
#[test]
fn the_offset_follows_the_depth_slope() {
    let l = Vec3::Y;
    let across = fibre_transport::own_strand_offset(0.002, Vec3::X, l);
    let diagonal = fibre_transport::own_strand_offset(0.002, Vec3::new(1.0, 1.0, 0.0).normalize(), l);
    let along = fibre_transport::own_strand_offset(0.002, l, l);
    assert_eq!(across, 0.0);
    assert!(
        (diagonal - 0.002 * std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-8,
        "{diagonal}"
    );
    assert!((along - 0.008).abs() < 1e-8, "{along}");
}

/// GPU = CPU on 4096 random unit tangents and light directions (texels 10⁻⁴ to 10⁻²), within
/// `1e-9 + 1e-5 |x|` (f32 `sqrt` and division; the measured maximum is printed).
#[test]
fn wgsl_own_strand_offset_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut rng = SplitMix64::new(29);
    let mut unit = || {
        let v = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        v.normalize_or(Vec3::X)
    };
    let mut rows: Vec<[f32; 8]> = Vec::new();
    for k in 0..4096 {
        let (t, l) = (unit(), unit());
        let texel = 1e-4 * 100f32.powf(k as f32 / 4095.0);
        rows.push([t.x, t.y, t.z, texel, l.x, l.y, l.z, 0.0]);
    }
    rows.push([0.0, 1.0, 0.0, 0.003, 0.0, 1.0, 0.0, 0.0]);
    let out: Vec<[f32; 4]> = common::run_probe_rows(
        &gpu,
        ("common/fibre_transport.wgsl", OFFSET_PROBE, "own_strand.probe"),
        &rows,
    );
    let mut worst = 0.0f32;
    for (r, o) in rows.iter().zip(&out) {
        let e = fibre_transport::own_strand_offset(
            r[3],
            Vec3::new(r[0], r[1], r[2]),
            Vec3::new(r[4], r[5], r[6]),
        );
        let d = (o[0] - e).abs();
        assert!(d <= 1e-9 + 1e-5 * e.abs(), "{r:?}: GPU {}, CPU {e}", o[0]);
        worst = worst.max(d / e.abs().max(1e-9));
    }
    println!(
        "own-strand offset GPU = CPU: {} probes, max relative |Δ| = {worst:.2e}",
        rows.len()
    );
}

/// One straight strand of 41 points rising 44° through the light's depth (the light straight above), running
/// diagonally across the map's texels, seen from the side: under the fibres model and the exact reference every hair pixel equals the image with no shadow
/// at all (`method = none`) to 1e-6, so no fragment of the strand shadows another of its own; under the
/// absorber model the same read darkens at least a tenth of its pixels (measured: 10 of 64), which is what the
/// offset removes.
#[test]
fn a_lone_strand_does_not_shadow_itself() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let points: Vec<Vec3> = (0..41)
        .map(|k| {
            let x = -0.05 + 0.0025 * k as f32;
            Vec3::new(x, x, 0.3 * x)
        })
        .collect();
    let scene = Scene::new(
        Strands {
            points,
            counts: vec![41],
            ..Strands::default()
        },
        Vec::new(),
    );
    let mut s: Settings = common::small_settings(96, 72);
    s.render.map_resolution = 64;
    s.render.shading = ShadingModel::Marschner;
    s.light.elevation_deg = 89.0;
    s.light.fit = LightFit::PerFrame;
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let mut capture = |model: HairModel, method: &str| {
        let mut s = s.clone();
        s.render.hair_model = model;
        s.method.name = method.into();
        s.method.params.clear();
        let m = registry::find(method).unwrap();
        r.render_capture(&common::frame_input(&s, m)).unwrap()
    };
    let reference = registry::reference().name();
    for model in [HairModel::Fibres, HairModel::Absorber] {
        let shadowed = capture(model, reference);
        let open = capture(model, "none");
        let hair: Vec<(f32, f32)> = shadowed
            .iter()
            .zip(&open)
            .filter(|(_, o)| o[3] > 0.0)
            .map(|(a, b)| (a[0] + a[1] + a[2], b[0] + b[1] + b[2]))
            .collect();
        assert!(hair.len() > 40, "{model:?}: {} hair pixels", hair.len());
        let darker = hair.iter().filter(|(a, b)| *a < b - 1e-6 * b.max(1.0)).count();
        println!(
            "{model:?}: {darker} of {} hair pixels darker under the reference",
            hair.len()
        );
        match model {
            HairModel::Fibres => assert_eq!(darker, 0, "the fibres' strand shadows itself"),
            HairModel::Absorber => {
                assert!(darker * 10 >= hair.len(), "absorbers: {darker} of {}", hair.len())
            }
        }
    }
}
