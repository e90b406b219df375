//! The motion claims (issue "Hair in motion"), measured on test-sized motion presets with `measure --motion`'s
//! library (`hairlab::measure::motion`; design.md's temporal metrics) on lavapipe: MC-1 (Sintorn & Assarsson
//! Fig. 4 in motion), MC-2 (Yuksel & Keyser: straight hair in motion), MC-3 (light-space anti-aliasing), MC-4 (Voicu: Bounding Opacity Maps' split
//! ratio chosen once or every frame) and MC-5 (the simulation's invariants over 10,000 frames, on the CPU model).
//! Thresholds sit below the figures measured when the tests were written (stated beside each); a claim the
//! measurement does not reproduce is asserted in the direction measured and says so. Reproduce a figure with the
//! `hairlab measure --motion …` line beside it.

use glam::{Mat4, Vec2, Vec3};
use hairlab::gpu::Gpu;
use hairlab::measure::motion::{MotionConfig, MotionMeasurement, MotionRow, measure_motion_on};
use hairlab::methods::LightMethod;
use hairlab::methods::bom::Bom;
use hairlab::methods::dom::Dom;
use hairlab::methods::occupancy::Occupancy;
use hairlab::methods::osm::Osm;
use hairlab::motion::{Ellipsoid, Motion};
use hairlab::render::Renderer;
use hairlab::render::passes::abuffer::RefFragment;
use hairlab::report::claims::mc1;
use hairlab::scene::LightFit;
use hairlab::scene::generate::HEAD_RADII;
use hairlab::scene::light_frame::LightFrame;
use hairlab::settings::Settings;
use std::collections::HashSet;

fn measure(
    gpu: &Gpu,
    preset: &str,
    overrides: &[&str],
    configs: &[String],
    frames: u32,
) -> MotionMeasurement {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let settings = Settings::load_preset(preset, &overrides).unwrap();
    let configs: Vec<MotionConfig> = configs.iter().map(|c| MotionConfig::parse(c).unwrap()).collect();
    let m = measure_motion_on(gpu, &settings, &configs, frames, &mut hairlab::progress::Quiet).unwrap();
    eprint!("{}", m.table(&format!("{preset} {overrides:?}")));
    m.kept()
}

fn row<'a>(m: &'a MotionMeasurement, label: &str) -> &'a MotionRow {
    m.row(label).unwrap_or_else(|| panic!("no row {label}"))
}

/// MC-1, Sintorn & Assarsson Fig. 4 in motion: the stray strand sweeping in front of the clump restarts Deep
/// Opacity Maps' layers wherever it passes, so the shadow on the clump pops; occupancy maps keep the whole depth
/// range and change as the truth does. Under the default fit (`light.fit = stable`), so the pops are the
/// method's and not the light frame's.
#[test]
fn mc1_a_sweeping_stray_strand_pops_deep_opacity_maps_several_times_more_than_occupancy_maps() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (dom3, dom4, occ) = (
        format!("{}:layers=3", Dom.name()),
        format!("{}:layers=4", Dom.name()),
        Occupancy.name().to_string(),
    );
    // hairlab measure --motion --preset stray-sweep --frames 12 --set scene.generator.strands=600
    //   --set render.map_resolution=128 --config dom:layers=3 --config dom:layers=4 --config occupancy
    let m = measure(
        &gpu,
        "stray-sweep",
        &["scene.generator.strands=600", "render.map_resolution=128"],
        &[dom3.clone(), dom4.clone(), occ.clone()],
        12,
    );
    let pops = |label: &str| row(&m, label).flicker.pop_rate;
    let (p3, p4, po) = (pops(&dom3), pops(&dom4), pops(&occ));
    // Measured pop rate under `stable`: DOM-3 1.28 %, DOM-4 1.30 %, occupancy 0.23 % (5.6x, 5.7x); flicker
    // 0.00522, 0.00512 against 0.00085 (6.1x). Under `per-frame`, the default before issue 35: 0.80 %, 0.82 %,
    // 0.22 % (3.6x, 3.7x); flicker 0.00319, 0.00323 against 0.00068.
    // The report's claims table judges with the same function (`hairlab::report::claims`).
    for (label, p) in [(&dom3, p3), (&dom4, p4)] {
        let claim = mc1(label, p, po);
        assert!(claim.holds, "{}", claim.measured);
    }
    let flicker = |label: &str| row(&m, label).flicker.mean;
    assert!(
        flicker(&dom3) > 3.0 * flicker(&occ),
        "DOM-3 flicker {} against occupancy's {}",
        flicker(&dom3),
        flicker(&occ)
    );
}

