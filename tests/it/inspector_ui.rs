//! The texel inspector driven headless by egui_kittest on the software adapter: picking a strand in the viewport,
//! the light-map view, the plot data of a selected texel against the exact fragment lists, pins, the CSV export
//! and the synthetic texel lab.

use crate::common;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use hairlab::app::inspector::TexelPlot;
use hairlab::app::texel_lab::{LabSettings, LabSource};
use hairlab::app::{HairlabApp, wgpu_setup};
use hairlab::gpu::{AdapterPreference, Gpu};
use hairlab::settings::Settings;
use hairlab::visibility::Fragment;

fn harness(settings: Settings) -> Harness<'static, HairlabApp> {
    // Plotting every method resizes the window over a few frames.
    Harness::builder()
        .with_size([1100.0, 760.0])
        .with_max_steps(8)
        .wgpu_setup(wgpu_setup(AdapterPreference::Software))
        .build_eframe(move |cc| {
            let mut app = HairlabApp::new(cc, Some(settings));
            app.set_snapshot_mode(true);
            app
        })
}

/// `exp(-sum of b)` over `fragments`, in f64.
fn transmittance_through(fragments: &[Fragment]) -> f64 {
    let b: f64 = fragments.iter().map(|f| -(1.0 - f64::from(f.alpha)).ln()).sum();
    (-b).exp()
}

fn current(harness: &Harness<'_, HairlabApp>) -> TexelPlot {
    harness
        .state()
        .inspector()
        .curves()
        .and_then(|c| c.current.clone())
        .expect("an inspected texel")
}

#[test]
fn click_on_hair_picks_a_texel_holding_the_clicked_segment() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = harness(common::small_settings(320, 240));
    harness.run();
    assert!(!harness.state().inspector().open);
    // Click (press and release without moving) down the middle of the viewport until one lands on hair.
    let picked = [140.0, 180.0, 220.0, 260.0, 300.0, 340.0, 380.0]
        .into_iter()
        .find_map(|y| {
            let pos = egui::pos2(720.0, y);
            harness.hover_at(pos);
            harness.step();
            harness.drag_at(pos);
            harness.step();
            harness.drop_at(pos);
            harness.run();
            harness.state().inspector().selected
        })
        .expect("no click down the middle of the viewport picked a strand");
    let pick = picked.picked.expect("selected by a pick");
    let app = harness.state();
    assert!(app.inspector().open, "picking opens the inspector");
    // The texel holds a fragment of the clicked segment (the light's rasteriser drew it there).
    let lists = app.inspector().lists().expect("fragment lists read");
    let [x, y] = picked.texel;
    let list = &lists.lists[(y * lists.resolution + x) as usize];
    assert!(
        list.iter().any(|f| f.segment == pick.segment),
        "texel ({x}, {y}) holds no fragment of segment {}: {list:?}",
        pick.segment
    );
    let (message, error) = app.message().unwrap();
    assert!(
        !error && message.contains(&format!("texel ({x}, {y})")),
        "{message}"
    );
    assert_eq!(current(&harness).depth_complexity(), list.len());
}

