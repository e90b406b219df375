//! Helpers shared by the integration tests: small scenes and image comparison with a tolerance.

#![allow(dead_code)]

use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::visibility::{Fragment, metrics};
use std::path::{Path, PathBuf};

/// Environment variable that rewrites snapshot images instead of comparing.
pub const UPDATE_ENV: &str = "HAIRLAB_UPDATE_SNAPSHOTS";

/// The default preset shrunk to a test-sized scene and image.
pub fn small_settings(width: u32, height: u32) -> Settings {
    Settings::load_preset(
        "default",
        &[
            "scene.generator.strands=600".into(),
            "scene.generator.segments=12".into(),
            format!("render.width={width}"),
            format!("render.height={height}"),
            "render.map_resolution=256".into(),
        ],
    )
    .expect("default preset")
}

pub fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots")
}

/// Compares `img` with `tests/snapshots/<name>.png`: fails when more than `max_bad_fraction` of the pixels differ
/// by more than `channel_tolerance` in any channel. On failure writes `<name>.new.png` and `<name>.diff.png`
/// under `target/snapshot-failures/`. With `HAIRLAB_UPDATE_SNAPSHOTS=1` it rewrites the snapshot instead.
pub fn compare_snapshot(name: &str, img: &image::RgbaImage, channel_tolerance: u8, max_bad_fraction: f64) {
    let path = snapshot_dir().join(format!("{name}.png"));
    if std::env::var(UPDATE_ENV).is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        eprintln!("snapshot {} rewritten", path.display());
        return;
    }
    let expected = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with {UPDATE_ENV}=1 to create it", path.display()))
        .to_rgba8();
    assert_eq!(
        expected.dimensions(),
        img.dimensions(),
        "{name}: size differs from the snapshot"
    );
    let mut diff = image::RgbaImage::new(img.width(), img.height());
    let mut bad = 0usize;
    for (x, y, p) in img.enumerate_pixels() {
        let q = expected.get_pixel(x, y);
        let d =
            p.0.iter()
                .zip(q.0.iter())
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap_or(0);
        if d > channel_tolerance {
            bad += 1;
        }
        diff.put_pixel(x, y, image::Rgba([d.saturating_mul(4), 0, 0, 255]));
    }
    let fraction = bad as f64 / (img.width() * img.height()) as f64;
    if fraction > max_bad_fraction {
        let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/snapshot-failures");
        std::fs::create_dir_all(&out).unwrap();
        img.save(out.join(format!("{name}.new.png"))).unwrap();
        diff.save(out.join(format!("{name}.diff.png"))).unwrap();
        panic!(
            "{name}: {:.3}% of pixels differ by more than {channel_tolerance} (allowed {:.3}%); see {}",
            fraction * 100.0,
            max_bad_fraction * 100.0,
            out.display()
        );
    }
}

/// Renders `method` with `params` on the small test scene and returns the largest |V_gpu - V_cpu| over all
/// samples, with the sample count.
pub fn max_gpu_cpu_difference(
    gpu: &Gpu,
    method: &str,
    params: &[(&str, f32)],
    resolution: u32,
) -> (f32, usize) {
    let mut s: Settings = small_settings(8, 8);
    s.scene.generator.strands = 300;
    s.scene.generator.segments = 10;
    s.render.map_resolution = resolution;
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let values: ParamValues = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let frame = |m: &'static str| FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method: registry::find(m).unwrap(),
        method_params: if m == "reference" {
            &s.method.params
        } else {
            &values
        },
        width: 8,
        height: 8,
    };
    r.render_light(&frame("reference")).unwrap();
    let lists = r.reference_lists().unwrap();
    let m = registry::find(method).unwrap();
    r.render_light(&frame(m.name())).unwrap();
    let model = m
        .model(&values, s.render.hair_alpha)
        .expect("method has a CPU model");
    let mut samples = Vec::new();
    let mut expected = Vec::new();
    for (t, list) in lists.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        let frags: Vec<Fragment> = list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
        let zs = metrics::sample_depths(&frags, 16);
        let (x, y) = ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
        expected.extend(model.visibility_curve(&frags, &zs));
        samples.extend(zs.iter().map(|&z| [x, y, z]));
    }
    assert!(
        expected.iter().any(|v| *v < 0.5) && expected.iter().any(|v| *v > 0.9),
        "{method}: the test scene should hold both lit and deeply shadowed samples"
    );
    let got = r.evaluate(m, &samples).unwrap();
    let worst = got
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(
        got.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
        "{method}: V outside [0,1]"
    );
    (worst, samples.len())
}
