//! The opacity-layer family's two builds on the GPU (`methods::opacity_layers`, CPU side
//! `visibility::opacity_layers`): GPU = CPU for the colour-target build and for the atomic build in every
//! storage, the atomic build in bands when its counters exceed a storage binding, the refusal when not even a
//! band of 4 entries fits, and the memory the report counts for each storage.

use crate::common::{
    Setup, gpu_cpu_difference, gpu_cpu_differences_on, light_frame, render_method_light, setup_scene, values,
};
use hairlab::gpu::{Gpu, GpuError};
use hairlab::methods::opacity_layers::CounterLayout;
use hairlab::methods::registry;
use hairlab::render::Renderer;

/// The family's stated `gpu_tolerance`. Measured max |ΔV| on lavapipe, the 300-strand head at 64² (OSM-64,
/// DOM-3, BOM-4), every build and storage: 1.8e-7 (targets: f32 sums in another order; atomic: integer sums, so
/// only `exp` and the rounding of `b = -ln(1 - alpha)` in WGSL against Rust's, and the u8 unorm read); OSM-256
/// atomic in two bands at 512²: 1.8e-7.
const TOLERANCE: f32 = 1e-4;

/// Each method of the family with its entry-count parameter at a usual value.
const FAMILY: [(&str, &str, f32); 3] = [
    ("osm", "slices", 64.0),
    ("dom", "layers", 3.0),
    ("bom", "layers", 4.0),
];

/// `(build, storage)` (build 1 atomic, 2 targets): targets, then atomic with f32, f16 and u8.
const BUILDS: [(f32, f32); 4] = [(2.0, 0.0), (1.0, 0.0), (1.0, 1.0), (1.0, 2.0)];

#[test]
fn both_builds_and_every_storage_gpu_equal_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (method, key, n) in FAMILY {
        for (build, storage) in BUILDS {
            let params = [(key, n), ("build", build), ("storage", storage)];
            let (worst, samples) = gpu_cpu_difference(&gpu, method, &params, Setup::new(300, 64));
            eprintln!("{method} {params:?}: {samples} samples, max |ΔV| {worst:.3e}");
            assert!(samples > 5000, "{method}: only {samples} samples");
            assert!(worst <= TOLERANCE, "{method} {params:?}: max |ΔV| = {worst}");
        }
    }
}

/// The 300-strand test head at 64², lit as the preset lights it and by a light turned 90° (and mirrored in
/// elevation), and a renderer for it.
fn two_lights(gpu: &Gpu) -> (hairlab::settings::Settings, hairlab::settings::Settings, Renderer) {
    let (first, scene) = setup_scene(Setup::new(300, 64));
    let mut turned = first.clone();
    turned.light.azimuth_deg += 90.0;
    turned.light.elevation_deg = -first.light.elevation_deg;
    let r = Renderer::new(gpu, &scene, 64).unwrap();
    (first, turned, r)
}

/// The atomic build skips the layers the map holds as zero already (an empty texel's once cleared, an occupied
/// one's in front of its first fragment): after a frame lit from one side, a frame lit from another (texels
/// occupied before are empty now, and the reverse; first fragments move between slices) equals the CPU model
/// everywhere, empty texels reading V = 1. Every storage, OSM-64 at 64².
#[test]
fn atomic_build_leaves_nothing_of_the_previous_frame() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (first, turned, mut r) = two_lights(&gpu);
    let occupied = |s: &hairlab::settings::Settings, r: &mut Renderer| -> Vec<bool> {
        let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
        lists.iter().map(|l| !l.is_empty()).collect()
    };
    let (before, after) = (occupied(&first, &mut r), occupied(&turned, &mut r));
    let emptied = before.iter().zip(&after).filter(|(b, a)| **b && !**a).count();
    assert!(emptied > 100, "only {emptied} texels go from occupied to empty");
    for storage in [0.0, 1.0, 2.0] {
        let params = [("slices", 64.0), ("build", 1.0), ("storage", storage)];
        let values = values(&params);
        r.render(&light_frame(&first, registry::find("osm").unwrap(), &values))
            .unwrap();
        let d = gpu_cpu_differences_on(&mut r, "osm", &params, &turned, true);
        let worst = d.iter().copied().fold(0.0f32, f32::max);
        assert!(d.len() > 5000, "only {} samples", d.len());
        assert!(worst <= TOLERANCE, "storage {storage}: max |ΔV| = {worst}");
        // Every emptied texel, through the whole light range: nothing in front, V = 1.
        let samples: Vec<[f32; 3]> = (0..before.len())
            .filter(|t| before[*t] && !after[*t])
            .flat_map(|t| [0.0, 0.5, 1.0].map(|z| [(t % 64) as f32, (t / 64) as f32, z]))
            .collect();
        let v = r.evaluate(registry::find("osm").unwrap(), &samples).unwrap();
        let darkest = v.iter().copied().fold(1.0f32, f32::min);
        eprintln!(
            "storage {storage}: {} samples after the turn, max |ΔV| {worst:.3e}; {emptied} texels emptied, \
             darkest V there {darkest}",
            d.len()
        );
        assert_eq!(
            darkest, 1.0,
            "storage {storage}: an emptied texel keeps the previous frame's shadow"
        );
    }
}

