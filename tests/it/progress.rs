//! Where the library loops stop when their `Progress` answers `false` (`hairlab::progress`): a bench ends after
//! the configuration in progress and keeps it, a motion measurement keeps the configurations finished (both
//! `Outcome::Stopped`), a streamed animation fails with `Stopped` after the frames handed over, and the reported
//! fractions rise from 0 to 1.

use hairlab::bench::{self, BenchConfig};
use hairlab::gpu::Gpu;
use hairlab::measure::MethodConfig;
use hairlab::measure::motion::{MotionConfig, MotionOptions, measure_motion};
use hairlab::progress::Stopped;
use hairlab::settings::Settings;

/// A small scene: 200 strands, a 64² map, a 96×72 image.
fn small(preset: &str) -> Settings {
    let set: Vec<String> = [
        "scene.generator.strands=200",
        "render.map_resolution=64",
        "render.width=96",
        "render.height=72",
    ]
    .map(String::from)
    .to_vec();
    Settings::load_preset(preset, &set).unwrap()
}

/// A stop asked while the first of three configurations runs (the first step after its start answers `false`)
/// ends the bench after it: its row is kept, the outcome says it was stopped, and the fractions told rose.
#[test]
fn a_bench_stopped_during_a_configuration_keeps_that_one_and_measures_no_more() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let configs: Vec<BenchConfig> = [4, 8, 16]
        .map(|n| BenchConfig {
            config: MethodConfig::parse(&format!("osm:slices={n}")).unwrap(),
            note: String::new(),
        })
        .to_vec();
    let first = configs[0].config.label();
    let mut started = false;
    let mut fractions = Vec::new();
    let mut progress = |label: &str, f: f32| {
        fractions.push(f);
        let go_on = !started;
        started |= label == first;
        go_on
    };
    let outcome =
        bench::measure_configs(&small("default"), "small", &configs, 1, usize::MAX, &mut progress).unwrap();
    assert!(outcome.is_stopped());
    let r = outcome.kept().expect("a row before the stop");
    let labels: Vec<String> = r.rows.iter().map(|row| row.config.label()).collect();
    assert_eq!(labels, [first]);
    assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{fractions:?}");
    assert!(fractions.iter().all(|f| (0.0..=1.0).contains(f)), "{fractions:?}");
    // The step after the first configuration says one of three is done.
    assert!(fractions.contains(&(1.0 / 3.0)), "{fractions:?}");
}

/// A stop asked at the second configuration's first frame ends a motion measurement there: the first
/// configuration's row is whole (a frame row per frame), the second has none.
#[test]
fn a_motion_measurement_stopped_in_a_configuration_keeps_the_ones_finished() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let configs: Vec<MotionConfig> = ["osm:slices=16", "dom:layers=3"]
        .iter()
        .map(|c| MotionConfig::parse(c).unwrap())
        .collect();
    let second = configs[1].label();
    let mut progress = |label: &str, _: f32| !label.starts_with(&second);
    let m = measure_motion(
        &gpu,
        &small("stray-sweep"),
        &configs,
        3,
        MotionOptions::default(),
        &mut progress,
    )
    .unwrap();
    assert!(m.is_stopped());
    assert_eq!(m.rows.len(), 1);
    assert_eq!(m.rows[0].config.label(), configs[0].label());
    assert_eq!(m.rows[0].frames.len(), 3);
}

/// A stop asked at the reference's step (the first; every later step would go on) measures no configuration:
/// the answer is read, not dropped, and the scene's figures, which need the reference, are still there.
#[test]
fn a_stop_at_the_reference_step_measures_no_configuration() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let configs = [MethodConfig::parse("osm:slices=4").unwrap()];
    let mut asked = 0;
    let mut progress = |_: &str, _: f32| {
        asked += 1;
        asked > 1
    };
    let measured = hairlab::measure::measure_on(&gpu, &small("default"), &configs, 1, &mut progress).unwrap();
    assert!(measured.is_stopped());
    let (stats, rows) = measured.kept();
    assert!(rows.is_empty(), "{} rows", rows.len());
    assert!(stats.occupied_texels > 0);
}

/// `compare_map` stopped after its third texel is `Outcome::Stopped` with those three; run to the end it is
/// complete with every occupied texel.
#[test]
fn a_stopped_fibre_visibility_map_keeps_its_texels_and_says_it_is_incomplete() {
    use hairlab::measure::fibre_visibility::compare_map;
    let Some(gpu) = Gpu::for_tests() else { return };
    let s = small("default");
    let whole = compare_map(&gpu, &s, 1, &mut hairlab::progress::Quiet).unwrap();
    assert!(
        !whole.is_stopped() && whole.texels.len() > 3,
        "{} texels",
        whole.texels.len()
    );
    let mut steps = 0;
    let mut progress = |_: &str, _: f32| {
        steps += 1;
        steps < 3
    };
    let cut = compare_map(&gpu, &s, 1, &mut progress).unwrap();
    assert!(cut.is_stopped());
    assert_eq!(cut.texels, whole.texels[..3]);
}

/// A stop asked after the second of four frames fails the run with `Stopped` once that frame was handed over:
/// two frames reached the sink, none after.
#[test]
fn stopped_animation_frames_fail_after_the_frames_handed_over() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small("stray-sweep");
    let mut handed = Vec::new();
    let mut progress = |_: &str, f: f32| f < 0.5;
    let result = hairlab::animation::render_frames_on(
        &gpu,
        &mut s,
        &[0, 1, 2, 3],
        &mut |_| {},
        &mut progress,
        &mut |k, _| {
            handed.push(k);
            Ok(())
        },
    );
    let e = result.expect_err("stopped");
    assert!(e.is::<Stopped>(), "{e:#}");
    assert_eq!(handed, [0, 1]);
}

/// The Bench window's sweep is a job in the job bar. Held at its first step by a test gate: the bar's Cancel drops
/// it at once (no result, "bench cancelled"); a second run stopped with the bar's Stop ends at its next step,
/// before any configuration, saying so, and leaves no result either.
#[test]
fn the_bench_window_runs_a_job_that_cancel_drops_and_stop_ends() {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;
    use hairlab::app::HairlabApp;
    if Gpu::for_tests().is_none() {
        return;
    }
    let settings = small("default");
    let mut harness = crate::common::snapshot_harness(settings, [1200.0, 900.0]);
    harness.get_by_label("Bench").click();
    harness.run();
    let gate = harness.state_mut().hold_jobs();
    let says = |harness: &Harness<'_, HairlabApp>, what: &str| {
        assert!(
            harness
                .state()
                .message()
                .is_some_and(|(m, err)| !err && m.contains(what)),
            "{what}: {:?}",
            harness.state().message()
        );
    };

    harness.get_by_label("Run bench").click();
    harness.step();
    assert!(harness.state().bench_running());
    let jobs: Vec<&str> = harness.state().jobs().iter().map(|j| j.name).collect();
    assert_eq!(jobs, ["bench"], "the sweep in the job bar");
    harness.step();
    harness.get_by_label("Cancel").click();
    harness.step();
    harness.step();
    assert!(!harness.state().bench_running());
    assert!(harness.state().bench_result().is_none());
    says(&harness, "bench cancelled");

    harness.get_by_label("Run bench").click();
    harness.step();
    harness.step();
    harness.get_by_label("Stop").click();
    harness.step();
    gate.open();
    let start = std::time::Instant::now();
    while harness.state().bench_running() {
        assert!(start.elapsed().as_secs() < 120, "the stopped bench did not end");
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    assert!(harness.state().bench_result().is_none());
    says(&harness, "bench stopped before any configuration finished");
}
