//! Every preset file in `presets/` loads, validates and builds its scene; the scalp-mesh preset grows hair on
//! the glTF mesh in `assets/`.

use hairlab::settings::Settings;
use std::path::Path;

#[test]
fn every_preset_file_builds_its_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let s = Settings::load_preset(path.to_str().unwrap(), &[]).unwrap_or_else(|e| panic!("{e:#}"));
        let scene = s
            .scene
            .build()
            .unwrap_or_else(|e| panic!("{}: {e:#}", path.display()));
        assert!(scene.strands.segment_count() > 0, "{}: no hair", path.display());
        count += 1;
    }
    assert!(count >= 7, "only {count} presets found in {}", dir.display());
}

#[test]
fn scalp_mesh_preset_grows_hair_on_the_asset() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/scalp-mesh.toml");
    let s = Settings::load_preset(path.to_str().unwrap(), &[]).unwrap();
    let scene = s.scene.build().unwrap();
    assert_eq!(scene.strands.strand_count(), 2000);
    // The asset: an upper half ellipsoid of 24 x 8 quads (384 triangles), radii 0.085 x 0.1 x 0.095.
    assert_eq!(scene.meshes[0].indices.len() / 3, 384);
    for (start, _) in scene.strands.ranges() {
        let root = scene.strands.points[start];
        let e = (root / glam::Vec3::new(0.085, 0.1, 0.095)).length();
        // Roots lie on the faceted surface: between the inscribed and the circumscribed ellipsoid.
        assert!(
            root.y >= -1e-4 && (0.95..=1.0001).contains(&e),
            "root {root} off the scalp ({e})"
        );
    }
}

/// The fur presets grow fur on the paper's meshes: Table 1's triangle counts, a valid shell, and a stored volume
/// (16 B a sub-element) inside lavapipe's 128 MiB storage binding.
#[test]
fn fur_presets_build_their_shells_on_the_papers_meshes() {
    use hairlab::fur::settings::{FurMode, FurScene};
    for (name, triangles) in [("fur-cylinder", 3584), ("fur-hat", 5632)] {
        let s = Settings::load_preset(name, &[]).unwrap();
        assert_eq!(s.fur.mode, FurMode::Hybrid, "{name}");
        let scene = s.scene.build().unwrap();
        let fur = FurScene::build(&scene, &s.fur).unwrap().expect("fur is on");
        assert_eq!(fur.shell.mesh.faces.len(), triangles, "{name}");
        let bytes = fur.shell.sub_elements * 16;
        eprintln!(
            "{name}: {} sub-elements ({:.1} MiB stored), levels {:?}..{:?}, {} guard hairs, warnings {:?}",
            fur.shell.sub_elements,
            bytes as f64 / (1 << 20) as f64,
            fur.shell.levels.iter().min(),
            fur.shell.levels.iter().max(),
            scene.strands.strand_count(),
            fur.warnings
        );
        assert!(bytes <= 128 << 20, "{name}: {bytes} bytes of volume");
    }
}

/// Fur grown on the glTF scalp (wound inward in the file, its normals outward) extrudes its shell outside the
/// scalp: every oriented face points away from the mesh's centre.
#[test]
fn fur_on_the_scalp_asset_grows_outside() {
    use hairlab::fur::settings::FurScene;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/scalp-mesh.toml");
    let s = Settings::load_preset(path.to_str().unwrap(), &["fur.mode=hybrid".into()]).unwrap();
    let scene = s.scene.build().unwrap();
    let fur = FurScene::build(&scene, &s.fur).unwrap().expect("fur is on");
    let m = &fur.shell.mesh;
    let centre = m.positions.iter().sum::<glam::Vec3>() / m.positions.len() as f32;
    let inward: Vec<usize> = (0..m.faces.len())
        .filter(|&f| {
            let c = m.faces[f]
                .iter()
                .map(|&v| m.positions[v as usize])
                .sum::<glam::Vec3>()
                / 3.0;
            m.face_normal(f).dot(c - centre) <= 0.0
        })
        .collect();
    assert!(
        inward.is_empty(),
        "{} of {} faces point inward: {inward:?}",
        inward.len(),
        m.faces.len()
    );
}
