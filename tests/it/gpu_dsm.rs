//! Compressed deep shadow maps on the GPU (`hairlab::methods::dsm`): the exact property `|V - V_ref| <= ε` read
//! through the WGSL lookup at every fragment depth, just before and after each and a 16-point grid of every
//! occupied texel, for each ε of the sweep (0, 0.01, 0.05, 0.1) and 0.5; GPU = CPU model on the same samples;
//! memory (headers and exactly the vertices the compressor keeps, as many as the CPU model's) and geometry passes.

use crate::common::small_settings;
use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::Renderer;
use hairlab::visibility::{Fragment, metrics, reference};

/// f32 rounding on top of ε: the GPU sums, divides and takes `exp`/`log` in f32 (Vulkan allows 2.5 ulp for a
/// division, 3 + 2|x| ulp for `exp`), the reference sums in f64. Measured maximum of |V_gpu - V_ref| - ε: 6.0e-8
/// at ε = 0, below 0 for the other ε (printed per ε by `gpu_is_within_epsilon_of_the_reference`).
const ROUNDING: f32 = 1e-6;

/// GPU = CPU model (the method's `gpu_tolerance`): the same f32 expressions in the same order but for the sums at
/// one depth; measured 7.7e-7 (ε = 0.1).
const GPU_CPU: f32 = 1e-5;

/// Per sample: (|V_gpu - V_ref|, |V_gpu - V_cpu|) on the 300-strand test scene at `resolution`² with `epsilon`.
fn differences(gpu: &Gpu, epsilon: f32, strands: u32, resolution: u32) -> Vec<(f32, f32)> {
    let (s, scene) = crate::common::setup_scene(crate::common::Setup::new(strands, resolution));
    let method = registry::find("dsm").unwrap();
    let values = ParamValues::from([("epsilon".to_string(), epsilon)]);
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    r.render(&crate::common::light_frame(&s, method, &values))
        .unwrap();
    r.read_output().unwrap();
    let model = method.model(&values, s.render.hair_alpha);
    let (mut samples, mut exact, mut cpu) = (Vec::new(), Vec::new(), Vec::new());
    for (t, list) in lists.iter().enumerate() {
        let frags: Vec<Fragment> = list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
        let mut zs = metrics::sample_depths(&frags, 16);
        zs.extend(
            frags
                .iter()
                .flat_map(|f| [f.depth.next_down(), f.depth.next_up()]),
        );
        if frags.is_empty() {
            zs.extend([-1.0, 0.0, 0.5, 1.0, 2.0]);
        }
        let (x, y) = ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
        exact.extend(zs.iter().map(|&z| reference::visibility(&frags, z)));
        cpu.extend(model.curve(&frags, &zs));
        samples.extend(zs.iter().map(|&z| [x, y, z]));
    }
    let got = r.evaluate(method, &samples).unwrap();
    assert!(got.iter().all(|v| (0.0..=1.0).contains(v)), "V outside [0, 1]");
    got.iter()
        .zip(exact.iter().zip(&cpu))
        .map(|(g, (e, c))| ((g - e).abs(), (g - c).abs()))
        .collect()
}

#[test]
fn gpu_is_within_epsilon_of_the_reference() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for epsilon in [0.0, 0.01, 0.05, 0.1, 0.5] {
        let d = differences(&gpu, epsilon, 300, 64);
        let beyond = d.iter().map(|(e, _)| e - epsilon).fold(f32::MIN, f32::max);
        let worst_cpu = d.iter().map(|(_, c)| *c).fold(0.0f32, f32::max);
        let cpu_beyond = d.iter().filter(|(_, c)| *c > GPU_CPU).count();
        eprintln!(
            "dsm ε {epsilon}: {} samples, max |V_gpu - V_ref| - ε = {beyond:.3e}, max |V_gpu - V_cpu| = \
             {worst_cpu:.3e} ({cpu_beyond} beyond {GPU_CPU:e})",
            d.len()
        );
        assert!(d.len() > 10000, "only {} samples", d.len());
        assert!(
            beyond <= ROUNDING,
            "ε {epsilon}: |V_gpu - V_ref| exceeds ε by {beyond}"
        );
        assert!(worst_cpu <= GPU_CPU, "ε {epsilon}: |V_gpu - V_cpu| = {worst_cpu}");
    }
}