#[test]
fn inspector_plots_pins_exports_and_compares() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(320, 240);
    settings.method.name = "osm".into();
    settings.method.params.insert("slices".into(), 4.0);
    let mut harness = harness(settings);
    harness.run();

    // The light map from the side panel; its "Densest texel" button inspects the texel with the most fragments.
    harness.get_by_label("Light map").click();
    harness.run();
    harness.get_by_label("Densest texel").click();
    harness.run();
    let lists = harness.state().inspector().lists().expect("fragment lists read");
    let max = lists.lists.iter().map(Vec::len).max().unwrap();
    let densest = lists.densest().unwrap();
    // Another texel, chosen programmatically: the first one in row-major order holding 3 fragments or more.
    let other = (0..lists.lists.len())
        .find(|&i| lists.lists[i].len() >= 3 && i != (densest[1] * lists.resolution + densest[0]) as usize)
        .map(|i| [i as u32 % lists.resolution, i as u32 / lists.resolution])
        .unwrap();
    let other_fragments: Vec<Fragment> = lists.lists[(other[1] * lists.resolution + other[0]) as usize]
        .iter()
        .map(|f| f.fragment())
        .collect();
    assert!(harness.state().inspector().open);
    assert_eq!(current(&harness).depth_complexity(), max);
    assert!(max > 3, "densest texel holds {max} fragments");

    harness.state_mut().select_texel(other[0], other[1]);
    harness.run();
    let t = current(&harness);
    assert_eq!(t.label, format!("texel ({}, {})", other[0], other[1]));
    assert_eq!(t.fragments, other_fragments);
    // The reference starts at 1 (before the nearest fragment) and ends at exp(-sum b) (beyond the furthest).
    assert_eq!(t.reference[0], 1.0);
    let end = transmittance_through(&t.fragments);
    assert!(
        (f64::from(*t.reference.last().unwrap()) - end).abs() < 1e-6,
        "{:?} vs {end}",
        t.reference.last()
    );
    assert!(t.depths[0] < t.near && *t.depths.last().unwrap() > t.far);
    // The hair count beside V: no strand in front before the nearest fragment, every fragment beyond the
    // furthest; OSM-4's count is -ln V / b of its own curve at the scene's hair alpha.
    assert_eq!(t.reference_count[0], 0.0);
    assert_eq!(*t.reference_count.last().unwrap(), t.fragments.len() as f32);
    // The reference has no error; OSM-4, the selected method, has some.
    let r = t.reference_error.unwrap();
    assert_eq!((r.mean, r.max), (0.0, 0.0));
    assert_eq!(t.methods.len(), 1);
    let osm = &t.methods[0];
    assert_eq!(osm.label, "osm-4");
    assert!(osm.selected && osm.error.unwrap().mean > 0.0, "{:?}", osm.error);
    assert!(
        harness
            .state()
            .inspector()
            .curves()
            .unwrap()
            .stored
            .as_ref()
            .unwrap()
            .boundaries
            .len()
            == 5
    );

    for (c, v) in osm.counts.iter().zip(&osm.values) {
        let want = hairlab::visibility::count_from_visibility(*v, t.hair_alpha);
        assert!((c - want).abs() < 1e-6, "{c} vs {want}");
    }
    // The "count" toggle plots n(z) in place of V(z), and "V" brings V back.
    harness.get_by_label("count").click();
    harness.run();
    assert!(harness.state().inspector().show_count);
    harness.get_by_label("V").click();
    harness.run();
    assert!(!harness.state().inspector().show_count);

    // Every method at once, then pin this texel and go back to the densest one.
    harness.get_by_label("every method").click();
    harness.run();
    let labels: Vec<String> = current(&harness)
        .methods
        .iter()
        .map(|m| m.label.clone())
        .collect();
    // Every inspected method once (the selected OSM with its 4 slices, the others at their defaults).
    let inspected = hairlab::methods::registry::all()
        .iter()
        .filter(|m| hairlab::app::inspector::inspected(**m))
        .count();
    assert_eq!(labels.len(), inspected, "{labels:?}");
    for want in ["osm-4", "dom-3", "bom-4", "occupancy", "dc-4"] {
        assert!(labels.iter().any(|l| l == want), "{want} missing from {labels:?}");
    }
    // The whole map: every plotted method's texel-error distribution over the occupied texels, on request. The
    // texel's ray-traced curve lands first (it adds rows above the buttons: a click while it is on its way can
    // land where a button was).
    harness.state_mut().finish_jobs();
    harness.run();
    assert!(harness.state().inspector().map_stats().is_none());
    harness.get_by_label("Whole map").click();
    harness.run();
    harness.get_by_label("Compute").click();
    // A job: one frame takes the click and starts it; wait for it and apply its result.
    harness.step();
    harness.state_mut().finish_jobs();
    harness.run();
    let stats = harness.state().inspector().map_stats().expect("computed").clone();
    let occupied = lists_occupied(&harness);
    assert_eq!(stats.rows.len(), inspected);
    for (row, curve) in stats.rows.iter().zip(&current(&harness).methods) {
        let e = row.error.as_ref().expect("occupied texels");
        let d = &e.distribution;
        assert_eq!((row.label.as_str(), e.texels), (curve.label.as_str(), occupied));
        assert!(d.p50 <= d.p95 && d.p95 <= d.p99 && d.p99 <= d.worst, "{row:?}");
        assert!(
            f64::from(e.mean) <= d.worst && d.share_over[1] <= d.share_over[0],
            "{row:?}"
        );
        assert!(
            d.worst <= f64::from(e.max) + 1e-6,
            "a texel's mean is at most its max: {row:?}"
        );
    }
    // Folded again, so that the rest of the window keeps its layout.
    harness.get_by_label("Whole map").click();
    harness.run();
    harness.get_by_label("Pin").click();
    harness.run();
    assert_eq!(harness.state().inspector().pins().len(), 1);
    harness.get_by_label("Densest texel").click();
    harness.run();
    let curves = harness.state().inspector().curves().unwrap().clone();
    assert_eq!(curves.current.as_ref().unwrap().depth_complexity(), max);
    assert_eq!(curves.pins.len(), 1);
    assert_eq!(curves.pins[0].fragments, other_fragments);

    // CSV: one row per plotted depth of either texel, the reference, the ray-traced V of both texels' fibres
    // (traced by a job: wait for it) and every curve shown.
    harness.state_mut().finish_jobs();
    harness.run();
    let curves = harness.state().inspector().curves().unwrap().clone();
    assert!(curves.current.as_ref().unwrap().traced.is_some() && curves.pins[0].traced.is_some());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("curves.csv");
    harness.state_mut().export_inspector_csv(&path);
    let text = std::fs::read_to_string(&path).expect("CSV written");
    let mut lines = text.lines();
    // The header: depth, the reference, every curve shown (in plot order), then the pin's; each curve followed by
    // its hair count.
    let curve_and_count = |name: String| {
        let count = format!("{name} count");
        [name, count]
    };
    let mut header = vec!["depth".to_string()];
    header.extend(curve_and_count("reference".into()));
    header.push("ray-traced".into());
    header.extend(labels.iter().cloned().flat_map(curve_and_count));
    header.extend(curve_and_count("pin1 reference".into()));
    header.push("pin1 ray-traced".into());
    header.extend(curve_and_count("pin1 osm-4".into()));
    assert_eq!(lines.next().unwrap(), header.join(","));
    let rows: Vec<Vec<f32>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let mut depths: Vec<f32> = curves
        .current
        .iter()
        .chain(&curves.pins)
        .flat_map(|t| t.depths.clone())
        .collect();
    depths.sort_by(f32::total_cmp);
    depths.dedup();
    assert_eq!(rows.len(), depths.len());
    // The rows hold the plotted values: the densest texel's reference, its ray-traced V and OSM-4 at its own
    // depths.
    let cur = curves.current.as_ref().unwrap();
    let traced = &cur.traced.as_ref().unwrap().values;
    for (i, z) in cur.depths.iter().enumerate() {
        let row = rows.iter().find(|r| r[0] == *z).expect("a row per plotted depth");
        assert_eq!(
            (row[1], row[2], row[3], row[4], row[5]),
            (
                cur.reference[i],
                cur.reference_count[i],
                traced[i],
                cur.methods[0].values[i],
                cur.methods[0].counts[i]
            )
        );
    }
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("curves exported"))
    );

    // Remove the pin through its button.
    harness.get_by_label("remove").click();
    harness.run();
    assert!(harness.state().inspector().pins().is_empty());
}

