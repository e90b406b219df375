//! The strands drawn from the light as ribbons (`render.light_strands = ribbons`, `shaders/casters/ribbons.wgsl`):
//! the exact reference stays exact (the A-buffer equals depth peeling under the caster), every method still
//! equals its CPU model fed the caster's fragments, the ribbons carry the strand's opacity (coverage alpha
//! summed over the texels equals the strand's area over the texel area), and a strand sliding by fractions of a
//! texel changes the light-space optical depth in smaller steps than as lines: the anti-flicker the caster is for.

use crate::common;

use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::passes::abuffer::RefFragment;
use hairlab::render::{LightStrands, Renderer, footprint_per_w};
use hairlab::scene::{Aabb, LightFit, Scene, Strands};
use hairlab::settings::Settings;
use hairlab::visibility::optical_depth;

fn ribbons(s: &mut Settings, min_width: f32) {
    s.render.light_strands = LightStrands::Ribbons;
    s.render.light_min_width = min_width;
}

#[test]
fn abuffer_equals_depth_peeling_under_ribbons() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for min_width in [1.0, 2.5] {
        crate::reference::assert_abuffer_equals_depth_peeling(&gpu, |s| ribbons(s, min_width));
    }
}

/// Every registered method at its defaults, its maps built from the ribbons' fragments, against its CPU model
/// fed the reference's lists of the same fragments: within the method's own stated tolerance (the same bound as
/// under lines; the per-method maxima are printed).
#[test]
fn every_method_gpu_equals_cpu_under_ribbons() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = common::setup_scene(common::Setup::new(300, 64));
    ribbons(&mut s, 1.5);
    for m in registry::all() {
        let info = m.info();
        let d = common::gpu_cpu_differences_in(&gpu, info.name, &[], &s, &scene, true);
        crate::methods_gpu::assert_within_stated_tolerance(info, "under ribbons", &d);
    }
}

/// `n` straight strands of 41 points along x at height 0, `spacing` apart in z, shifted by `dz`.
pub(crate) fn combed(n: usize, spacing: f32, dz: f32) -> Strands {
    let mut points = Vec::new();
    for i in 0..n {
        let z = (i as f32 - (n - 1) as f32 / 2.0) * spacing + dz;
        points.extend((0..41).map(|k| Vec3::new(-0.05 + 0.0025 * k as f32, 0.0, z)));
    }
    Strands {
        points,
        counts: vec![41; n],
        ..Strands::default()
    }
}

/// Settings for the combed strands: a light straight above them, its frame fitted once to a fixed box so that
/// moving the strands moves them across the map's texels.
pub(crate) fn combed_settings(resolution: u32) -> Settings {
    let mut s = common::small_settings(8, 8);
    s.render.map_resolution = resolution;
    s.light.elevation_deg = 89.0;
    s.light.fit = LightFit::Bound;
    s
}

const BOX: Aabb = Aabb {
    min: Vec3::new(-0.08, -0.01, -0.08),
    max: Vec3::new(0.08, 0.01, 0.08),
};

/// The reference lists of `strands` under `s`, with the light frame fitted to [`BOX`]; and the world size of
/// one light texel.
pub(crate) fn lists_of(gpu: &Gpu, s: &Settings, strands: Strands) -> (Vec<Vec<RefFragment>>, f32) {
    let scene = Scene::new(strands, Vec::new());
    let mut s = s.clone();
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution).unwrap();
    r.set_fit_bound(Some(BOX));
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let res = s.render.map_resolution;
    let texel = footprint_per_w(&r.hair_light_frame(&s.light).view_to_clip, res, res);
    (lists, texel)
}

/// A strand thinner than a texel, drawn as a ribbon of least width `w` texels: its fragments' alphas sum to
/// hair_alpha × strand width × strand length / texel² (the strand's area in texels times its opacity). A ribbon
/// `w` texels wide covers floor(w) or ceil(w) texel centres per column, each at alpha / w, so the sum is exact
/// up to the ends of the strands for a whole `w` (measured: +0.35 % at w = 1, 2 and 3) and within
/// [floor(w) / w, ceil(w) / w] of it otherwise (measured: +14.7 % at w = 3.5, whose columns cover 4 centres).
#[test]
fn ribbons_carry_the_strands_coverage() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for w in [1.0f32, 2.0, 3.0, 3.5] {
        let mut s = combed_settings(32);
        ribbons(&mut s, w);
        let (lists, texel) = lists_of(&gpu, &s, combed(3, 0.03, 0.0));
        let width = s.render.strand_width;
        assert!(width < 0.5 * texel, "the strands must be thinner than a texel");
        let sum: f32 = lists.iter().flatten().map(|f| f.alpha).sum();
        let expected = 3.0 * s.render.hair_alpha * width * 0.1 / (texel * texel);
        let ratio = sum / expected;
        eprintln!("least width {w}: coverage sum {sum:.4}, expected {expected:.4}, ratio {ratio:.4}");
        let (low, high) = if w.fract() == 0.0 {
            (0.98, 1.02)
        } else {
            (w.floor() / w - 0.02, w.ceil() / w + 0.02)
        };
        assert!(
            (low..=high).contains(&ratio),
            "least width {w}: coverage sum {sum} against {expected}"
        );
    }
}

/// Per-texel optical depth of the lists.
fn optical_depths(lists: &[Vec<RefFragment>]) -> Vec<f32> {
    lists
        .iter()
        .map(|l| l.iter().map(|f| optical_depth(f.alpha)).sum())
        .collect()
}

/// The largest change of the light-space optical-depth map between consecutive positions of strands sliding
/// across the map by eighths of a texel (L1 over texels, relative to the map's total).
fn largest_step(gpu: &Gpu, s: &Settings) -> f32 {
    let (_, texel) = lists_of(gpu, s, combed(3, 0.03, 0.0));
    let maps: Vec<Vec<f32>> = (0..=16)
        .map(|k| optical_depths(&lists_of(gpu, s, combed(3, 0.03, k as f32 * texel / 8.0)).0))
        .collect();
    maps.windows(2)
        .map(|w| {
            let total: f32 = w[0].iter().sum();
            let change: f32 = w[0].iter().zip(&w[1]).map(|(a, b)| (a - b).abs()).sum();
            change / total
        })
        .fold(0.0, f32::max)
}

/// The anti-flicker: as lines, a strand thinner than a texel moves all its opacity to the next texel row at
/// once when it crosses a texel centre (a step of 2× its share of the map's total, L1; two of the three strands
/// cross at the same step here); as ribbons of least width 2 texels the opacity is spread over two rows and a
/// crossing moves half of it. Measured: lines 1.333, ribbons (2 texels) 0.667, ribbons (4 texels) 0.321.
#[test]
fn ribbons_move_opacity_in_smaller_steps_than_lines() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let lines = largest_step(&gpu, &combed_settings(32));
    let mut steps = Vec::new();
    for w in [2.0, 4.0] {
        let mut s = combed_settings(32);
        ribbons(&mut s, w);
        steps.push(largest_step(&gpu, &s));
    }
    eprintln!(
        "largest step: lines {lines:.3}, ribbons (2 texels) {:.3}, (4 texels) {:.3}",
        steps[0], steps[1]
    );
    assert!(lines > 1.0, "lines: largest step {lines}");
    assert!(
        steps[0] < 0.6 * lines,
        "ribbons (2 texels) {} against lines {lines}",
        steps[0]
    );
    assert!(
        steps[1] < 0.6 * steps[0],
        "ribbons (4 texels) {} against 2 texels {}",
        steps[1],
        steps[0]
    );
}
