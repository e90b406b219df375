//! `hairlab render`, `compare` and `soak`: images of the requested size, fur and its Table 1, bad presets and
//! outputs refused before any work, the image metrics and the FLIP map, memory growth over cycles.

use crate::common::cli::{assert_fails, hairlab, stderr};
use std::path::Path;

#[test]
fn render_rejects_bad_presets_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let o = dir.path().join("shot.png");
    let out_s = out.to_str().unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", "no-such-preset", "--out", out_s]),
        &["no-such-preset"],
    );
    assert_fails(
        &hairlab(&["render", "--set", "render.hair_alpha=5", "--out", out_s]),
        &["hair_alpha"],
    );
    assert_fails(
        &hairlab(&["render", "--set", "method.name=magic", "--out", out_s]),
        &["magic"],
    );
    let preset = dir.path().join("broken.toml");
    std::fs::write(&preset, "[render]\nmap_resolution = \"big\"\n").unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", preset.to_str().unwrap(), "--out", out_s]),
        &["broken.toml"],
    );
    let missing = dir.path().join("scene.toml");
    std::fs::write(&missing, "[scene]\nfile = \"missing.hair\"\n").unwrap();
    assert_fails(
        &hairlab(&["render", "--preset", missing.to_str().unwrap(), "--out", out_s]),
        &["missing.hair"],
    );
    assert!(!Path::new(&o).exists(), "no output on failure");
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shot.png");
    let o = hairlab(&[
        "render",
        "--set",
        "scene.generator.strands=300",
        "--set",
        "scene.generator.segments=8",
        "--width",
        "96",
        "--height",
        "64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "temporary files left behind: {leftovers:?}");
}

/// The output path is checked before any work, and the image size flags are named as the user typed them.
#[test]
fn outputs_are_checked_first_and_size_flags_name_themselves() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nowhere/shot.png");
    let o = hairlab(&["render", "--out", missing.to_str().unwrap()]);
    assert_fails(&o, &["nowhere/shot.png: the folder", "does not exist"]);
    let txt = dir.path().join("a.txt");
    let o = hairlab(&["gen", "head", "--out", txt.to_str().unwrap()]);
    assert_fails(&o, &["a.txt: the output must be a .hair file"]);
    assert!(!txt.exists());
    let png = dir.path().join("shot.png");
    let o = hairlab(&["render", "--width", "0", "--out", png.to_str().unwrap()]);
    assert_fails(
        &o,
        &["--width/--height", "render.width/height must be in 1..=8192"],
    );
    let o = hairlab(&[
        "render",
        "--width",
        "64",
        "--set",
        "render=1",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        !stderr(&o).contains("render.width=64"),
        "blames an override the user never typed: {}",
        stderr(&o)
    );
    assert!(!png.exists());
}

/// A headless GPU run with no session (no `XDG_RUNTIME_DIR`) prints no driver noise about it.
#[test]
fn headless_runs_print_nothing_about_a_missing_session() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("small.png");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args([
            "render",
            "--set",
            "scene.generator.strands=50",
            "--width",
            "32",
            "--height",
            "24",
        ])
        .args(["--out", out.to_str().unwrap()])
        .env("RUST_LOG", "warn")
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .expect("run hairlab");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("XDG_RUNTIME_DIR"), "{}", stderr(&o));
}

/// `hairlab soak`, short: four cycles of every method on a tiny scene, one memory sample per cycle, and the growth
/// from the first cycle's end to the last's within the 5 % it allows.
#[test]
fn soak_samples_memory_per_cycle_and_reports_its_growth() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let methods = hairlab::methods::registry::all().len();
    let frames = (4 * 2 * methods).to_string();
    let mut args = vec!["soak", "--frames", &frames, "--switch-every", "2"];
    for s in [
        "scene.generator.strands=50",
        "render.map_resolution=64",
        "render.width=32",
        "render.height=24",
    ] {
        args.extend(["--set", s]);
    }
    let o = hairlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let samples: Vec<u64> = out
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    let cycle = 2 * methods as u64;
    assert_eq!(samples, [cycle, 2 * cycle, 3 * cycle, 4 * cycle], "{out}");
    assert!(
        out.contains("growth from the first cycle's end to the last's: resident"),
        "{out}"
    );
    let o = hairlab(&["soak", "--frames", "10", "--switch-every", "2"]);
    assert_fails(&o, &["--frames 10 holds fewer than two cycles"]);
}