/// The atomic build skips a layer that holds the sum of the texel's flat tail again within the map's tail (where
/// every layer holds its total): after a frame whose fragments end in other layers, the next equals the CPU model
/// everywhere. DOM-16 at 64² (one run) with every fragment kept (`beyond = add-to-last`, so each texel's total is
/// the same whatever the span) from a span of 0.05 (most fragments in the last layer) to 0.5 (spread out) and
/// back; OSM-256 (four runs, the tail's start carried across them) from one light to one turned 90° and back;
/// OSM-64 under one light from f32 to u8 storage (a new map: nothing of the old one's tails holds in it). Each
/// texel is also looked up behind all its strands (depth 1, in the tail), where the harness's samples do not go.
#[test]
fn atomic_build_reuses_the_flat_tail_only_where_it_holds() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (first, turned, mut r) = two_lights(&gpu);
    let dom = |span: f32| {
        vec![
            ("layers", 16.0),
            ("depth_span", span),
            ("spacing", 1.0),
            ("beyond", 1.0),
            ("build", 1.0),
        ]
    };
    let osm = vec![("slices", 256.0), ("build", 1.0)];
    let stored = |storage: f32| vec![("slices", 64.0), ("build", 1.0), ("storage", storage)];
    let cases = [
        ("dom", dom(0.05), &first, dom(0.5), &first),
        ("dom", dom(0.5), &first, dom(0.05), &first),
        ("osm", osm.clone(), &first, osm.clone(), &turned),
        ("osm", osm.clone(), &turned, osm, &first),
        ("osm", stored(0.0), &first, stored(2.0), &first),
    ];
    for (method, before, lit_before, after, lit_after) in cases {
        let m = registry::find(method).unwrap();
        r.render(&light_frame(lit_before, m, &values(&before))).unwrap();
        let mut d = gpu_cpu_differences_on(&mut r, method, &after, lit_after, true);
        let lists = r
            .reference_lists(&lit_after.camera, &lit_after.light, &lit_after.render)
            .unwrap();
        let model = m.model(&values(&after), lit_after.render.hair_alpha);
        let (mut behind, mut expected) = (Vec::new(), Vec::new());
        for (t, list) in lists.iter().enumerate().filter(|(_, l)| !l.is_empty()) {
            let frags: Vec<_> = list.iter().map(|f| f.fragment()).collect();
            behind.push([(t % 64) as f32, (t / 64) as f32, 1.0]);
            expected.extend(model.curve(&frags, &[1.0]));
        }
        let got = r.evaluate(m, &behind).unwrap();
        d.extend(got.iter().zip(&expected).map(|(a, b)| (a - b).abs()));
        let worst = d.iter().copied().fold(0.0f32, f32::max);
        eprintln!(
            "{method} {before:?} -> {after:?}: {} samples ({} behind the strands), max |ΔV| {worst:.3e}",
            d.len(),
            behind.len()
        );
        assert!(behind.len() > 500, "only {} occupied texels", behind.len());
        assert!(
            worst <= TOLERANCE,
            "{method} {before:?} -> {after:?}: max |ΔV| = {worst}"
        );
    }
}

