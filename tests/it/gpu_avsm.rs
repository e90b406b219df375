//! Adaptive volumetric shadow maps on the GPU (`hairlab::methods::avsm`: its own A-buffer, then the compression
//! pass) against the CPU model `visibility::avsm`, fed each texel's exact fragment list (with segments) from the
//! reference A-buffer: N from 4 to 16, both insertion orders, map resolutions 1 (179, about 700 and about 2100
//! fragments in one list, the longer sorted and walked over several dispatches on a CPU adapter) to 512, hair
//! alphas from nearly clear to opaque; memory, geometry passes and the storage-size limit.

use crate::common;

use crate::common::{Setup, gpu_cpu_differences};
use hairlab::gpu::{Gpu, GpuError};
use hairlab::methods::registry;
use hairlab::render::Renderer;

const ORDERS: [f32; 2] = [0.0, 1.0];

/// |ΔV| of every sample and the method's stated tolerance and outlier share.
fn check(gpu: &Gpu, nodes: f32, order: f32, setup: Setup) -> (f32, usize) {
    let info = registry::find("avsm").unwrap().info();
    let d = gpu_cpu_differences(gpu, "avsm", &[("nodes", nodes), ("order", order)], setup);
    let worst = d.iter().copied().fold(0.0f32, f32::max);
    let beyond = d.iter().filter(|&&x| x > info.gpu_tolerance).count();
    eprintln!(
        "avsm N={nodes} order={order} {setup:?}: {} samples, max |ΔV| {worst:.3e}, {beyond} beyond {:.0e}",
        d.len(),
        info.gpu_tolerance
    );
    assert!(
        beyond as f64 <= info.gpu_outliers * d.len() as f64,
        "N={nodes} order={order} {setup:?}: {beyond} of {} samples beyond {} (max {worst})",
        d.len(),
        info.gpu_tolerance
    );
    (worst, d.len())
}

#[test]
fn avsm_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for order in ORDERS {
        for nodes in [4.0, 5.0, 8.0, 12.0, 16.0] {
            let (_, n) = check(&gpu, nodes, order, Setup::new(300, 64));
            assert!(n > 5000, "only {n} samples");
        }
    }
}

#[test]
fn extreme_resolutions_and_alphas() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for order in ORDERS {
        // One texel: the 179 fragments of 250 strands crossing its centre in one list, sorted in five passes and
        // walked in six batches of 32, each in one dispatch on a CPU adapter.
        for nodes in [8.0, 16.0] {
            let (_, n) = check(&gpu, nodes, order, Setup::new(250, 1));
            assert!(n > 150, "only {n} samples");
        }
        for hair_alpha in [0.01, 1.0] {
            // Under 100 strands: the harness asks no texel to fall below V = 1/2 (none does at alpha 0.01).
            let setup = Setup {
                hair_alpha: Some(hair_alpha),
                ..Setup::new(60, 64)
            };
            for nodes in [4.0, 16.0] {
                let (_, n) = check(&gpu, nodes, order, setup);
                assert!(n > 1000, "only {n} samples");
            }
        }
        let (_, n) = check(&gpu, 16.0, order, Setup::new(40, 512));
        assert!(n > 5000, "only {n} samples");
    }
}

fn render_light_at(gpu: &Gpu, resolution: u32, nodes: f32) -> (Renderer, Result<(), GpuError>) {
    render_light_with(gpu, 20, resolution, nodes)
}

fn render_light_with(
    gpu: &Gpu,
    strands: u32,
    resolution: u32,
    nodes: f32,
) -> (Renderer, Result<(), GpuError>) {
    common::render_method_light(gpu, "avsm", &[("nodes", nodes)], strands, resolution)
}