/// `render --preset fur-cylinder` renders the fur in each mode and prints the paper's Table 1 rows; a bad fur
/// value is refused by its key before anything is written, and so is a technique that cannot show fur.
#[test]
fn render_draws_fur_and_prints_table_1() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fur.png");
    let out_s = out.to_str().unwrap();
    for mode in ["implicit", "explicit", "hybrid"] {
        let o = hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            &format!("fur.mode={mode}"),
            "--set",
            "fur.max_steps=48",
            "--set",
            "fur.layers=4",
            "--set",
            "fur.max_level=2",
            "--set",
            "scene.generator.strands=200",
            "--width",
            "96",
            "--height",
            "72",
            "--out",
            out_s,
        ]);
        assert!(o.status.success(), "{mode}: {}", stderr(&o));
        let err = stderr(&o);
        for row in hairlab::fur::table::TIME_ROWS
            .iter()
            .chain(&hairlab::fur::table::MEMORY_ROWS)
        {
            assert!(err.contains(row), "{mode}: no '{row}' in\n{err}");
        }
        assert!(
            err.contains(&format!("fur ({mode}, virtual blending): 3584 triangles")),
            "{err}"
        );
        assert_eq!(image::open(&out).unwrap().width(), 96);
    }
    std::fs::remove_file(&out).unwrap();
    assert_fails(
        &hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            "fur.layers=0",
            "--out",
            out_s,
        ]),
        &["invalid fur.layers = 0: must be in 1..=256"],
    );
    assert!(!out.exists(), "no output on failure");
    // Fur is shown by its own technique, never swapped in: another one is refused, naming the fur's.
    let strands_only = hairlab::render::transparency::registry::default_technique().name();
    let fur_technique = hairlab::render::transparency::registry::fur().name();
    assert_fails(
        &hairlab(&[
            "render",
            "--preset",
            "fur-cylinder",
            "--set",
            &format!("transparency.name={strands_only}"),
            "--set",
            "fur.layers=4",
            "--set",
            "fur.max_level=2",
            "--width",
            "96",
            "--height",
            "72",
            "--out",
            out_s,
        ]),
        &[
            "the scene has fur",
            format!("'{strands_only}' cannot show it; choose '{fur_technique}'").as_str(),
        ],
    );
    assert!(!out.exists(), "no output on failure");
}

/// `compare`'s printed value of `name`.
fn printed(o: &std::process::Output, name: &str) -> f64 {
    let stdout = String::from_utf8_lossy(&o.stdout);
    stdout
        .lines()
        .find_map(|l| {
            let mut words = l.split_whitespace();
            (words.next() == Some(name)).then(|| words.next().unwrap().parse().unwrap())
        })
        .unwrap_or_else(|| panic!("no {name} in {stdout}"))
}

fn flip_fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/flip")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

#[test]
fn compare_prints_every_image_metric_and_writes_the_flip_map() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("flip.png");
    let (a, b, mask) = (
        flip_fixture("strands_a.png"),
        flip_fixture("strands_b.png"),
        flip_fixture("strands_mask.png"),
    );
    let o = hairlab(&[
        "compare",
        &a,
        &b,
        "--mask",
        &mask,
        "--flip-map",
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // NVIDIA's and scikit-image's values for this pair and mask (`tests/fixtures/flip/reference.py`).
    assert!((printed(&o, "flip") - 0.187_431_14).abs() < 1e-3);
    assert!((printed(&o, "flip_hair") - 0.203_148_66).abs() < 1e-3);
    assert!((printed(&o, "flip_p99_hair") - 0.597_611_90).abs() < 1e-3);
    assert!((printed(&o, "ssim") + 0.221_951_82).abs() < 1e-5);
    for name in [
        "rmse",
        "psnr",
        "rmse_hair",
        "ssim_hair",
        "p99",
        "contrast_retention",
        "flip_p95_hair",
    ] {
        assert!(printed(&o, name).is_finite(), "{name}");
    }
    let heat = image::open(&map).unwrap();
    assert_eq!((heat.width(), heat.height()), (32, 24));
    // Without a mask every pixel is hair; an image against itself has no error.
    let o = hairlab(&["compare", &a, &a]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        (printed(&o, "flip"), printed(&o, "rmse"), printed(&o, "ssim")),
        (0.0, 0.0, 1.0)
    );
}

#[test]
fn compare_names_missing_unreadable_and_mismatched_files() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("flip.png");
    let map_arg = map.to_str().unwrap();
    let a = flip_fixture("strands_a.png");
    let missing = dir.path().join("missing.png");
    let o = hairlab(&["compare", &a, missing.to_str().unwrap(), "--flip-map", map_arg]);
    assert_fails(&o, &["missing.png", "cannot read"]);
    let garbage = dir.path().join("garbage.png");
    std::fs::write(&garbage, b"not a png").unwrap();
    let o = hairlab(&["compare", garbage.to_str().unwrap(), &a, "--flip-map", map_arg]);
    assert_fails(&o, &["garbage.png", "not a readable image"]);
    let small = dir.path().join("small.png");
    image::RgbaImage::new(8, 8).save(&small).unwrap();
    let o = hairlab(&["compare", &a, small.to_str().unwrap(), "--flip-map", map_arg]);
    assert_fails(&o, &["small.png", "8x8", "strands_a.png", "32x24", "same size"]);
    let o = hairlab(&["compare", &a, &a, "--mask", small.to_str().unwrap()]);
    assert_fails(&o, &["small.png", "8x8", "same size"]);
    assert!(!map.exists(), "no heat map after a failure");
}