/// The sweep at test size: `stray-sweep`'s stray strand swept ±0.067 (a little past the clump's side)
/// over half a 0.8 s period in 12 frames, 600 strands, 128-texel maps.
const SWEEP: [&str; 4] = [
    "scene.generator.strands=600",
    "render.map_resolution=128",
    "motion.sweep_amplitude=0.067",
    "motion.head_period=0.8",
];

/// The texels (row-major indices into a `res`-texel map) that the segments of `strands` (first point, count)
/// of `points` cross under `world_to_clip`, dilated by one texel: each segment walked in steps of a quarter
/// texel.
fn footprint(points: &[Vec3], strands: &[(usize, usize)], world_to_clip: Mat4, res: u32) -> HashSet<usize> {
    let texel = |p: Vec3| {
        let c = world_to_clip.project_point3(p);
        Vec2::new((c.x * 0.5 + 0.5) * res as f32, (0.5 - c.y * 0.5) * res as f32)
    };
    let mut out = HashSet::new();
    for &(first, count) in strands {
        for w in points[first..first + count].windows(2) {
            let (a, b) = (texel(w[0]), texel(w[1]));
            let steps = ((b - a).length() * 4.0).ceil().max(1.0) as u32;
            for i in 0..=steps {
                let t = a.lerp(b, i as f32 / steps as f32).floor();
                for (dx, dy) in (-1..=1).flat_map(|dx| (-1..=1).map(move |dy| (dx, dy))) {
                    let (x, y) = (t.x as i64 + dx, t.y as i64 + dy);
                    if (0..res as i64).contains(&x) && (0..res as i64).contains(&y) {
                        out.insert(y as usize * res as usize + x as usize);
                    }
                }
            }
        }
    }
    out
}

/// Under the default fit (`stable`), the stray strand sweeping across the clump changes the hair maps' light
/// frame by nothing (the matrices and the depth range bit for bit on every frame) and changes the exact
/// reference's depth lists only in texels its footprint crosses (on the frame before or after, dilated by one
/// texel).
#[test]
fn a_sweeping_stray_strand_changes_only_the_texels_it_crosses_under_the_default_fit() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let overrides: Vec<String> = SWEEP.iter().map(|s| s.to_string()).collect();
    let mut s = Settings::load_preset("stray-sweep", &overrides).unwrap();
    assert_eq!(s.light.fit, LightFit::Stable, "the default fit");
    let (scene, mut motion) = s.open_motion().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let ranges: Vec<(usize, usize)> = scene.strands.ranges().collect();
    let frames: Vec<Vec<Vec3>> = (0..8).map(|k| motion.frame(k).unwrap().to_vec()).collect();
    let res = s.render.light_map_side();
    let mut r = Renderer::new(&gpu, &scene, res).unwrap();
    r.set_fit_bound(Some(motion.bound(&s.motion).unwrap()));
    let bits = |f: &LightFrame| {
        let m = [f.world_to_view, f.view_to_clip].map(|m| m.to_cols_array().map(f32::to_bits));
        (m, f.near.to_bits(), f.far.to_bits())
    };
    let mut first_frame = None;
    let mut previous: Option<Vec<Vec<RefFragment>>> = None;
    let (mut changed_total, mut footprint_total) = (0, 0);
    for (k, points) in frames.iter().enumerate() {
        r.update_points(points).unwrap();
        let frame = r.hair_light_frame(&s.light);
        let first = *first_frame.get_or_insert(frame);
        assert_eq!(bits(&frame), bits(&first), "frame {k}: the light frame moved");
        let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
        if let Some(before) = previous {
            // The strands that moved between the frames: the swept one alone (the clump stands still).
            let moved: Vec<(usize, usize)> = ranges
                .iter()
                .copied()
                .filter(|&(f, n)| frames[k - 1][f..f + n] != points[f..f + n])
                .collect();
            assert_eq!(moved.len(), 1, "frame {k}: {} strands moved", moved.len());
            let mut crossed = footprint(&frames[k - 1], &moved, frame.world_to_clip(), res);
            crossed.extend(footprint(points, &moved, frame.world_to_clip(), res));
            let changed: Vec<usize> = (0..lists.len()).filter(|&t| lists[t] != before[t]).collect();
            let outside: Vec<usize> = changed.iter().copied().filter(|t| !crossed.contains(t)).collect();
            assert!(
                outside.is_empty(),
                "frame {k}: {} of {} changed texels lie outside the strand's footprint, e.g. {:?}",
                outside.len(),
                changed.len(),
                &outside[..outside.len().min(5)]
            );
            assert!(
                !changed.is_empty(),
                "frame {k}: the moving strand changed no texel"
            );
            changed_total += changed.len();
            footprint_total += crossed.len();
        }
        previous = Some(lists);
    }
    eprintln!(
        "7 frame pairs: {changed_total} texels changed, all inside the footprints ({footprint_total} texels) of \
         {} texels a map",
        res * res
    );
}