#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for nodes in [4u64, 16] {
        let (r, result) = render_light_at(&gpu, 512, nodes as f32);
        result.unwrap();
        let m = r.method_gpu(registry::find("avsm").unwrap()).unwrap();
        // The node buffer alone: N nodes of two f32 per texel; the A-buffer (at least its 4-byte heads per
        // texel) is build memory.
        assert_eq!(m.memory_bytes(), 512 * 512 * nodes * 8);
        assert!(m.build_bytes() >= 512 * 512 * 4, "{}", m.build_bytes());
        assert_eq!(m.shared_bytes(), 0);
        // The A-buffer's counting and filling passes.
        assert_eq!(m.geometry_passes(), 2);
    }
}

#[test]
fn node_buffers_beyond_the_storage_binding_size_are_refused() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size;
    // 16 nodes at 2048²: 512 MiB, four times lavapipe's 128 MiB binding limit.
    let resolution = 2048u32;
    let bytes = resolution as u64 * resolution as u64 * 16 * 8;
    let (_r, result) = render_light_at(&gpu, resolution, 16.0);
    if bytes > limit {
        match result {
            Err(GpuError::TooLarge {
                bytes: b,
                limit: l,
                what,
            }) => {
                assert_eq!((b, l), (bytes, limit));
                assert!(what.contains("hairlab.avsm.nodes"), "{what}");
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
    } else {
        result.unwrap();
    }
}

/// A texel list beyond what one dispatch walks on a CPU adapter (lavapipe: 17 batches of 32, 544 fragments) is
/// compressed over several dispatches, each resuming where the one before stopped, and still equals the CPU model:
/// one texel holding the fragments of 1000 strands (about 700: sorted in one dispatch, walked in two on lavapipe,
/// one each on another adapter) and of 3000 strands (about 2100: the sort's nine passes over two dispatches, the
/// walk over four).
#[test]
fn long_lists_compress_over_several_dispatches() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for order in ORDERS {
        let (_, n) = check(&gpu, 8.0, order, Setup::new(1000, 1));
        assert!(n > 600, "only {n} samples");
    }
    let (_, n) = check(&gpu, 8.0, ORDERS[0], Setup::new(3000, 1));
    assert!(n > 1800, "only {n} samples");
}

/// On a device whose storage bindings hold 4096 list nodes, the A-buffer's lists span several node pages: the sort
/// relinks them and the walk reads them through the accesses made for that page count (`list_pages` in
/// `shaders/common/list_node.wgsl`), and the nodes still equal the CPU model's in both insertion orders.
#[test]
fn lists_over_several_pages_sort_and_compress_as_the_cpu_model() {
    use crate::common::{gpu_cpu_differences_in, setup_scene};
    use hairlab::gpu::AdapterPreference;
    use hairlab::render::passes::abuffer::NODE_BYTES;
    const PAGE_BYTES: u64 = 64 << 10;
    let Some(_) = Gpu::for_tests() else { return };
    let pref = AdapterPreference::from_env_or(AdapterPreference::Software);
    let paged = Gpu::headless_with_binding_limit(pref, PAGE_BYTES).unwrap();
    let info = registry::find("avsm").unwrap().info();
    let (s, scene) = setup_scene(Setup::new(3000, 16));
    let mut r = Renderer::new(&paged, &scene, s.render.map_resolution).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let total: usize = lists.iter().map(Vec::len).sum();
    let pages = total.div_ceil((PAGE_BYTES / NODE_BYTES) as usize);
    assert!((3..=8).contains(&pages), "{total} fragments: {pages} pages");
    for order in ORDERS {
        let d = gpu_cpu_differences_in(
            &paged,
            "avsm",
            &[("nodes", 8.0), ("order", order)],
            &s,
            &scene,
            true,
        );
        let worst = d.iter().copied().fold(0.0f32, f32::max);
        eprintln!(
            "avsm order={order}, {total} fragments in {pages} pages: {} samples, max |ΔV| {worst:.3e}",
            d.len()
        );
        assert!(d.len() > 1000, "only {} samples", d.len());
        assert!(worst <= info.gpu_tolerance, "order {order}: max |ΔV| {worst}");
    }
}
