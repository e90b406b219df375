//! The exact reference on the GPU (lavapipe in CI): the A-buffer gives exactly the lists depth peeling gives,
//! depth ties survive, the light-depth maps hold exactly the lists' extremes, and the reference lookup equals the
//! CPU definition `V = exp(-sum of b over fragments in front)`.

use crate::common;

use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::passes::abuffer::RefFragment;
use hairlab::render::{FrameInput, Renderer};
use hairlab::scene::{Scene, Strands};
use hairlab::settings::Settings;
use hairlab::visibility::{Fragment, Reference, TexelModel, metrics};

fn frame<'a>(s: &'a Settings, method: &'a str) -> FrameInput<'a> {
    crate::common::light_frame(s, registry::find(method).unwrap(), &s.method.params)
}

fn small_scene(s: &mut Settings) -> Scene {
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    scene
}

#[test]
fn abuffer_equals_depth_peeling() {
    let Some(gpu) = Gpu::for_tests() else { return };
    assert_abuffer_equals_depth_peeling(&gpu, |_| {});
}

/// The A-buffer's lists equal depth peeling's, texel for texel, on a 150-strand head at 48² under the small
/// settings adjusted by `adjust` (e.g. another light caster).
pub fn assert_abuffer_equals_depth_peeling(gpu: &Gpu, adjust: impl Fn(&mut Settings)) {
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = 150;
    s.scene.generator.segments = 8;
    s.render.map_resolution = 48;
    adjust(&mut s);
    let scene = small_scene(&mut s);
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let peeled = r.depth_peel(4096).unwrap();
    let total: usize = lists.iter().map(Vec::len).sum();
    let max = lists.iter().map(Vec::len).max().unwrap();
    assert!(
        total > 1000 && max > 5,
        "test scene too thin: {total} fragments, depth complexity {max}"
    );
    assert_eq!(
        peeled.layers as usize, max,
        "one peel layer per fragment of the deepest texel"
    );
    assert_eq!(peeled.lists.len(), lists.len());
    for (t, (a, p)) in lists.iter().zip(&peeled.lists).enumerate() {
        assert_eq!(a, p, "texel {t}: A-buffer and depth peel disagree");
    }
}

/// Two identical strands: every fragment of one has a twin with the same depth in the same texel. A peel with a
/// strict depth test would keep one of each pair; peeling on (depth, segment) keeps both.
#[test]
fn depth_ties_are_kept() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let points: Vec<glam::Vec3> = (0..6)
        .map(|i| glam::Vec3::new(0.02 * i as f32, 0.01 * i as f32, 0.003 * i as f32))
        .collect();
    let mut strands = Strands {
        points: points.clone(),
        counts: vec![6],
        ..Strands::default()
    };
    strands.append(&Strands {
        points,
        counts: vec![6],
        ..Strands::default()
    });
    let scene = Scene::new(strands, Vec::new());
    let mut s = common::small_settings(8, 8);
    s.render.map_resolution = 32;
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(&gpu, &scene, 32).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let peeled = r.depth_peel(256).unwrap();
    let mut pairs = 0;
    for (a, p) in lists.iter().zip(&peeled.lists) {
        assert_eq!(a, p);
        assert_eq!(p.len() % 2, 0, "a fragment lost its twin: {p:?}");
        for pair in p.chunks(2) {
            assert_eq!(pair[0].depth, pair[1].depth);
            // Segment ids of the twins differ by the 6 points of the first strand.
            assert_eq!(pair[1].segment, pair[0].segment + 6, "{pair:?}");
            pairs += 1;
        }
    }
    assert!(
        pairs >= 20,
        "only {pairs} tied pairs: the strands barely cover the map"
    );
}