#[test]
fn extreme_resolutions() {
    let Some(gpu) = Gpu::for_tests() else { return };
    // 250 strands in one texel: 179 fragments, sorted in five passes and walked in six batches of 32, each in one
    // dispatch on a CPU adapter.
    for (strands, resolution) in [(250, 1), (20, 1024)] {
        for epsilon in [0.0, 0.1] {
            let d = differences(&gpu, epsilon, strands, resolution);
            let beyond = d.iter().map(|(e, _)| e - epsilon).fold(f32::MIN, f32::max);
            eprintln!("dsm ε {epsilon}, {strands} strands at {resolution}²: max |ΔV_ref| - ε = {beyond:.3e}");
            assert!(beyond <= ROUNDING, "ε {epsilon} at {resolution}²: {beyond}");
        }
    }
}

#[test]
fn memory_is_the_vertex_count() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small_settings(8, 8);
    s.scene.generator.strands = 300;
    s.render.map_resolution = 128;
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(&gpu, &scene, 128).unwrap();
    let lists: Vec<Vec<Fragment>> = r
        .reference_lists(&s.camera, &s.light, &s.render)
        .unwrap()
        .iter()
        .map(|l| l.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect())
        .collect();
    let method = registry::find("dsm").unwrap();
    for epsilon in [0.0, 0.01, 0.1] {
        let values = ParamValues::from([("epsilon".to_string(), epsilon)]);
        let model = method.model(&values, s.render.hair_alpha);
        let vertices: u64 = lists.iter().map(|l| model.stored_values(l)[0] as u64).sum();
        r.render_light(&crate::common::light_frame(&s, method, &values))
            .unwrap();
        let m = r.method_gpu(method).unwrap();
        eprintln!(
            "dsm ε {epsilon}: {} bytes for {vertices} vertices of the CPU model at 128²",
            m.memory_bytes()
        );
        assert!(vertices > 1000, "only {vertices} vertices");
        // Headers (offset, count) 8 bytes per texel, vertices (z, V) 8 bytes each, as many as the CPU model keeps.
        assert_eq!(m.memory_bytes(), 128 * 128 * 8 + vertices * 8, "ε {epsilon}");
        assert_eq!(m.shared_bytes(), 0);
        // The A-buffer's count and fill: the compressor walks the lists the vertex count sorted.
        assert_eq!(m.geometry_passes(), 2);
    }
}

/// The compressor takes each list as AVSM's does, sorted over several dispatches on a CPU adapter when a list is
/// long (one texel holding the fragments of 3000 strands, about 2100: the sort's nine passes over two dispatches
/// on lavapipe, the walk in one), and still equals the CPU model. The A-buffer it compresses is its build memory.
#[test]
fn long_lists_compress_over_several_dispatches() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let info = registry::find("dsm").unwrap().info();
    let d = crate::common::gpu_cpu_differences(
        &gpu,
        "dsm",
        &[("epsilon", 0.01)],
        crate::common::Setup::new(3000, 1),
    );
    let worst = d.iter().copied().fold(0.0f32, f32::max);
    eprintln!(
        "dsm ε 0.01, one texel of 3000 strands: {} samples, max |ΔV| {worst:.3e}",
        d.len()
    );
    assert!(d.len() > 1800, "only {} samples", d.len());
    assert!(worst <= info.gpu_tolerance, "max |ΔV| {worst}");
    let (r, result) = crate::common::render_method_light(&gpu, "dsm", &[], 60, 64);
    result.unwrap();
    let m = r.method_gpu(registry::find("dsm").unwrap()).unwrap();
    assert!(m.build_bytes() >= 64 * 64 * 4, "{}", m.build_bytes());
}
