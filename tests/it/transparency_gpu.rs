//! GPU = CPU for every eye transparency technique: each technique's resolve captured in f32 (the hair's
//! premultiplied colour H and coverage 1 - T per pixel) against its CPU model fed that pixel's exact fragment
//! list, read back from the reference's per-pixel lists.

use crate::common::small_settings;
use hairlab::gpu::Gpu;
use hairlab::render::method::ParamValues;
use hairlab::render::transparency::{EyeTransparency, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::transparency::{EyeFragment, ModelContext};

pub fn eye_frame<'a>(
    s: &'a Settings,
    technique: &'static dyn EyeTransparency,
    params: &'a ParamValues,
) -> FrameInput<'a> {
    FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method: hairlab::methods::registry::find(&s.method.name).unwrap(),
        method_params: &s.method.params,
        technique,
        technique_params: params,
        width: s.render.width,
        height: s.render.height,
    }
}

/// The small head at `width`×`height` with its camera framed, its renderer and the exact lists.
pub fn eye_scene(gpu: &Gpu, width: u32, height: u32) -> (Settings, Renderer, Vec<Vec<EyeFragment>>) {
    let mut s = small_settings(width, height);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution).unwrap();
    let empty = ParamValues::new();
    let lists = r
        .eye_lists(&eye_frame(&s, registry::reference(), &empty))
        .unwrap();
    (s, r, lists)
}

/// Largest per-channel |GPU - CPU| of `technique` with `params` on the captured frame, and the hair pixels.
pub fn gpu_cpu_difference(
    s: &Settings,
    r: &mut Renderer,
    lists: &[Vec<EyeFragment>],
    technique: &'static dyn EyeTransparency,
    params: &ParamValues,
) -> (f32, usize) {
    let captured = r.render_capture(&eye_frame(s, technique, params)).unwrap();
    assert_eq!(captured.len(), lists.len());
    let ctx = ModelContext {
        hair_alpha: s.render.hair_alpha,
        depth_range: r.eye_depth_range(&s.camera),
    };
    let model = technique.model(params, &ctx);
    let mut worst = 0.0f32;
    for (p, (gpu, list)) in captured.iter().zip(lists).enumerate() {
        let h = model.composite(list, [0.0; 3]);
        let white = model.composite(list, [1.0; 3]);
        let coverage = 1.0 - (white[0] - h[0]);
        for (c, (g, m)) in gpu.iter().zip(h.iter().chain([&coverage])).enumerate() {
            assert!(
                g.is_finite(),
                "{}: pixel {p} channel {c} is {g}",
                technique.name()
            );
            worst = worst.max((g - m).abs());
        }
    }
    (worst, lists.iter().filter(|l| !l.is_empty()).count())
}

#[test]
fn every_registered_technique_gpu_equals_its_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 160, 120);
    let hair = lists.iter().filter(|l| !l.is_empty()).count();
    let deepest = lists.iter().map(Vec::len).max().unwrap_or(0);
    assert!(
        hair > 2000 && deepest >= 8,
        "a non-trivial view: {hair} hair pixels, deepest {deepest}"
    );
    let defaults = ParamValues::new();
    for t in registry::all() {
        let (worst, _) = gpu_cpu_difference(&s, &mut r, &lists, *t, &defaults);
        println!(
            "{}: max |C_gpu - C_cpu| = {worst:.2e} over {hair} hair pixels (deepest {deepest})",
            t.name()
        );
        assert!(
            worst <= t.info().gpu_tolerance,
            "{}: {worst} > {}",
            t.name(),
            t.info().gpu_tolerance
        );
    }
}

/// The lists hold every fragment the count pass counted, each pixel's front to back on (depth, segment) with
/// no repeated key, and no fragment is shaded to a non-finite colour or an alpha outside [0, 1].
#[test]
fn the_reference_lists_are_complete_and_totally_ordered() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (_, r, lists) = eye_scene(&gpu, 96, 72);
    let (deepest, total) = r.eye_depth_complexity().unwrap();
    assert_eq!(lists.iter().map(Vec::len).sum::<usize>() as u64, total);
    assert_eq!(lists.iter().map(Vec::len).max().unwrap() as u32, deepest);
    for l in &lists {
        for w in l.windows(2) {
            assert!(
                (w[0].depth.to_bits(), w[0].segment) < (w[1].depth.to_bits(), w[1].segment),
                "{w:?}"
            );
        }
        for f in l {
            assert!(f.color.iter().all(|c| c.is_finite() && *c >= 0.0) && (0.0..=1.0).contains(&f.alpha));
        }
    }
}