/// The seed claim under the default fit and under `per-frame`, on the sweep above: with the frame stable,
/// DOM-3 pops at least 3× as often as occupancy maps (Sintorn & Assarsson Fig. 4 by a clear margin); refitted
/// every frame, the fit's own flicker makes occupancy maps pop more and drowns the ratio.
#[test]
fn on_the_sweep_deep_opacity_maps_pop_three_times_as_often_as_occupancy_under_the_default_fit() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (dom3, occ) = (format!("{}:layers=3", Dom.name()), Occupancy.name().to_string());
    let configs = [dom3.clone(), occ.clone()];
    // hairlab measure motion --preset stray-sweep --frames 12 --set scene.generator.strands=600
    //   --set render.map_resolution=128 --set motion.sweep_amplitude=0.067 --set motion.head_period=0.8
    //   --config dom:layers=3 --config occupancy [--set light.fit=per-frame]
    let stable = measure(&gpu, "stray-sweep", &SWEEP, &configs, 12);
    let mut refit = SWEEP.to_vec();
    refit.push("light.fit=per-frame");
    let per_frame = measure(&gpu, "stray-sweep", &refit, &configs, 12);
    let pops = |m: &MotionMeasurement, label: &str| row(m, label).flicker.pop_rate;
    let (d, o) = (pops(&stable, &dom3), pops(&stable, &occ));
    let (pd, po) = (pops(&per_frame, &dom3), pops(&per_frame, &occ));
    eprintln!("pop rate: stable DOM-3 {d}, occupancy {o}; per-frame DOM-3 {pd}, occupancy {po}");
    assert!(
        o > 0.0,
        "occupancy maps never pop under the default fit: the ratio is undefined"
    );
    assert!(
        d >= 3.0 * o,
        "default fit: DOM-3 pop rate {d} against occupancy's {o}"
    );
    assert!(
        po > o,
        "per-frame: occupancy pop rate {po} should exceed the stable fit's {o}"
    );
    assert!(
        pd / po < d / o,
        "per-frame: the ratio {pd}/{po} should be below the stable fit's {d}/{o}"
    );
}

