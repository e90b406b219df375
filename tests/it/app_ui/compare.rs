//! The compare view (four labelled images and their metrics) and the pixel inspector (the list of a clicked hair
//! pixel).

use super::{click_pixel, open_compare, tall_harness, tall_harness_on};
use egui_kittest::kittest::{NodeT, Queryable};
use hairlab::gpu::Gpu;
use hairlab::measure::MethodConfig;
use hairlab::render::transparency::registry as techniques;

#[test]
fn compare_view_renders_four_labelled_images_and_their_metrics() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    open_compare(&mut harness);
    let app = harness.state();
    let frames = app.compare().frames().expect("compare frames rendered");
    assert_eq!(frames.images.len(), 4);
    assert_eq!(frames.images[0].name, techniques::reference().name());
    assert_eq!(frames.images[1].name, app.settings().transparency.name);
    assert_eq!(frames.lists.len(), (frames.width * frames.height) as usize);
    let hair = frames.hair.iter().filter(|&&h| h).count();
    assert!(hair > 500, "only {hair} hair pixels");
    for (i, img) in frames.images.iter().enumerate() {
        assert_eq!(img.image.dimensions(), (frames.width, frames.height));
        assert!(app.compare().image_rect(i).is_some(), "image {i} not drawn");
        // Outside the hair every technique shows the opaque image alone.
        let differ = img
            .image
            .pixels()
            .zip(frames.images[0].image.pixels())
            .zip(&frames.hair)
            .filter(|((p, q), h)| !**h && p != q)
            .count();
        assert_eq!(
            differ, 0,
            "{}: pixels without hair differ from the reference",
            img.name
        );
    }
    // Four captions, each naming its technique and its GPU time (or why there is none).
    let captions: Vec<String> = harness
        .query_all_by_label_contains(" — GPU")
        .map(|n| n.accesskit_node().value().unwrap_or_default())
        .collect();
    assert_eq!(captions.len(), 4, "{captions:?}");
    for (c, img) in captions.iter().zip(&frames.images) {
        assert!(c.starts_with(&format!("{} — GPU", img.label)), "{c}");
    }
    // The metrics of the selected technique against the reference: a real difference on the hair.
    let m = &frames.images[1].metrics;
    assert!(m.rmse_hair > 0.0 && m.rmse_hair > m.rmse, "{m:?}");
    assert!(harness.query_by_label("RMSE hair").is_some());
    assert!(harness.query_by_label("contrast retention").is_some());
    // FLIP beside them: the hair differs, so its hair mean is above the all-pixel one (no difference elsewhere).
    assert!(m.flip.mean_hair > m.flip.mean && m.flip.mean > 0.0, "{m:?}");
    assert!(harness.query_by_label("FLIP hair").is_some());
    // The FLIP map in place of the difference.
    let caption = format!(
        "FLIP of {} against {}",
        frames.images[1].label, frames.images[0].label
    );
    harness.get_by_label("FLIP map").click();
    harness.run();
    assert!(harness.state().compare().flip_map);
    harness.get_by_label_contains(&caption);

    // Export: every image, the difference and FLIP maps and metrics.csv, into a folder set in place of the dialog.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export images…").click();
    harness.run();
    let frames = harness.state().compare().frames().unwrap();
    let open = |name: String| image::open(export.path().join(name)).unwrap().to_rgba8();
    for (i, img) in frames.images.iter().enumerate() {
        let k = i + 1;
        assert!(
            open(format!("{k}_{}.png", img.name)) == img.image,
            "image {k} written as shown"
        );
        if i > 0 {
            for map in ["difference", "flip"] {
                let written = open(format!("{map}_{k}_{}.png", img.name));
                assert_eq!(written.dimensions(), (frames.width, frames.height), "{map} {k}");
            }
        }
    }
    let mut csv = csv::Reader::from_path(export.path().join("metrics.csv")).unwrap();
    let header = csv.headers().unwrap().clone();
    assert_eq!(
        &header.iter().take(4).collect::<Vec<_>>(),
        &["slot", "technique", "label", "rmse"]
    );
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 3);
    for (r, img) in rows.iter().zip(&frames.images[1..]) {
        assert_eq!(&r[column("technique")], img.name);
        assert_eq!(
            r[column("rmse_hair")].parse::<f64>().unwrap(),
            img.metrics.rmse_hair
        );
        assert_eq!(
            r[column("flip_hair")].parse::<f64>().unwrap(),
            img.metrics.flip.mean_hair
        );
    }
}