#[test]
fn synthetic_lab_shows_density_clustering_break_down_with_more_gaussians() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(320, 240);
    settings.method.name = "dc".into();
    let mut harness = harness(settings);
    harness.run();
    harness.get_by_label("Texel inspector").click();
    harness.run();
    harness.get_by_label("Synthetic texel").click();
    harness.run();
    // Mertens et al. Fig. 5: 100 fragments from Q Gaussians against K = 4 clusters.
    let mut dc_error = |gaussians: u32| {
        harness.state_mut().inspector_mut().lab = LabSettings {
            source: LabSource::Gaussians,
            gaussians,
            per_gaussian: 100 / gaussians,
            spread: 0.03,
            alpha: 0.05,
            seed: 5,
            ..LabSettings::default()
        };
        harness.run();
        let t = current(&harness);
        assert_eq!(t.depth_complexity() as u32, gaussians * (100 / gaussians));
        assert_eq!(t.methods[0].label, "dc-4");
        assert_eq!(t.reference[0], 1.0);
        t.methods[0].error.unwrap()
    };
    let two = dc_error(2);
    let eight = dc_error(8);
    eprintln!("DC-4 texel error, Q=2: {two:?}; Q=8: {eight:?}");
    assert!(eight.mean > two.mean, "Q=8 {eight:?} vs Q=2 {two:?}");

    // Typed fragments: a bad line is reported, a good text plotted.
    harness.get_by_label("Typed fragments").click();
    harness.run();
    harness.state_mut().inspector_mut().lab.text = "0.2,0.5\n0.6;0.5\n".into();
    harness.run();
    let (message, error) = harness.state().message().unwrap();
    assert!(error && message.contains("typed fragments:2"), "{message}");
    assert!(harness.state().inspector().curves().unwrap().current.is_none());
    harness.state_mut().inspector_mut().lab.text = "0.2,0.5\n0.6,0.5\n".into();
    harness.run();
    let t = current(&harness);
    assert_eq!(t.fragments, [Fragment::new(0.2, 0.5), Fragment::new(0.6, 0.5)]);
    assert!((t.reference.last().unwrap() - 0.25).abs() < 1e-6);
}