/// MC-2, Yuksel & Keyser 2008: opacity-map layering artifacts are "especially significant in animated
/// sequences or straight hair", so on straight hair in motion OSM-16 should flicker more than DOM-3.
/// NOT REPRODUCED: on `straight-motion` DOM-3's flicker is the larger (measured below); the test asserts the
/// direction measured, so a change that makes the claim hold shows here. Measured under `light.fit = per-frame`
/// and held there: under the default `stable` the two tie (flicker DOM-3 0.0518, OSM-16 0.0516; pop rate
/// 14.6 % and 15.1 %), the refit having been a third of DOM-3's flicker; still not the claim's direction.
#[test]
fn mc2_on_straight_hair_in_motion_dom3_flickers_at_least_as_much_as_osm16_claim_not_reproduced() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (osm16, dom3) = (
        format!("{}:slices=16", Osm.name()),
        format!("{}:layers=3", Dom.name()),
    );
    // hairlab measure --motion --preset straight-motion --frames 12 --set scene.generator.strands=800
    //   --set render.map_resolution=128 --set light.fit=per-frame --config osm:slices=16 --config dom:layers=3
    let m = measure(
        &gpu,
        "straight-motion",
        &[
            "scene.generator.strands=800",
            "render.map_resolution=128",
            "light.fit=per-frame",
        ],
        &[osm16.clone(), dom3.clone()],
        12,
    );
    let (o, d) = (row(&m, &osm16), row(&m, &dom3));
    // Measured flicker: OSM-16 0.0805, DOM-3 0.0939 (DOM-3 / OSM-16 = 1.17); pop rate 24.4 % and 26.8 %; image
    // flicker 0.0298 and 0.0358.
    assert!(
        d.flicker.mean > 1.05 * o.flicker.mean,
        "DOM-3 flicker {} against OSM-16's {}: the claim (OSM-16 above DOM-3) may now hold",
        d.flicker.mean,
        o.flicker.mean
    );
    assert!(
        d.image_flicker > o.image_flicker,
        "DOM-3 image flicker {} against OSM-16's {}",
        d.image_flicker,
        o.image_flicker
    );
}

/// MC-3, Yuksel & Keyser 2008 (deep opacity maps showed "minor flickering due to aliased line drawing", which
/// multisampling the shadow computation reduced): light-space anti-aliasing lowers DOM's flicker. The strands
/// drawn from the light as ribbons of a least width with a coverage alpha (`render.light_strands = ribbons`,
/// Unreal's shadow-view anti-aliasing; the reference sees the same fragments) against lines, on straight hair in
/// motion. Measured (flicker, pop rate): lines 0.0939, 26.8 %; ribbons 2 texels wide 0.0589, 20.3 %; 4 texels
/// 0.0375, 9.3 % (OSM-16 likewise: 0.0805, 0.0368, 0.0202; occupancy maps do not gain — their map error grows
/// from 0.014 to 0.214 at 2 texels, the per-fragment alpha no longer being one constant).
/// Yuksel & Keyser's own remedy, light-map supersampling (`render.light_supersample = s`: every map built
/// `s` times finer, the lookup averaging the `s × s` sub-texels of the point's texel), measured the same way:
/// s = 2 0.0796, 31.9 %; s = 4 0.0515, 14.4 % — the flicker falls at both, the pop rate only at 4 (at 2 the finer
/// maps' own aliasing, halved by the average, still crosses the 0.1 pop threshold more often).
/// Measured under `light.fit = per-frame` and held there. Under the default `stable` (flicker, pop rate): lines
/// 0.0518, 14.6 %; ribbons 2 texels 0.0346, 9.3 %; 4 texels 0.0208, 3.0 %; supersampled s = 2 0.0533, 19.1 %;
/// s = 4 0.0441, 11.0 % — the ribbons still gain (0.67×, 0.40×), supersampling barely (1.03×, 0.85×): most of
/// what it removed under `per-frame` was the refit's flicker.
#[test]
fn mc3_light_space_anti_aliasing_lowers_deep_opacity_maps_flicker() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let dom3 = format!("{}:layers=3", Dom.name());
    // hairlab measure motion --preset straight-motion --frames 12 --set scene.generator.strands=800
    //   --set render.map_resolution=128 --set light.fit=per-frame --set render.light_strands=ribbons
    //   --set render.light_min_width=W --config dom:layers=3 (W = 2, 4; without the two render keys for lines)
    let flicker = |extra: &[&str]| {
        let mut overrides = vec![
            "scene.generator.strands=800",
            "render.map_resolution=128",
            "light.fit=per-frame",
        ];
        overrides.extend(extra);
        let m = measure(
            &gpu,
            "straight-motion",
            &overrides,
            std::slice::from_ref(&dom3),
            12,
        );
        let r = row(&m, &dom3);
        (r.flicker.mean, r.flicker.pop_rate)
    };
    let lines = flicker(&[]);
    let ribbons2 = flicker(&["render.light_strands=ribbons", "render.light_min_width=2"]);
    let ribbons4 = flicker(&["render.light_strands=ribbons", "render.light_min_width=4"]);
    assert!(
        ribbons2.0 < 0.8 * lines.0,
        "ribbons (2 texels) flicker {:?} against lines {:?}",
        ribbons2,
        lines
    );
    assert!(
        ribbons4.0 < 0.8 * ribbons2.0 && ribbons4.1 < ribbons2.1,
        "ribbons (4 texels) {:?} against 2 texels {:?}",
        ribbons4,
        ribbons2
    );
    // The same command with --set render.light_supersample=S (S = 2, 4) and lines.
    let super2 = flicker(&["render.light_supersample=2"]);
    let super4 = flicker(&["render.light_supersample=4"]);
    // Measured flicker ratios against lines: 0.848 (s = 2), 0.549 (s = 4); pop rate 0.537 of lines' at s = 4.
    assert!(
        super2.0 < 0.92 * lines.0,
        "supersampled 2×2 flicker {:?} against lines {:?}",
        super2,
        lines
    );
    assert!(
        super4.0 < 0.65 * lines.0 && super4.1 < 0.7 * lines.1,
        "supersampled 4×4 {:?} against lines {:?}",
        super4,
        lines
    );
}