/// Depth peeling (TC-2): a count pass that counts what the reference counts, then one layer per fragment of the
/// deepest pixel; a frame deeper than `max_layers` is refused, naming the key, and exactly as deep is peeled.
#[test]
fn depth_peel_peels_the_deepest_pixels_layers_and_refuses_more_than_max_layers() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 96, 72);
    let reference = r.eye_depth_complexity().unwrap();
    let deepest = reference.0;
    assert_eq!(deepest as usize, lists.iter().map(Vec::len).max().unwrap());
    let peel = registry::find("depth-peel").unwrap();
    let mut params = ParamValues::new();
    r.render(&eye_frame(&s, peel, &params)).unwrap();
    assert_eq!(r.eye_depth_complexity(), Some(reference));
    assert_eq!(r.eye_geometry_passes(), deepest + 1);
    params.insert("max_layers".into(), (deepest - 1) as f32);
    assert_eq!(
        r.render(&eye_frame(&s, peel, &params)).unwrap_err().to_string(),
        format!(
            "transparency.max_layers: depth peel did not finish within {} layers (the deepest pixel has {deepest} \
             fragments)",
            deepest - 1
        )
    );
    params.insert("max_layers".into(), deepest as f32);
    r.render(&eye_frame(&s, peel, &params)).unwrap();
    assert_eq!(r.eye_geometry_passes(), deepest + 1);
}

/// Bands: with a list budget far below the frame's fragments the reference renders in several bands of rows,
/// to the same image, bit for bit.
#[test]
fn the_reference_in_bands_equals_the_reference_in_one() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 160, 120);
    let fragments: usize = lists.iter().map(Vec::len).sum();
    let empty = ParamValues::new();
    let one = r
        .render_capture(&eye_frame(&s, registry::reference(), &empty))
        .unwrap();
    assert_eq!(r.eye_geometry_passes(), 2, "count + one fill");
    let banded = ParamValues::from([("band_kib".to_string(), 64.0)]);
    let many = r
        .render_capture(&eye_frame(&s, registry::reference(), &banded))
        .unwrap();
    let bands = r.eye_geometry_passes() - 1;
    let expected = (fragments as u64 * 32).div_ceil(64 << 10) as u32;
    println!("{fragments} fragments: {bands} bands of at most 64 KiB");
    assert!(
        bands >= expected.max(2),
        "{bands} bands for {fragments} fragments"
    );
    assert!(one == many, "banded and single-band images differ");
}

/// TC-9: depth peeling is exact except where two fragments of a pixel share a depth (its strict test keeps one):
/// on every pixel without a tie it equals the sorted composite to f32 rounding.
#[test]
fn depth_peeling_equals_the_sorted_composite_except_at_depth_ties() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 96, 72);
    let empty = ParamValues::new();
    let sorted = r
        .render_capture(&eye_frame(&s, registry::reference(), &empty))
        .unwrap();
    let peel = registry::find("depth-peel").unwrap();
    let peeled = r.render_capture(&eye_frame(&s, peel, &empty)).unwrap();
    let tied = |l: &Vec<EyeFragment>| l.windows(2).any(|w| w[0].depth == w[1].depth);
    let (mut ties, mut worst) = (0, 0.0f32);
    for ((a, b), l) in sorted.iter().zip(&peeled).zip(&lists) {
        if tied(l) {
            ties += 1;
            continue;
        }
        worst = (0..4).map(|c| (a[c] - b[c]).abs()).fold(worst, f32::max);
    }
    println!("depth peel vs sorted: max |Δ| {worst:.2e} off ties; {ties} pixels with a depth tie");
    assert!(worst <= 1e-5, "{worst}");
}

/// A row of the view whose fragments exceed one band is refused with a message naming the row, the view, its
/// fragments and the budget (here a 1 KiB band budget: 32 nodes), never a truncated image.
#[test]
fn a_row_over_the_band_budget_is_refused_by_name() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, _) = eye_scene(&gpu, 160, 120);
    let tiny = ParamValues::from([("band_kib".to_string(), 1.0)]);
    let e = r
        .render(&eye_frame(&s, registry::reference(), &tiny))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("transparency.params.band_kib: the exact eye reference's row ")
            && e.contains("of a 160x120 view (")
            && e.ends_with("more than the band budget of 1024 bytes"),
        "{e}"
    );
}

/// A pixel deeper than the exact reference's largest sort (1024 fragments) is refused with a message naming the
/// limit, the view and the pixel's depth, never resolved from a truncated list: 1100 horizontal strands at
/// different depths all cross the view's centre.
#[test]
fn a_pixel_deeper_than_the_sort_is_refused_by_name() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let n = 1100;
    let strands = hairlab::scene::Strands {
        points: (0..n)
            .flat_map(|i| {
                let z = i as f32 / n as f32 - 0.5;
                [glam::Vec3::new(-1.0, 0.0, z), glam::Vec3::new(1.0, 0.0, z)]
            })
            .collect(),
        counts: vec![2; n],
        ..Default::default()
    };
    let scene = hairlab::scene::Scene::new(strands, Vec::new());
    let mut s = crate::common::small_settings(64, 49);
    s.camera = hairlab::scene::Camera {
        yaw_deg: 0.0,
        pitch_deg: 0.0,
        ..Default::default()
    };
    s.camera.frame(&scene.bounds());
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let empty = ParamValues::new();
    let e = r
        .render(&eye_frame(&s, registry::reference(), &empty))
        .unwrap_err()
        .to_string();
    let deepest: u32 = e
        .rsplit(' ')
        .next()
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("no depth at the end of: {e}"));
    assert!(
        e.starts_with(
            "transparency.name: the exact reference sorts at most 1024 fragments per pixel, and a pixel of this \
             64x49 view has "
        ) && deepest > 1024,
        "{e}"
    );
}