/// Texels of the inspector's lists holding fragments.
fn lists_occupied(harness: &Harness<'_, HairlabApp>) -> usize {
    let lists = harness.state().inspector().lists().expect("fragment lists");
    lists.lists.iter().filter(|l| !l.is_empty()).count()
}

/// "Export plot…" writes the texel inspector's `V(z)` plot (and, with "count" on, the count plot too) as PNG and
/// SVG through the bench's chart writer: each PNG decodes at the chart size and shows the reference's and the
/// method's curves in their colours; "Copy plot" copies the plot shown.
#[test]
fn the_texel_plot_is_exported_as_png_with_its_curves() {
    use hairlab::app::inspector::{PlotKind, REFERENCE_COLOR};
    use hairlab::methods::LightMethod;
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut settings = common::small_settings(320, 240);
    settings.method.name = hairlab::methods::dc::Dc.name().into();
    let mut harness = harness(settings);
    harness.run();
    harness.get_by_label("Texel inspector").click();
    harness.run();
    harness.get_by_label("Synthetic texel").click();
    harness.run();
    harness.state_mut().inspector_mut().lab = LabSettings {
        source: LabSource::Gaussians,
        gaussians: 2,
        per_gaussian: 50,
        spread: 0.03,
        alpha: 0.05,
        seed: 5,
        ..LabSettings::default()
    };
    harness.run();
    let t = current(&harness);
    assert_eq!(t.methods.len(), 1, "the selected method's curve");
    let method = t.methods[0].model.color;
    let method = [method.r(), method.g(), method.b()];
    let dir = tempfile::tempdir().unwrap();
    harness.state_mut().set_export_dir(Some(dir.path().to_path_buf()));
    harness.get_by_label("Export plot…").click();
    harness.run();
    let (w, h) = hairlab::bench::CHART_SIZE;
    // The x columns of the PNG of `kind` holding a pixel of exactly `color`.
    let columns = |kind: PlotKind, color: [u8; 3]| {
        let img = image::open(dir.path().join(format!("{}.png", kind.stem())))
            .unwrap()
            .to_rgb8();
        assert_eq!(img.dimensions(), (w, h), "{kind:?}: the chart size");
        (0..img.width())
            .filter(|&x| (0..img.height()).any(|y| img.get_pixel(x, y).0 == color))
            .count()
    };
    // A curve across the fragments' depths (z 0.06 to 0.88) spans some 870 of the plot's ~1060 columns; its
    // legend disc and markers ~100. Where DC-4 lies on the reference it hides it in the V plot (drawn after it).
    // Measured on lavapipe: V: DC-4 894, reference 159 columns; count: DC-4 879, reference 795.
    let v = PlotKind::Visibility;
    let (r, m) = (columns(v, REFERENCE_COLOR), columns(v, method));
    assert!(m > 700 && r > 100, "V: reference {r}, method {m} columns");
    assert!(dir.path().join("texel_v.svg").is_file());
    assert!(
        !dir.path().join("texel_count.png").exists(),
        "no count plot while V is shown"
    );
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("wrote 2 files")),
        "{:?}",
        harness.state().message()
    );

    // With the count plot shown, both plots.
    harness.get_by_label("count").click();
    harness.run();
    harness.get_by_label("Export plot…").click();
    harness.run();
    let count = PlotKind::Count;
    let (r, m) = (columns(count, REFERENCE_COLOR), columns(count, method));
    assert!(m > 700 && r > 700, "count: reference {r}, method {m} columns");
    assert!(columns(v, method) > 700, "the V plot written beside it");
    harness.get_by_label("Copy plot").click();
    harness.run();
    assert!(
        harness
            .state()
            .message()
            .is_some_and(|(m, e)| !e && m.contains("plot copied")),
        "{:?}",
        harness.state().message()
    );
}

