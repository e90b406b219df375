//! Helpers shared by the integration tests: small scenes and image comparison with a tolerance.

#![allow(dead_code)]

use hairlab::settings::Settings;
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