#[test]
fn light_depth_maps_hold_the_lists_extremes_and_lookup_matches_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = 200;
    s.scene.generator.segments = 10;
    s.render.map_resolution = 64;
    let scene = small_scene(&mut s);
    let mut r = Renderer::new(&gpu, &scene, 64).unwrap();
    let reference = registry::reference();
    // The reference method's own A-buffer (what `evaluate` reads) and the renderer's lists of the same view.
    r.render_light(&frame(&s, "reference")).unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    let near = r.read_light_depth(false).unwrap();
    let far = r.read_light_depth(true).unwrap();
    let mut samples = Vec::new();
    let mut expected = Vec::new();
    for (t, list) in lists.iter().enumerate() {
        if list.is_empty() {
            assert_eq!(
                (near[t], far[t]),
                (1.0, 0.0),
                "texel {t} empty in the A-buffer but not in the depth maps"
            );
            continue;
        }
        // Bitwise: the same fragments, the same interpolated depths.
        assert_eq!(near[t].to_bits(), list[0].depth.to_bits(), "texel {t} nearest");
        assert_eq!(
            far[t].to_bits(),
            list.last().unwrap().depth.to_bits(),
            "texel {t} furthest"
        );
        let frags: Vec<Fragment> = list
            .iter()
            .map(|f: &RefFragment| Fragment::new(f.depth, f.alpha))
            .collect();
        let zs = metrics::sample_depths(&frags, 16);
        let (x, y) = ((t % 64) as f32, (t / 64) as f32);
        expected.extend(Reference.curve(&frags, &zs));
        samples.extend(zs.iter().map(|&z| [x, y, z]));
    }
    assert!(samples.len() > 10_000, "{} samples", samples.len());
    let gpu_v = r.evaluate(reference, &samples).unwrap();
    let worst = gpu_v
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    // Both sum the same f32 optical depths, in different orders: rounding only.
    assert!(
        worst <= 1e-5,
        "reference lookup differs from the CPU definition by {worst}"
    );
}

/// Storage bindings of the paged test device: 1024 list nodes per page.
const PAGE_BYTES: u64 = 16 << 10;

/// On a device whose storage bindings hold 1024 list nodes, a small scene's light A-buffer spans several node pages
/// (`abuffer::NODE_PAGES` bindings): its lists equal, fragment for fragment, those of the same scene in one page
/// on the usual device. (AVSM and the compressed deep shadow map sort and read their lists through the same pages:
/// `gpu_avsm::lists_over_several_pages_sort_and_compress_as_the_cpu_model`.)
#[test]
fn paged_lists_equal_one_page() {
    use crate::common::{Setup, setup_scene};
    use hairlab::gpu::AdapterPreference;
    use hairlab::render::passes::abuffer::{NODE_BYTES, NODE_PAGES};
    let Some(gpu) = Gpu::for_tests() else { return };
    let pref = AdapterPreference::from_env_or(AdapterPreference::Software);
    let paged = Gpu::headless_with_binding_limit(pref, PAGE_BYTES).unwrap();
    assert_eq!(paged.device.limits().max_storage_buffer_binding_size, PAGE_BYTES);
    // 600 strands: about 2,800 fragments (200 gave 943), three pages of 1024 nodes.
    let setup = Setup::new(600, 12);
    let (s, scene) = setup_scene(setup);
    let lists = |g: &Gpu| {
        let mut r = Renderer::new(g, &scene, s.render.map_resolution).unwrap();
        r.reference_lists(&s.camera, &s.light, &s.render).unwrap()
    };
    let (whole, pages) = (lists(&gpu), lists(&paged));
    let total: usize = whole.iter().map(Vec::len).sum();
    let per_page = (PAGE_BYTES / NODE_BYTES) as usize;
    assert!(
        total > 2 * per_page && total <= NODE_PAGES * per_page,
        "{total} fragments: not 3..={NODE_PAGES} pages of {per_page} nodes"
    );
    assert_eq!(whole.len(), pages.len());
    for (t, (a, p)) in whole.iter().zip(&pages).enumerate() {
        assert_eq!(a, p, "texel {t}: paged lists differ");
    }
}