/// The inspected texel's ray-traced `V(z)`: the inspector's series is `pathtrace::visibility::texel_visibility`
/// of the texel's footprint in the hair maps' light frame (a renderer of its own on the app's scene), with
/// `TRACED_RAYS`² rays seeded as `compare_map` seeds them, at the plotted depths times `far − near`; the legend
/// names it, and the figures give its value beyond the last fragment.
#[test]
fn the_inspected_texel_shows_its_ray_traced_visibility() {
    use hairlab::app::inspector::{TRACED_RAYS, traced_label};
    use hairlab::pathtrace::visibility::{light_map_texel, texel_visibility};
    use hairlab::pathtrace::{bvh::Bvh, fibre};
    let Some(gpu) = Gpu::for_tests() else { return };
    let settings = common::small_settings(320, 240);
    let mut harness = harness(settings.clone());
    harness.run();
    harness.get_by_label("Light map").click();
    harness.run();
    harness.get_by_label("Densest texel").click();
    harness.run();
    harness.state_mut().finish_jobs();
    harness.run();
    let t = current(&harness);
    let traced = t
        .traced
        .clone()
        .expect("the ray-traced curve of the inspected texel");
    let [x, y] = harness.state().inspector().scene_texel().unwrap();
    let scene = harness.state().scene().unwrap();
    let side = settings.render.light_map_side();
    let frame = hairlab::render::Renderer::new(&gpu, scene, settings.render.map_resolution)
        .unwrap()
        .hair_light_frame(&settings.light);
    let footprint = light_map_texel(&frame, side, x, y);
    let span = frame.far - frame.near;
    assert_eq!(traced.rays.footprint, footprint);
    assert_eq!(
        (traced.rays.span, traced.rays.footprint.seed),
        (span, u64::from(y * side + x))
    );
    let bvh = Bvh::new(fibre::segments(&scene.strands, settings.render.strand_width));
    let at: Vec<f32> = t.depths.iter().map(|z| z * span).collect();
    let want = texel_visibility(&bvh, &footprint, TRACED_RAYS, &at);
    assert_eq!(traced.values, want);
    // The densest texel's fibres block some of its rays, not before its first fragment.
    assert_eq!(traced.values[0], 1.0);
    assert!(*traced.values.last().unwrap() < 1.0, "{:?}", traced.values.last());
    assert!(
        harness.query_by_label_contains(&traced_label()).is_some(),
        "the legend names the series"
    );
    assert!(
        harness.query_by_label("ray-traced, beyond").is_some(),
        "the figures row"
    );
}

