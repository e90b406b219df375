//! Light-map supersampling (`render.light_supersample`, Yuksel & Keyser 2008 §5): every light map is built at
//! `map_resolution × s` and the eye lookup `hair_visibility` averages the method's visibility over the `s × s`
//! sub-texels of the point's texel. On the GPU (lavapipe): the eye lookup at world points equals its CPU model
//! (`hairlab::visibility::lookup`) over the method's CPU model on each sub-texel's exact fragments, the
//! reference's A-buffer equals depth peeling on the supersampled maps, the maps and their memory grow by `s²`,
//! a side the GPU cannot hold is one error naming the key, and the Light section's selector sets the key.

use glam::{Vec2, Vec3};
use hairlab::gpu::Gpu;
use hairlab::methods::dom::Dom;
use hairlab::methods::osm::Osm;
use hairlab::methods::reference::Reference;
use hairlab::methods::{LightMethod, ShadowMethod, registry};
use hairlab::render::Renderer;
use hairlab::visibility::Fragment;
use hairlab::visibility::lookup::Lookup;

/// Base light-map side of the lookup tests.
const BASE: u32 = 24;

/// The eye lookup on the GPU against its CPU model, for `method` with `params` at supersampling `s` (PCF when
/// `pcf`), on a 300-strand head at `BASE`² (every strand point and segment midpoint). Returns the largest
/// |V_gpu − V_cpu| and the number of points compared. Points within 1e-3 base texels of a texel edge, or within
/// 1e-4 light depth of a fragment in the texels averaged, are left out: there the f32 projection of the GPU and
/// of the CPU may pick the neighbouring texel, or the other side of the reference's step.
fn lookup_difference(
    gpu: &Gpu,
    method: &'static dyn ShadowMethod,
    params: &[(&str, f32)],
    s: u32,
    pcf: bool,
) -> (f32, usize) {
    let (mut st, scene) = crate::common::setup_scene(crate::common::Setup::new(300, BASE));
    st.render.light_supersample = s;
    st.render.pcf = pcf;
    let mut r = Renderer::new(gpu, &scene, st.render.light_map_side()).unwrap();
    let lists = r.reference_lists(&st.camera, &st.light, &st.render).unwrap();
    assert_eq!(
        lists.len(),
        (BASE * s * BASE * s) as usize,
        "the lists are the maps as built"
    );
    let values = crate::common::values(params);
    r.render(&crate::common::light_frame(&st, method, &values))
        .unwrap();
    assert_eq!(r.map_resolution(), BASE * s);
    let frame = r.hair_light_frame(&st.light);
    let clip = frame.world_to_clip();
    let lookup = Lookup {
        base: BASE,
        supersample: s,
        pcf,
    };
    let model = method.model(&values, st.render.hair_alpha);
    let strands = &scene.strands;
    let mut candidates: Vec<Vec3> = strands.points.clone();
    for (start, n) in strands.ranges() {
        let pts = &strands.points[start..start + n];
        candidates.extend(pts.windows(2).map(|p| (p[0] + p[1]) * 0.5));
    }
    let (mut points, mut expected) = (Vec::new(), Vec::new());
    for p in candidates {
        let c = clip.project_point3(p);
        let uv = Vec2::new(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5);
        let f = (uv * BASE as f32).fract();
        if f.min_element() < 1e-3 || f.max_element() > 1.0 - 1e-3 {
            continue;
        }
        let z = frame.depth(p);
        let texels = lookup.texels(uv);
        let frags = |t: [u32; 2]| -> Vec<Fragment> {
            lists[(t[1] * BASE * s + t[0]) as usize]
                .iter()
                .map(|f| f.fragment())
                .collect()
        };
        if texels
            .iter()
            .any(|&t| frags(t).iter().any(|f| (f.depth - z).abs() < 1e-4))
        {
            continue;
        }
        points.push(p);
        expected.push(lookup.visibility(uv, z, |t, z| model.curve(&frags(t), &[z])[0]));
    }
    let got = r.evaluate_points(method, &points).unwrap();
    assert!(
        got.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
        "{}: V outside [0, 1]",
        method.name()
    );
    assert!(
        expected.iter().any(|&v| v < 0.5),
        "{}: the test scene should shadow some point below V = 1/2",
        method.name()
    );
    let worst = got
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    (worst, points.len())
}

