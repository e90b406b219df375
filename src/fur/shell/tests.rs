//! The shell by hand: a flat triangle extruded, levels from area, a tube that shrinks, errors naming face or key.

use super::*;
use crate::scene::Mesh;

fn fur_mesh(positions: &[[f32; 3]], indices: &[u32]) -> FurMesh {
    let m = Mesh {
        positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
        normals: vec![Vec3::Y; positions.len()],
        indices: indices.to_vec(),
        color: Vec3::ONE,
    };
    FurMesh::build("test", &m).unwrap()
}

fn flat_triangle() -> FurMesh {
    fur_mesh(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2])
}

#[test]
fn a_flat_triangle_extrudes_straight_up() {
    let s = Shell::build(
        flat_triangle(),
        &ShellParams {
            height: 0.5,
            ..ShellParams::default()
        },
    )
    .unwrap();
    assert_eq!(
        s.tops,
        vec![
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(1.0, 0.0, 0.5),
            Vec3::new(0.0, 1.0, 0.5)
        ]
    );
    // A point at height 0.2 above (0.25, 0.25): w = 0.4, λ = (0.5, 0.25, 0.25).
    let at = s.locate(Vec3::new(0.25, 0.25, 0.2), 0);
    assert!((at.w - 0.4).abs() < 1e-6, "{at:?}");
    for (l, e) in at.lambda.iter().zip([0.5, 0.25, 0.25]) {
        assert!((l - e).abs() < 1e-6, "{at:?}");
    }
    assert_eq!(
        s.report,
        ShellReport {
            min_height_ratio: 1.0,
            ..ShellReport::default()
        }
    );
}

#[test]
fn levels_follow_area_by_hand() {
    // Area 0.5, cell edge 0.25: equilateral cell area √3/64 = 0.02706; 0.5/16 = 0.03125 > it ≥ 0.5/64.
    let p = ShellParams {
        height: 1.0,
        layers: 4,
        cell: Some(0.25),
        levels: Levels::Dynamic { max: 8 },
    };
    let s = Shell::build(flat_triangle(), &p).unwrap();
    assert_eq!(s.levels, vec![3]);
    assert_eq!(s.sub_elements, 4 * 64);
    // Capped by max, and uniform as asked.
    let s = Shell::build(
        flat_triangle(),
        &ShellParams {
            levels: Levels::Dynamic { max: 2 },
            ..p
        },
    )
    .unwrap();
    assert_eq!(s.levels, vec![2]);
    let s = Shell::build(
        flat_triangle(),
        &ShellParams {
            levels: Levels::Uniform(5),
            ..p
        },
    )
    .unwrap();
    assert_eq!(s.sub_elements, 4 * 1024);
}

#[test]
fn the_inside_of_a_tube_thicker_than_its_radius_shrinks_and_reports() {
    // Wound inward, a tube of radius 1 extrudes towards its axis: every prism inverts past h = 1. Shrinking
    // ×0.8 a pass: 1.5 → 1.2 (still inverted) → 0.96 (valid), so two passes and 0.64 × h_0 everywhere.
    let mut tube = crate::scene::fur_shapes::cylinder(1.0, 2.0, 16, 4);
    for t in tube.indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    // The inside of a tube: its normals point inward too.
    for n in &mut tube.normals {
        *n = -*n;
    }
    let m = FurMesh::build("tube", &tube).unwrap();
    let thin = Shell::build(
        m.clone(),
        &ShellParams {
            height: 0.5,
            ..ShellParams::default()
        },
    )
    .unwrap();
    assert_eq!(thin.report.shrunk_vertices, 0);
    let s = Shell::build(
        m,
        &ShellParams {
            height: 1.5,
            ..ShellParams::default()
        },
    )
    .unwrap();
    assert_eq!(s.report.inverted_prisms, 16 * 4 * 2);
    assert_eq!(s.report.shrunk_vertices, 16 * 5);
    assert_eq!(s.report.shrink_passes, 2);
    assert!((s.report.min_height_ratio - 0.64).abs() < 1e-6, "{:?}", s.report);
    assert!(s.report.warning("tube").unwrap().contains("128 prisms inverted"));
    for f in 0..s.mesh.faces.len() {
        let (b, t) = s.prism(f);
        let d = std::array::from_fn(|k| (t[k] - b[k]).as_dvec3());
        assert!(prism_valid(b.map(|v| v.as_dvec3()), d), "face {f}");
    }
}

#[test]
fn a_normal_behind_its_face_is_an_error_naming_the_face() {
    // A spike: three faces around a tall apex plus one nearly flat face folded back over them, so the
    // area-weighted normal at the shared vertex points behind the small face.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.3, 0.3, -0.01],
    ];
    let m = fur_mesh(&p, &[0, 1, 2, 1, 0, 3]);
    let e = Shell::build(m, &ShellParams::default()).unwrap_err();
    assert!(
        matches!(
            e,
            ShellError::NormalBehindFace { .. } | ShellError::Inverted { .. }
        ),
        "{e}"
    );
    assert!(e.to_string().starts_with("fur shell on 'test': face "), "{e}");
}

#[test]
fn bad_parameters_name_their_key() {
    let build = |p: ShellParams| Shell::build(flat_triangle(), &p).unwrap_err().to_string();
    let d = ShellParams::default();
    assert_eq!(
        build(ShellParams { height: -1.0, ..d }),
        "fur shell on 'test': invalid fur.shell_height = -1: must be finite and > 0"
    );
    assert!(build(ShellParams { layers: 0, ..d }).contains("fur.layers = 0"));
    assert!(build(ShellParams { layers: 257, ..d }).contains("fur.layers = 257"));
    assert!(
        build(ShellParams {
            levels: Levels::Uniform(11),
            ..d
        })
        .contains("fur.level = 11")
    );
    assert!(
        build(ShellParams {
            cell: Some(f32::NAN),
            ..d
        })
        .contains("fur.cell_size = NaN")
    );
    // 256 layers × 4^10 = 2^28 per face on 32 faces is 2^33, over 2^32 − 1.
    let m = FurMesh::build("test", &crate::scene::fur_shapes::cylinder(1.0, 1.0, 16, 1)).unwrap();
    let e = Shell::build(
        m,
        &ShellParams {
            layers: 256,
            levels: Levels::Uniform(10),
            ..d
        },
    )
    .unwrap_err();
    assert_eq!(
        e,
        ShellError::TooManySubElements {
            mesh: "test".into(),
            total: 1 << 33,
            limit: u64::from(u32::MAX)
        }
    );
}

#[test]
fn split_global_inverts_eq_3() {
    let m = fur_mesh(
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [3.0, 3.0, 0.0]],
        &[0, 1, 2, 2, 1, 3],
    );
    let s = Shell::build(
        m,
        &ShellParams {
            height: 0.1,
            layers: 3,
            cell: Some(0.3),
            ..ShellParams::default()
        },
    )
    .unwrap();
    assert_ne!(s.levels[0], s.levels[1]);
    for g in 0..s.sub_elements {
        let (f, l, i) = s.split_global(g);
        assert_eq!(index::global_index(s.offsets[f], l, s.levels[f], i), g);
        assert!(l < 3 && i < 1 << (2 * s.levels[f]));
    }
}