/// Strands along x at depths 1.6 apart, each alone in a row of the 16² map of a light along −z (azimuth and
/// elevation 0, light space x and y the world's), 0.3 of a texel wide and well inside its row; one strand along y
/// at x = −0.5 makes the map square (8.5 deep). Returns the settings (coverage alpha: each fragment's `α` is the strand's
/// share of the texel, 0.3) and the directory holding the file.
fn row_strands_scene() -> (Settings, tempfile::TempDir) {
    use glam::Vec3;
    use hairlab::scene::Strands;
    const SIDE: u32 = 16;
    // The per-frame window: the strands' box [-0.5, 0.5]² grown by 1e-3 of its side on each side.
    let texel = 1.002 / SIDE as f32;
    let width = 0.3 * texel;
    let mut points = vec![Vec3::new(-0.5, -0.5, 4.5), Vec3::new(-0.5, 0.5, 4.5)];
    for (k, row) in [2u32, 4, 6, 9, 11, 13].into_iter().enumerate() {
        // A tenth of a texel off the row's centre (clear of the line rasteriser's ties).
        let y = 0.501 - (row as f32 + 0.5) * texel + 0.1 * texel;
        let z = -4.0 + 1.6 * k as f32;
        points.extend([Vec3::new(-0.4, y, z), Vec3::new(0.5, y, z)]);
    }
    let strands = Strands {
        counts: vec![2; points.len() / 2],
        points,
        ..Strands::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.hair");
    hairlab::scene::load::save_strands(&path, &strands, "rows").unwrap();
    let settings = common::measured_preset(
        "default",
        &[
            format!("scene.file={}", path.display()),
            "render.width=320".into(),
            "render.height=240".into(),
            format!("render.map_resolution={SIDE}"),
            "render.alpha=coverage".into(),
            "render.hair_alpha=1".into(),
            format!("render.strand_width={width}"),
            "light.azimuth_deg=0".into(),
            "light.elevation_deg=0".into(),
        ],
    );
    (settings, dir)
}

/// Where each strand is alone in its texel and the fragment's `α` is its coverage, the product of `(1 − α)` is
/// the geometry: the ray-traced and depth-peeled curves agree. Measured away from the fragment (the fibre's front
/// surface lies half a width before the centre line the rasteriser draws, 0.0011 of the normalised depth here;
/// the plot spans 0.005 either side of a lone fragment),
/// within 0.05: the 16 × 16 jittered rays estimate the 0.3 coverage with σ ≈ 0.01 (two partly covered strata
/// rows of 16 rays).
#[test]
fn lone_strands_with_coverage_alpha_trace_as_the_reference() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let (settings, _dir) = row_strands_scene();
    let mut harness = harness(settings);
    harness.run();
    harness.get_by_label("Texel inspector").click();
    harness.run();
    harness.state_mut().select_texel(0, 0);
    harness.run();
    let lists = harness.state().inspector().lists().expect("fragment lists");
    // Texels of the horizontal strands, clear of their ends: one fragment each.
    let lone: Vec<[u32; 2]> = (0..lists.lists.len())
        .map(|i| [i as u32 % lists.resolution, i as u32 / lists.resolution])
        .filter(|&[x, y]| {
            (3..=13).contains(&x) && lists.lists[(y * lists.resolution + x) as usize].len() == 1
        })
        .collect();
    let rows: std::collections::BTreeSet<u32> = lone.iter().map(|t| t[1]).collect();
    assert_eq!(
        rows.into_iter().collect::<Vec<_>>(),
        [2, 4, 6, 9, 11, 13],
        "{lone:?}"
    );
    for [x, y] in lone.into_iter().filter(|t| t[0] == 8) {
        harness.state_mut().select_texel(x, y);
        harness.run();
        harness.state_mut().finish_jobs();
        harness.run();
        let t = current(&harness);
        let f = t.fragments[0];
        assert!(
            (f.alpha - 0.3).abs() < 0.01,
            "texel ({x}, {y}): α {} is not the coverage",
            f.alpha
        );
        let traced = t.traced.as_ref().expect("traced");
        let mut compared = 0;
        for ((z, v_ref), v_ray) in t.depths.iter().zip(&t.reference).zip(&traced.values) {
            if (z - f.depth).abs() > 0.002 {
                assert!(
                    (v_ray - v_ref).abs() < 0.05,
                    "texel ({x}, {y}) at z {z}: ray-traced {v_ray}, reference {v_ref}"
                );
                compared += 1;
            }
        }
        assert!(compared > 200, "{compared} of {} depths compared", t.depths.len());
        eprintln!(
            "texel ({x}, {y}): V beyond: reference {}, ray-traced {}",
            t.reference.last().unwrap(),
            traced.values.last().unwrap()
        );
    }
}