/// OSM-256 at 512²: 256 slices of 4-byte counters over 262 144 texels take 256 MiB, two of lavapipe's 128 MiB
/// storage bindings, so the atomic build counts every slice in one geometry pass over two pages (four runs of
/// 64 slices); on a device whose bindings hold 16 MiB it counts in four bands of 64 slices (runs of 16, one
/// per page), the running sum carried across; at 128² its four runs share one page. Each of the three count
/// pipelines (one run, runs in one page, several pages) equals the CPU model.
#[test]
fn paged_and_banded_atomic_builds_gpu_equal_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let params = [("slices", 256.0), ("build", 1.0)];
    let small = Gpu::headless_with_binding_limit(
        hairlab::gpu::AdapterPreference::from_env_or(hairlab::gpu::AdapterPreference::Software),
        16 << 20,
    )
    .unwrap();
    for (g, name, res) in [
        (&gpu, "this device", 512),
        (&small, "16 MiB bindings", 512),
        (&gpu, "this device", 128),
    ] {
        let (worst, samples) = gpu_cpu_difference(g, "osm", &params, Setup::new(60, res));
        let limits = g.device.limits();
        let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let layout = CounterLayout::new("osm", res, 256, limit).unwrap();
        eprintln!("osm-256 atomic at {res}², {name}: {layout:?}, {samples} samples, max |ΔV| {worst:.3e}");
        assert!(samples > 2000, "only {samples} samples");
        assert!(worst <= TOLERANCE, "{name}: max |ΔV| = {worst}");
        if res == 128 {
            assert_eq!(
                (layout.band, layout.run, layout.pages()),
                (256, 64, 1),
                "four runs in one page"
            );
            continue;
        }
        let (r, result) = render_method_light(g, "osm", &params, 60, 512);
        result.unwrap();
        let m = r.method_gpu(registry::find("osm").unwrap()).unwrap();
        assert_eq!(m.geometry_passes(), 256u32.div_ceil(layout.band), "{name}");
        if limit == 128 << 20 {
            assert_eq!(
                m.geometry_passes(),
                1,
                "lavapipe's two bindings hold all 256 slices"
            );
        }
        if limit == 16 << 20 {
            assert_eq!(m.geometry_passes(), 4, "pages of 16 slices, four per band");
        }
    }
}

/// A map whose counters of 4 entries alone exceed a storage binding is refused with one error naming the
/// method, the `build` parameter and the resolution, and nothing is held: OSM-16 (u8, so that the map itself
/// stays within hairlab's budget) at 4096² needs 64 MiB of counters per slice.
#[test]
fn atomic_build_beyond_a_band_of_four_is_refused_naming_the_key() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let limits = gpu.device.limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    let params = [("slices", 16.0), ("build", 1.0), ("storage", 2.0)];
    let (r, result) = render_method_light(&gpu, "osm", &params, 20, 4096);
    if 4 * 4096 * 4096 * 4 > limit {
        match result {
            Err(GpuError::Setting(msg)) => {
                assert!(
                    msg.contains("osm") && msg.contains("build = atomic") && msg.contains("4096²"),
                    "{msg}"
                );
            }
            other => panic!("expected a Setting error, got {other:?}"),
        }
        assert!(
            r.method_gpu(registry::find("osm").unwrap()).is_none(),
            "no maps held"
        );
    } else {
        result.unwrap();
    }
}

/// The memory report per storage, worked out by hand for OSM-64 at 64² (4096 texels, 16 layers of 4 slices):
/// the map takes 16, 8 or 4 bytes per texel and layer; the atomic build's counters (4 bytes per slice and
/// texel, in one page; the other three bind a counter each), running sums and leading-zero counts (4 bytes per
/// texel each), flat tails (12 bytes per texel), null target (1 byte per texel) and the resolve's one dispatch
/// uniform (one dynamic-offset step) are build memory.
#[test]
fn memory_report_counts_each_storage() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let texels = 64 * 64;
    let parts = gpu.device.limits().min_uniform_buffer_offset_alignment as u64;
    // The counters' first page, and three unused pages of one counter each.
    let atomic = texels * (64 * 4 + 4 + 4 + 12 + 1) + 3 * 4 + parts;
    for (build, storage, map_bytes, build_bytes) in [
        (2.0, 0.0, texels * 16 * 16, 0),
        (1.0, 0.0, texels * 16 * 16, atomic),
        (1.0, 1.0, texels * 16 * 8, atomic),
        (1.0, 2.0, texels * 16 * 4, atomic),
    ] {
        let params = [("slices", 64.0), ("build", build), ("storage", storage)];
        let (r, result) = render_method_light(&gpu, "osm", &params, 20, 64);
        result.unwrap();
        let m = r.method_gpu(registry::find("osm").unwrap()).unwrap();
        assert_eq!(m.memory_bytes(), map_bytes, "{params:?}");
        assert_eq!(m.build_bytes(), build_bytes, "{params:?}");
        let passes = if build == 2.0 { 2 } else { 1 };
        assert_eq!(m.geometry_passes(), passes, "{params:?}");
    }
}
