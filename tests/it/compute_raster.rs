//! The compute rasteriser (`render.raster = compute`, `render::caster::compute`): its fragment stream equals its
//! CPU model (`render::caster::raster_model`, whose rule the unit tests there check on hand-worked segments)
//! fragment for fragment; the exact reference stays exact under it (the A-buffer equals depth peeling); every
//! method still equals its CPU model fed the rasteriser's fragments; and its coverage is set against the
//! hardware lines' (a measurement: the two rules differ). Binned to tiles, the stream is the per-segment one.

use crate::common;

use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::caster::raster_model::{rasterise, tile_lists};
use hairlab::render::geometry::{hair_indices, hair_vertices};
use hairlab::render::passes::abuffer::RefFragment;
use hairlab::render::{AlphaMode, LightStrands, Raster, Renderer};
use hairlab::settings::Settings;
use hairlab::shading::HairModel;

fn compute(s: &mut Settings) {
    s.render.raster = Raster::Compute;
}

/// The stream of a 300-strand head at 64² (both alpha modes of the absorber model, and the fibres model's
/// texel coverage) against the CPU model run on the same frame uniforms and strand points: the same texels and
/// segments in the same order, depth and alpha within 1e-5 (float contraction may differ between the CPU and
/// the shader compiler; measured on lavapipe: 6555 fragments, depth 3.0e-7, alpha 0 in both modes; the
/// fibres model's maxima are printed).
#[test]
fn gpu_stream_equals_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (alpha, hair) in [
        (AlphaMode::Constant, HairModel::Absorber),
        (AlphaMode::Coverage, HairModel::Absorber),
        (AlphaMode::Coverage, HairModel::Fibres),
    ] {
        let (mut s, scene) = common::setup_scene(common::Setup::new(300, 64));
        s.render.alpha = alpha;
        s.render.hair_model = hair;
        let case = (alpha, hair);
        let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
        let (stream, u) = r.raster_stream(&s.camera, &s.light, &s.render).unwrap();
        let model = rasterise(&u, &hair_vertices(&scene), &hair_indices(&scene));
        assert!(
            model.len() > 2000,
            "test scene too thin: {} fragments",
            model.len()
        );
        assert_eq!(stream.len(), model.len(), "{case:?}: fragment count");
        let (mut depth, mut alpha_diff) = (0.0f32, 0.0f32);
        for (i, (g, c)) in stream.iter().zip(&model).enumerate() {
            assert_eq!(
                (g.texel, g.segment),
                (c.texel, c.segment),
                "{case:?}: fragment {i}: texel and segment"
            );
            depth = depth.max((g.depth - c.depth).abs());
            alpha_diff = alpha_diff.max((g.alpha - c.alpha).abs());
        }
        eprintln!(
            "{case:?}: {} fragments, max |depth| difference {depth:e}, max |alpha| difference {alpha_diff:e}",
            model.len()
        );
        assert!(
            depth <= 1e-5 && alpha_diff <= 1e-5,
            "{case:?}: depth {depth}, alpha {alpha_diff}"
        );
    }
}

#[test]
fn abuffer_equals_depth_peeling_under_compute_raster() {
    let Some(gpu) = Gpu::for_tests() else { return };
    crate::reference::assert_abuffer_equals_depth_peeling(&gpu, compute);
    crate::reference::assert_abuffer_equals_depth_peeling(&gpu, |s| {
        compute(s);
        s.render.raster_tile = 8;
    });
}

/// Binned to tiles (`render.raster_tile`): the stream of a 300-strand head at 64² equals the per-segment
/// stream bit for bit (texel, depth, alpha and segment, in order) at tile sides 4 (segments crossing several
/// tiles), 24 (3 × 3 tiles, the last row and column 16 texels) and 64 (one tile); each tile's list holds
/// exactly the segments the CPU model of the binning puts there, each once.
#[test]
fn binned_stream_equals_the_per_segment_stream() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = common::setup_scene(common::Setup::new(300, 64));
    compute(&mut s);
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let (plain, _) = r.raster_stream(&s.camera, &s.light, &s.render).unwrap();
    assert!(r.raster_tile_lists().unwrap().is_empty(), "per segment, no tiles");
    let first_points = hair_indices(&scene);
    for tile in [4, 24, 64] {
        s.render.raster_tile = tile;
        let (binned, _) = r.raster_stream(&s.camera, &s.light, &s.render).unwrap();
        assert_eq!(binned, plain, "tile {tile}: the binned stream");
        let mut expected = tile_lists(&plain, 64, tile);
        let mut lists: Vec<Vec<u32>> = r
            .raster_tile_lists()
            .unwrap()
            .into_iter()
            .map(|l| l.iter().map(|&s| first_points[2 * s as usize]).collect())
            .collect();
        for l in expected.iter_mut().chain(lists.iter_mut()) {
            l.sort_unstable();
        }
        let pairs: usize = expected.iter().map(Vec::len).sum();
        eprintln!(
            "tile {tile}: {} tiles, {pairs} (segment, tile) pairs for {} fragments",
            expected.len(),
            plain.len()
        );
        assert_eq!(lists.len(), 64usize.div_ceil(tile as usize).pow(2), "tile {tile}");
        assert_eq!(lists, expected, "tile {tile}: the tiles' lists");
    }
}