/// "Fit α to fibres" runs `compare_map` as a job and shows its result: the same comparison as `compare_map` run
/// directly on the window's settings. On the lone strands of 0.3 coverage the fitted α is near 0.3 whatever the
/// scene's (measured 0.267: the strand along y lies half outside the map and the strands' ends cover less of their
/// texels than a whole texel's width, so those texels fit lower); under a constant α the window offers it for
/// `render.hair_alpha`, and applying it sets it.
#[test]
fn the_alpha_fit_is_compare_maps_and_applies_to_the_hair_alpha() {
    use hairlab::app::inspector::FIT_RAYS;
    use hairlab::measure::fibre_visibility::compare_map;
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut settings, _dir) = row_strands_scene();
    settings.render.alpha = hairlab::render::AlphaMode::Constant;
    settings.render.hair_alpha = 0.5;
    let mut harness = harness(settings);
    harness.run();
    harness.get_by_label("Texel inspector").click();
    harness.run();
    harness.state_mut().select_texel(8, 2);
    harness.run();
    harness.get_by_label("Fit α to fibres").click();
    harness.step();
    harness.state_mut().finish_jobs();
    harness.run();
    let settings = harness.state().settings().clone();
    let fit = harness
        .state()
        .inspector()
        .alpha_fit(&settings)
        .expect("fitted")
        .clone();
    let direct = compare_map(&gpu, &settings, FIT_RAYS, &mut hairlab::progress::Quiet).unwrap();
    assert!(!direct.is_stopped());
    assert_eq!(fit.comparison, direct.kept());
    let a = fit.alpha().unwrap();
    eprintln!("{}", fit.summary(&settings));
    assert!((a - 0.3).abs() < 0.05, "best-fit α {a}");
    assert!(fit.comparison.mean_abs_dv_at_best < fit.comparison.mean_abs_dv);
    assert!(harness.query_by_label_contains("best-fit α = ").is_some());
    harness.get_by_label(&format!("Set hair α {a:.3}")).click();
    harness.run();
    assert_eq!(harness.state().settings().render.hair_alpha, a);
    // The fit is of the scene, light and map, not of the hair alpha: it stays shown, with nothing left to apply.
    let settings = harness.state().settings().clone();
    assert!(harness.state().inspector().alpha_fit(&settings).is_some());
    assert!(harness.query_by_label_contains("Set hair α").is_none());
}