#[test]
fn pixel_inspector_shows_the_list_of_a_clicked_hair_pixel() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let mut harness = tall_harness();
    harness.run();
    open_compare(&mut harness);
    // The hair pixel with the most fragments, clicked in the reference image.
    let app = harness.state();
    let frames = app.compare().frames().expect("compare frames rendered");
    let (index, list) = frames
        .lists
        .iter()
        .enumerate()
        .max_by_key(|(_, l)| l.len())
        .unwrap();
    let expected = list.clone();
    let w = frames.width;
    let pixel = [index as u32 % w, index as u32 / w];
    let gpu_reference = frames.images[0].image.get_pixel(pixel[0], pixel[1]).0;
    click_pixel(&mut harness, pixel);
    let app = harness.state();
    let report = app.pixel_inspector().report().expect("a report of the pixel");
    assert_eq!(report.fragments, expected);
    assert!(
        expected.len() >= 2,
        "deepest pixel holds {} fragments",
        expected.len()
    );
    assert!(expected.windows(2).all(|p| p[0].depth <= p[1].depth));
    // The transmittance behind the last fragment is the product of (1 - a), in f64 here.
    let through: f64 = expected.iter().map(|f| 1.0 - f64::from(f.alpha)).product();
    assert!((f64::from(*report.transmittance.last().unwrap()) - through).abs() < 1e-5);
    // The exact model's colour, sRGB encoded, is the GPU reference's pixel (8-bit rounding of both, and of the
    // background the model is fed).
    let encoded: egui::Color32 =
        egui::Rgba::from_rgb(report.reference[0], report.reference[1], report.reference[2]).into();
    for (c, g) in [encoded.r(), encoded.g(), encoded.b()].iter().zip(gpu_reference) {
        assert!(
            c.abs_diff(g) <= 2,
            "CPU exact {encoded:?} vs GPU {gpu_reference:?}"
        );
    }
    assert_eq!(report.composites.len(), techniques::all().len());
    let reference = &report.composites[0];
    assert_eq!(
        (reference.name, reference.delta),
        (techniques::reference().name(), 0.0)
    );
    let title = format!(
        "pixel ({}, {}) · {} fragments",
        pixel[0],
        pixel[1],
        expected.len()
    );
    assert!(harness.query_by_label(&title).is_some(), "{title} not shown");

    // The fragment table and the plot leave the window: pixel.csv and the plot's PNG into a folder set in place
    // of the dialog, and the table's text copied to the clipboard.
    let export = tempfile::tempdir().unwrap();
    harness
        .state_mut()
        .set_export_dir(Some(export.path().to_path_buf()));
    harness.get_by_label("Export table and plot…").click();
    harness.run();
    let plot = image::open(export.path().join("pixel_transmittance.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), hairlab::bench::CHART_SIZE);
    let text = std::fs::read_to_string(export.path().join("pixel.csv")).unwrap();
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("rank,depth,segment,alpha,r,g,b,transmittance,weight")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), expected.len());
    for (k, (r, f)) in rows.iter().zip(&expected).enumerate() {
        assert_eq!(r[0], k.to_string());
        assert_eq!(r[1].parse::<f32>().unwrap(), f.depth);
        assert_eq!(r[2], f.segment.to_string());
    }
    harness.get_by_label("Copy table").click();
    harness.step();
    let copied = harness
        .output()
        .platform_output
        .commands
        .iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t.clone()),
            _ => None,
        })
        .expect("the table copied");
    assert_eq!(copied, text);
}

/// The compare window's decomposition against the path-traced truth (issue 42): its button runs the chain as a
/// job, the table holds the rows `measure::shading::against_truth` gives for the selected method under
/// `render.shading` (the one place the CLI and the report call; the same numbers, as the path tracer is seeded),
/// each effect on screen, and the pixel inspector notes each chain image's colour at a clicked hair pixel.
#[test]
fn the_compare_window_decomposes_against_the_truth_and_the_inspector_notes_the_chain() {
    let gpu = Gpu::for_tests().expect("GPU tests opted out");
    let mut settings = crate::common::small_settings(320, 240);
    settings.render.spp = 2;
    let expected = hairlab::measure::shading::against_truth(
        &gpu,
        &settings,
        &[MethodConfig::new(
            &settings.method.name,
            settings.method.params.clone(),
        )],
        &[settings.render.shading],
        &mut hairlab::progress::Quiet,
    )
    .unwrap()
    .expect("not stopped")
    .1
    .decomposition;
    let mut harness = tall_harness_on(settings);
    harness.run();
    open_compare(&mut harness);
    harness.get_by_label("Against the path-traced truth").click();
    harness.run();
    harness.get_by_label("Decompose against the truth").click();
    harness.run();
    harness.state_mut().finish_jobs();
    harness.run();
    let app = harness.state();
    assert_eq!(app.compare().truth.error(), None);
    let got = &app.compare().truth.result().expect("a decomposition").rows;
    assert_eq!(got, &expected);
    for row in &expected {
        assert!(
            harness.query_all_by_label(row.effect).next().is_some(),
            "no row {}",
            row.effect
        );
    }
    let total = expected.last().unwrap();
    for (what, v) in [("RMSE", total.hair_rmse), ("coarse RMSE", total.hair_coarse)] {
        assert!(
            harness.query_all_by_label(&format!("{v:.3}")).next().is_some(),
            "the total's hair {what} {v:.3} is not on screen"
        );
    }
    // The inspector's note: every chain image at the deepest hair pixel.
    let frames = harness.state().compare().frames().unwrap();
    let (w, h) = (frames.width, frames.height);
    let index = (0..frames.lists.len())
        .max_by_key(|&i| frames.lists[i].len())
        .unwrap();
    let pixel = [index as u32 % w, index as u32 / w];
    click_pixel(&mut harness, pixel);
    harness.get_by_label("path-traced chain here:");
    let chain = harness
        .state()
        .compare()
        .truth
        .result()
        .unwrap()
        .at(pixel, (w, h));
    assert_eq!(
        chain.len(),
        7,
        "truth, fibre events, one event, map shadows, raster one event, raster, reference"
    );
    for (label, _) in &chain {
        assert!(
            harness.query_by_label_contains(&format!("{label} (")).is_some(),
            "no note for {label}"
        );
    }
}