/// The memory report counts the compute rasteriser's buffers: the segments' counts (one more for the total),
/// the stream's two pages (the second a one-fragment placeholder while the stream fits one) and, binned to 3 × 3
/// tiles, their counts (one more for the total), cursors and lists; under the hardware lines, none.
#[test]
fn memory_report_counts_the_raster_stream() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = common::setup_scene(common::Setup::new(300, 64));
    compute(&mut s);
    s.render.raster_tile = 24;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let (stream, _) = r.raster_stream(&s.camera, &s.light, &s.render).unwrap();
    let pairs: usize = r.raster_tile_lists().unwrap().iter().map(Vec::len).sum();
    let segments = hair_indices(&scene).len() / 2;
    let fragment = std::mem::size_of::<hairlab::render::caster::raster_model::RasterFragment>();
    let expected = (segments + 1) * 4 + (stream.len() + 1) * fragment + (9 + 1) * 4 + 9 * 4 + pairs * 4;
    assert_eq!(r.memory().raster_stream, expected as u64);
    s.render.raster = Raster::Hardware;
    s.render.raster_tile = 0;
    r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    assert_eq!(r.memory().raster_stream, 0, "under the hardware lines");
}

/// `render.raster_tile` outside 0 and 4..=256 is one setting error naming the key.
#[test]
fn raster_tile_out_of_range_is_refused() {
    for tile in [1, 3, 257] {
        let mut s = common::small_settings(8, 8);
        compute(&mut s);
        s.render.raster_tile = tile;
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("render.raster_tile") && e.contains(&tile.to_string()),
            "{e}"
        );
    }
}

/// Every registered method at its defaults, its maps built from the compute rasteriser's fragments, against its
/// CPU model fed the reference's lists of the same fragments: within the method's own stated tolerance.
#[test]
fn every_method_gpu_equals_cpu_under_compute_raster() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = common::setup_scene(common::Setup::new(300, 64));
    compute(&mut s);
    for m in registry::all() {
        let info = m.info();
        let d = common::gpu_cpu_differences_in(&gpu, info.name, &[], &s, &scene, true);
        crate::methods_gpu::assert_within_stated_tolerance(info, "under the compute raster", &d);
    }
}

/// The compute rasteriser lines strands only: with ribbons it is one setting error naming both keys, from the
/// settings and from the renderer.
#[test]
fn compute_raster_with_ribbons_is_refused() {
    let mut s = common::small_settings(8, 8);
    compute(&mut s);
    s.render.light_strands = LightStrands::Ribbons;
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains("render.raster") && e.contains("render.light_strands"),
        "{e}"
    );
    let Some(gpu) = Gpu::for_tests() else { return };
    let (_, scene) = common::setup_scene(common::Setup::new(20, 16));
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let e = r
        .reference_lists(&s.camera, &s.light, &s.render)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("render.raster") && e.contains("render.light_strands"),
        "{e}"
    );
}

/// Per texel, the segments covering it.
fn segments(lists: &[Vec<RefFragment>]) -> Vec<Vec<u32>> {
    lists
        .iter()
        .map(|l| {
            let mut s: Vec<u32> = l.iter().map(|f| f.segment).collect();
            s.sort_unstable();
            s
        })
        .collect()
}