/// MC-4, Voicu: Bounding Opacity Maps' split ratio chosen by the analysis on frame 0 and kept, against chosen
/// again on every frame, while the head turns. Measured: both choose alike until the turn is under way, then
/// the per-frame choice changes and its map error drops below the kept ratio's.
#[test]
fn mc4_choosing_bounding_opacity_maps_split_ratio_every_frame_lowers_the_error_over_a_head_turn() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (once, every) = (
        format!("{}:layers=4,split_ratio=auto", Bom.name()),
        format!("{}:layers=4,split_ratio=auto-per-frame", Bom.name()),
    );
    // hairlab measure --motion --preset head-turn --frames 12 --set scene.generator.strands=600
    //   --set render.map_resolution=128 --set motion.head_period=1
    //   --config bom:layers=4,split_ratio=auto --config bom:layers=4,split_ratio=auto-per-frame
    let m = measure(
        &gpu,
        "head-turn",
        &[
            "scene.generator.strands=600",
            "render.map_resolution=128",
            "motion.head_period=1",
        ],
        &[once.clone(), every.clone()],
        12,
    );
    let (a, b) = (row(&m, &once), row(&m, &every));
    // Frame 0: the same choice, so the same error, bit for bit.
    assert_eq!(a.frames[0].map_error, b.frames[0].map_error);
    // Measured map error over the 12 frames: kept 0.09689, per frame 0.08881 (0.917); frames 9–11: 0.0997–0.1021
    // against 0.0680–0.0692.
    assert!(
        b.map_error.mean < 0.96 * a.map_error.mean,
        "per-frame split ratio {} against kept {}",
        b.map_error.mean,
        a.map_error.mean
    );
    assert!(
        b.frames
            .iter()
            .zip(&a.frames)
            .all(|(x, y)| x.map_error <= y.map_error + 1e-9),
        "the per-frame choice should never be worse than the kept one on a frame"
    );
}

