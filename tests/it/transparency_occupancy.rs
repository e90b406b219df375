//! GPU tests of the occupancy-order eye transparency technique (S&A 2009 §3.4) on the software adapter: its
//! memory and geometry passes, its refusal of viewports beyond the storage binding size, and TC-6 (the
//! per-pixel fragment count `n` from the slab map is the exact count).

use crate::common;
use crate::transparency_gpu::{eye_frame, eye_scene, gpu_cpu_difference};

use hairlab::gpu::{Gpu, GpuError};
use hairlab::methods::registry as methods;
use hairlab::render::transparency::{occupancy_order, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;

/// The small test head (`strands` strands of 10 segments) framed, drawn with occupancy-order and `params`.
fn settings(strands: u32, width: u32, height: u32, params: &[(&str, f32)]) -> Settings {
    let mut s = common::small_settings(width, height);
    s.scene.generator.strands = strands;
    s.scene.generator.segments = 10;
    s.transparency.name = "occupancy-order".into();
    s.transparency.params = common::values(params);
    s
}

fn frame<'a>(s: &'a Settings, width: u32, height: u32) -> FrameInput<'a> {
    FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method: methods::find(&s.method.name).unwrap(),
        method_params: &s.method.params,
        technique: s.transparency.technique().unwrap(),
        technique_params: &s.transparency.params,
        width,
        height,
    }
}

fn renderer(gpu: &Gpu, s: &mut Settings) -> Renderer {
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    Renderer::new(gpu, &scene, s.render.map_resolution).unwrap()
}

/// 56 bytes per pixel at f32 (depth range 8, bitmap 16, slabs 16, accumulation 16), 48 at f16; 3 geometry passes.
#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = settings(50, 40, 30, &[]);
    let mut r = renderer(&gpu, &mut s);
    r.render(&frame(&s, 40, 30)).unwrap();
    let m = r.memory();
    assert_eq!(m.transparency_name, "occupancy-order");
    assert_eq!(m.transparency_targets, 40 * 30 * 56);
    assert_eq!(r.transparency_gpu().unwrap().geometry_passes(), 3);
    s.transparency.params = common::values(&[("precision", 1.0)]);
    r.render(&frame(&s, 40, 30)).unwrap();
    assert_eq!(r.memory().transparency_targets, 40 * 30 * 48);
    r.render(&frame(&s, 20, 10)).unwrap();
    assert_eq!(r.memory().transparency_targets, 20 * 10 * 48);
}

/// A viewport whose bitmap (16 bytes per pixel) exceeds the storage binding size is refused before allocation,
/// naming the viewport.
#[test]
fn a_viewport_beyond_the_storage_binding_size_is_refused() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    let width = 4096u32;
    let height = (limit / 16 / width as u64) as u32 + 1;
    let mut s = settings(20, width, height, &[]);
    let mut r = renderer(&gpu, &mut s);
    match r.render(&frame(&s, width, height)) {
        Err(e @ GpuError::TooLarge { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains(&format!("{width}×{height} viewport")), "{msg}");
        }
        other => panic!("expected TooLarge, got {other:?}"),
    }
}

/// TC-6 (S&A §3.4: the background is multiplied by (1 - α)^n, n the sum of the four slabs): per pixel, n from
/// the slab map (and the occupancy-only total) equals the exact fragment count of the reference's lists, so the
/// occupancy pass keeps exactly the hair pass's fragments (meshes tested by hand before its atomics).
#[test]
fn slab_counts_are_the_exact_fragment_counts() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 160, 120);
    let technique = registry::find("occupancy-order").unwrap();
    let deepest = lists.iter().map(Vec::len).max().unwrap();
    assert!(deepest >= 8, "deepest pixel {deepest}");
    for variant in [0.0, 1.0] {
        let params = common::values(&[("variant", variant)]);
        r.render(&eye_frame(&s, technique, &params)).unwrap();
        let slabs = occupancy_order::read_slabs(&r).unwrap();
        assert_eq!(slabs.len(), lists.len());
        let mut wrong = 0;
        for (counts, list) in slabs.iter().zip(&lists) {
            wrong += usize::from(counts.iter().sum::<u32>() as usize != list.len());
            if variant == 1.0 {
                assert_eq!(counts[1..], [0, 0, 0], "occupancy-only keeps its count in slab 0");
            }
        }
        let hair = lists.iter().filter(|l| !l.is_empty()).count();
        println!(
            "variant {variant}: n = exact count on {} of {} pixels ({hair} hair, deepest {deepest})",
            lists.len() - wrong,
            lists.len()
        );
        assert_eq!(
            wrong, 0,
            "variant {variant}: pixels whose slab sum is not the exact count"
        );
    }
}

/// GPU = CPU for every option (the registry-wide test covers the defaults): the largest per-channel |ΔC| of
/// each stays within the technique's tolerance, the f16 accumulation within its own.
#[test]
fn every_option_gpu_equals_the_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, mut r, lists) = eye_scene(&gpu, 96, 72);
    let technique = registry::find("occupancy-order").unwrap();
    for (key, v) in [
        ("variant", 1.0),
        ("correction", 1.0),
        ("order_bias", 1.0),
        ("precision", 1.0),
    ] {
        let params = common::values(&[(key, v)]);
        let (worst, hair) = gpu_cpu_difference(&s, &mut r, &lists, technique, &params);
        println!("{key} = {v}: max |C_gpu - C_cpu| = {worst:.2e} over {hair} hair pixels");
        let tolerance = if key == "precision" {
            occupancy_order::F16_GPU_TOLERANCE
        } else {
            technique.info().gpu_tolerance
        };
        assert!(worst <= tolerance, "{key} = {v}: {worst} > {tolerance}");
    }
}