/// A method and its parameters.
type Case = (&'static dyn ShadowMethod, &'static [(&'static str, f32)]);

/// GPU = CPU for the eye lookup under supersampling, OSM-16, DOM-3 and the reference at s = 2 and 4 (and s = 2
/// with 3×3 PCF), within 1e-4 (the methods' stated per-texel GPU tolerance; 1e-5 for the reference's).
/// Measured maxima (lavapipe, ~5,000–5,900 points a case): OSM-16 5.2e-6, 4.3e-6, 1.9e-6 (s = 2, 4, 2 with PCF);
/// DOM-3 6.7e-6, 2.4e-6, 1.8e-6; reference 1.2e-7, 6.0e-8, 3.0e-7.
#[test]
fn supersampled_eye_lookup_equals_its_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let reference: &'static dyn ShadowMethod = registry::find(Reference.name()).unwrap();
    let osm = registry::find(Osm.name()).unwrap();
    let dom = registry::find(Dom.name()).unwrap();
    let cases: [(Case, f32); 3] = [
        ((osm, &[("slices", 16.0)]), 1e-4),
        ((dom, &[("layers", 3.0)]), 1e-4),
        ((reference, &[]), 1e-5),
    ];
    for ((method, params), tolerance) in cases {
        for (s, pcf) in [(2, false), (4, false), (2, true)] {
            let (worst, n) = lookup_difference(&gpu, method, params, s, pcf);
            eprintln!(
                "{} s = {s} pcf = {pcf}: max |ΔV| = {worst:e} over {n} points",
                method.name()
            );
            assert!(n > 1000, "{}: only {n} points compared", method.name());
            assert!(
                worst <= tolerance,
                "{} at s = {s} (pcf {pcf}): max |ΔV| = {worst}",
                method.name()
            );
        }
    }
}

/// The reference stays exact for what the methods see: at s = 2 the A-buffer's lists over the 96² maps equal
/// depth peeling's, texel for texel.
#[test]
fn supersampled_abuffer_equals_depth_peeling() {
    let Some(gpu) = Gpu::for_tests() else { return };
    crate::reference::assert_abuffer_equals_depth_peeling(&gpu, |s| s.render.light_supersample = 2);
}

/// Memory reported per configuration grows by s²: OSM-16's maps at s = 2 and 4 hold 4 and 16 times the bytes
/// of s = 1 at the same `map_resolution`.
#[test]
fn supersampled_maps_hold_s_squared_the_memory() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let osm = registry::find(Osm.name()).unwrap();
    let values = crate::common::values(&[("slices", 16.0)]);
    let bytes = |s: u32| {
        let (mut st, scene) = crate::common::setup_scene(crate::common::Setup::new(50, 32));
        st.render.light_supersample = s;
        let mut r = Renderer::new(&gpu, &scene, st.render.map_resolution).unwrap();
        r.render_light(&crate::common::light_frame(&st, osm, &values))
            .unwrap();
        assert_eq!(r.map_resolution(), 32 * s);
        r.method_gpu(osm).unwrap().memory_bytes()
    };
    let one = bytes(1);
    assert!(one > 0);
    assert_eq!(bytes(2), 4 * one);
    assert_eq!(bytes(4), 16 * one);
}

/// A supersampled side above the GPU's largest texture is one error naming `render.light_supersample`, and
/// the settings refuse a factor other than 1, 2 or 4.
#[test]
fn too_large_or_bad_supersampling_is_one_clear_error() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let limit = gpu.device.limits().max_texture_dimension_2d;
    let (mut st, scene) = crate::common::setup_scene(crate::common::Setup::new(20, 8));
    st.render.map_resolution = limit / 2 + 1;
    st.render.light_supersample = 2;
    let mut r = Renderer::new(&gpu, &scene, 8).unwrap();
    let osm = registry::find(Osm.name()).unwrap();
    let values = crate::common::values(&[]);
    let err = r
        .render_light(&crate::common::light_frame(&st, osm, &values))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("render.light_supersample = 2") && err.contains(&limit.to_string()),
        "{err}"
    );
    let mut bad = hairlab::settings::Settings::default();
    bad.render.light_supersample = 3;
    let err = bad.validate().unwrap_err().to_string();
    assert!(
        err.contains("render.light_supersample must be 1, 2 or 4"),
        "{err}"
    );
}

/// The Light section's supersample selector offers 1, 2 and 4 and sets `render.light_supersample`.
#[test]
fn the_light_section_sets_the_supersampling() {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;
    use hairlab::app::{HairlabApp, wgpu_setup};
    use hairlab::gpu::AdapterPreference;
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = crate::common::small_settings(320, 240);
    let mut harness = Harness::builder()
        .with_size([1400.0, 1500.0])
        .with_max_steps(8)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| HairlabApp::new(cc, Some(settings)));
    harness.run();
    assert_eq!(harness.state().settings().render.light_supersample, 1);
    for s in hairlab::render::render_settings::LIGHT_SUPERSAMPLES {
        assert!(
            harness.query_by_label(&format!("{s}×{s}")).is_some(),
            "{s}×{s} is not offered"
        );
    }
    harness.get_by_label("4×4").click();
    harness.run();
    assert_eq!(harness.state().settings().render.light_supersample, 4);
}