/// MC-5 over 10,000 frames, on the CPU model (`motion::sim`, the specification; the GPU pass equals it per
/// frame, `motion::the_gpu_simulation_equals_the_cpu_model_over_a_run_of_frames`): a small head in gusty wind,
/// shaking, keeps every segment at its rest length, every root on the moving scalp and every point out of the
/// head up to a stated depth, with bounded kinetic energy; a second run is the same bits at every frame, and
/// scrubbing back after the run lands on the same bits.
#[test]
fn mc5_the_simulation_keeps_its_invariants_over_ten_thousand_frames() {
    const FRAMES: u32 = 10_000;
    let settings = Settings::load_preset(
        "wind",
        &[
            "scene.generator.strands=24".to_string(),
            "scene.generator.segments=8".to_string(),
            "motion.head=shake".to_string(),
            "motion.head_period=1".to_string(),
            format!("motion.frames={FRAMES}"),
        ],
    )
    .unwrap();
    let head = Ellipsoid {
        center: Vec3::ZERO,
        radii: HEAD_RADII,
    };
    let checksum = |p: &[Vec3]| {
        p.iter()
            .flat_map(|v| v.to_array())
            .fold(0u64, |h, x| h.rotate_left(5) ^ u64::from(x.to_bits()))
    };
    let run = || {
        let (scene, mut motion) = settings.open_motion().unwrap();
        let starts: Vec<usize> = scene.strands.ranges().map(|(first, _)| first).collect();
        let Motion::Simulate(sim) = &mut motion else {
            panic!("wind simulates")
        };
        let n = scene.strands.point_count() as f64;
        let (mut len, mut depth, mut root, mut scalp) = (0f32, 0f32, 0f32, 0f32);
        let (mut first_energy, mut last_energy) = (0f64, 0f64);
        let mut sums = Vec::with_capacity(FRAMES as usize);
        let mut kept = Vec::new();
        for k in 0..FRAMES {
            let points = sim.frame(k).to_vec();
            let st = sim.stats();
            assert!(st.finite, "frame {k}: a non-finite point");
            len = len.max(st.max_length_error);
            depth = depth.max(st.max_depth);
            root = root.max(st.max_root_error);
            let pose = sim.head_pose_at_frame(k);
            for &r in &starts {
                scalp = scalp.max((head.level(pose.inverse_apply(points[r])) - 1.0).abs());
            }
            let e = st.kinetic_energy / n;
            if k < 1000 {
                first_energy = first_energy.max(e);
            } else if k >= FRAMES - 1000 {
                last_energy = last_energy.max(e);
            }
            sums.push(checksum(&points));
            if k % 2500 == 1234 {
                kept.push((k, points));
            }
        }
        // Scrubbing back after the run: the same bits.
        for (k, points) in &kept {
            assert_eq!(sim.frame(*k), &points[..], "frame {k} scrubbed back to");
        }
        (sums, [len, depth, root, scalp], first_energy, last_energy)
    };
    let (sums, [len, depth, root, scalp], first_energy, last_energy) = run();
    eprintln!(
        "{FRAMES} frames: length {len:e}, depth {depth:e}, root {root:e}, scalp level {scalp:e}, energy per point \
         first 1000 frames {first_energy}, last 1000 {last_energy}"
    );
    // Measured (x86-64, debug, 10,000 frames): length 4.8e-7, depth 8.0e-8 world units, root 7.5e-9, scalp level
    // 4.8e-7, energy per point at most 0.576 (m/s)² in the first 1000 frames and 0.573 in the last 1000.
    assert!(len < 1e-5, "worst relative segment-length error {len}");
    // Depth: measured at most 8.0e-8; held to 5e-7, about 60 ulps of an f32 at the head's radii (0.09–0.115,
    // ulp 7.5e-9 near 0.1), so a change that leaves points inside the head shows here.
    assert!(
        depth < 5e-7,
        "worst depth inside the head {depth} (radii 0.09–0.115)"
    );
    assert!(root < 1e-6, "a root left its posed rest position by {root}");
    assert!(scalp < 1e-5, "a root left the scalp: |level − 1| = {scalp}");
    assert!(
        last_energy < 2.0 * first_energy && last_energy < 10.0,
        "kinetic energy per point: {first_energy} in the first 1000 frames, {last_energy} in the last"
    );
    let (again, ..) = run();
    let differ = sums.iter().zip(&again).position(|(a, b)| a != b);
    assert_eq!(differ, None, "a second run differs from frame {differ:?}");
}