/// The compute rule against the hardware lines on a 300-strand head at 64² and 256², predicted from the
/// segments' own texel-space extents. Under the major-axis rule a segment covers one texel per column (or row)
/// it crosses along its major axis, about `max(|Δx|, |Δy|)` texels; lavapipe draws lines as one-texel-wide
/// rectangles (Vulkan's non-strict lines), which cover about their length `√(Δx² + Δy²)`. So the fragment totals
/// must stand in the ratio `Σ max(|Δx|, |Δy|) / Σ length` of this scene's segments (0.90 for uniformly spread
/// directions) — within 2 %, the rounding of each segment's ends (a segment is about one texel long at 64²); the
/// same rule on both sides would give 1.0 and fail by 12 %. Measured on lavapipe: predicted 0.8923 at both sizes
/// (the directions do not change); 64², 0.9008; 256², 0.8924.
#[test]
fn compute_coverage_against_hardware_lines() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for resolution in [64, 256] {
        let (mut s, scene) = common::setup_scene(common::Setup::new(300, resolution));
        let mut r = Renderer::new(&gpu, &scene, resolution).unwrap();
        let hardware = segments(&r.reference_lists(&s.camera, &s.light, &s.render).unwrap());
        compute(&mut s);
        let computed = segments(&r.reference_lists(&s.camera, &s.light, &s.render).unwrap());
        let covered = hardware
            .iter()
            .zip(&computed)
            .filter(|(h, c)| !h.is_empty() || !c.is_empty())
            .count();
        let total = |l: &[Vec<u32>]| l.iter().map(Vec::len).sum::<usize>() as f64;
        let ratio = total(&computed) / total(&hardware);
        // The segments in texel space under the light frame both rasterisers drew.
        let m = r.hair_light_frame(&s.light).world_to_clip();
        let texel = |p: glam::Vec3| {
            let c = m * p.extend(1.0);
            glam::Vec2::new(c.x / c.w, c.y / c.w) * 0.5 * resolution as f32
        };
        let points = &scene.strands.points;
        let (mut major, mut length) = (0.0f64, 0.0f64);
        for pair in hair_indices(&scene).chunks_exact(2) {
            let d = texel(points[pair[1] as usize]) - texel(points[pair[0] as usize]);
            major += f64::from(d.x.abs().max(d.y.abs()));
            length += f64::from(d.length());
        }
        let predicted = major / length;
        eprintln!(
            "{resolution}²: {covered} texels covered; fragments compute / hardware {ratio:.4}, predicted {predicted:.4}"
        );
        assert!(covered > 100, "{resolution}²: test scene too thin");
        assert!(
            (ratio / predicted - 1.0).abs() < 0.02,
            "{resolution}²: fragment totals {ratio:.4}, predicted {predicted:.4} from the segments' extents"
        );
    }
}

/// A stream longer than one storage binding spans the rasteriser's two pages: on a device whose bindings hold
/// three fifths of this scene's stream, the stream read back and the reference's lists drawn from it (the
/// caster reading both pages) equal, fragment for fragment, those of the same scene on the usual device.
#[test]
fn a_stream_past_one_binding_spans_two_pages() {
    use hairlab::gpu::AdapterPreference;
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = common::setup_scene(common::Setup::new(300, 256));
    compute(&mut s);
    let run = |g: &Gpu, tile| {
        let mut s = s.clone();
        s.render.raster_tile = tile;
        let mut r = Renderer::new(g, &scene, s.render.map_resolution).unwrap();
        let (stream, _) = r.raster_stream(&s.camera, &s.light, &s.render).unwrap();
        let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
        (stream, lists)
    };
    let (stream, lists) = run(&gpu, 0);
    let fragment_bytes = std::mem::size_of::<hairlab::render::caster::raster_model::RasterFragment>() as u64;
    let stream_bytes = stream.len() as u64 * fragment_bytes;
    // What else this scene binds as one storage buffer: the strand points and the A-buffer's heads.
    let points = (hair_vertices(&scene).len() * std::mem::size_of_val(&hair_vertices(&scene)[0])) as u64;
    let heads = 256 * 256 * 4;
    let limit = (stream_bytes * 3 / 5)
        .max(points)
        .max(heads)
        .next_multiple_of(256);
    assert!(
        stream_bytes > limit && stream_bytes <= 2 * limit,
        "{} fragments ({stream_bytes} B) do not span two pages of {limit} B",
        stream.len()
    );
    let pref = AdapterPreference::from_env_or(AdapterPreference::Software);
    let paged = Gpu::headless_with_binding_limit(pref, limit).unwrap();
    eprintln!(
        "{} fragments over pages of {} fragments",
        stream.len(),
        limit / fragment_bytes
    );
    // Per segment, and binned to 32-texel tiles (whose workgroups write across the pages' boundary).
    for tile in [0, 32] {
        let (paged_stream, paged_lists) = run(&paged, tile);
        assert_eq!(stream, paged_stream, "tile {tile}: the stream across two pages");
        assert_eq!(lists.len(), paged_lists.len());
        for (t, (a, p)) in lists.iter().zip(&paged_lists).enumerate() {
            assert_eq!(a, p, "tile {tile}: texel {t}: lists drawn from two pages differ");
        }
    }
}
