//! Guard hairs on the paper's fur base meshes (spec FR-GUARD, B.3 #14; Andersen et al. 2016 §3.1): the
//! `fur-cylinder` and `fur-hat` generator kinds, counts, taper and tip transparency per point by hand, roots
//! on the mesh surface, determinism, and bad values refused naming the key.

use crate::common::cli::{assert_fails, hairlab, stderr};
use glam::Vec3;
use hairlab::scene::fur_shapes as shapes;
use hairlab::scene::generate::{GenError, GenKind, GenParams, HairStyle, generate};
use hairlab::scene::hair::read_hair_file;
use hairlab::scene::style as guard;
use hairlab::scene::{Mesh, Strands};

fn fur(kind: GenKind) -> GenParams {
    GenParams {
        kind,
        style: HairStyle::Straight,
        strands: 200,
        segments: 4,
        length: 0.03,
        clumps: 0,
        floor: false,
        ..GenParams::default()
    }
}

/// Distance from `p` to the triangle `abc` (Ericson, Real-Time Collision Detection §5.1.5).
fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return p.distance(a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return p.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return p.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    p.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

fn distance_to_mesh(p: Vec3, m: &Mesh) -> f32 {
    m.indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            point_triangle_distance(p, a, b, c)
        })
        .fold(f32::INFINITY, f32::min)
}

fn roots(s: &Strands) -> Vec<Vec3> {
    s.ranges().map(|(start, _)| s.points[start]).collect()
}

#[test]
fn fur_kinds_are_the_paper_meshes_with_guard_hairs_grown_on_them() {
    for (kind, mesh, triangles) in [
        (GenKind::FurCylinder, shapes::fur_cylinder(), 3584),
        (GenKind::FurHat, shapes::fur_hat(), 5632),
    ] {
        let p = fur(kind);
        let scene = generate(&p).unwrap();
        assert_eq!(scene.meshes.len(), 1, "{kind:?}: the base mesh only (no floor)");
        assert_eq!(scene.meshes[0], mesh, "{kind:?}");
        assert_eq!(scene.meshes[0].indices.len() / 3, triangles, "{kind:?}");
        let s = &scene.strands;
        assert_eq!(s.strand_count(), 200);
        assert_eq!(s.point_count(), 200 * 5);
        assert_eq!(s.segment_count(), 200 * 4);
        // Neutral taper and tip transparency: no per-point arrays, as for every other kind.
        assert_eq!((s.thickness.is_some(), s.alpha.is_some()), (false, false));
        assert_eq!(
            generate(&GenParams {
                floor: true,
                ..p.clone()
            })
            .unwrap()
            .meshes
            .len(),
            2,
            "{kind:?}: the floor is added after the base mesh"
        );
        // guard_hairs on the same mesh is the kind's hair.
        assert_eq!(
            &hairlab::scene::generate::guard_hairs(&p, &mesh).unwrap(),
            s,
            "{kind:?}"
        );
    }
}

#[test]
fn guard_roots_lie_on_the_mesh_and_strands_start_along_its_normal() {
    for kind in [GenKind::FurCylinder, GenKind::FurHat] {
        let scene = generate(&fur(kind)).unwrap();
        let mesh = &scene.meshes[0];
        let s = &scene.strands;
        let worst = roots(s)
            .iter()
            .map(|&r| distance_to_mesh(r, mesh))
            .fold(0.0f32, f32::max);
        println!("{kind:?}: largest root distance to the mesh {worst:e}");
        assert!(worst < 1e-6, "{kind:?}: {worst}");
        // Straight strands: the first step is the root's interpolated normal, which points out of the
        // surface. On the cylinder that is radial.
        if kind == GenKind::FurCylinder {
            for (start, _) in s.ranges() {
                let (r, q) = (s.points[start], s.points[start + 1]);
                let radial = Vec3::new(r.x, 0.0, r.z).normalize();
                let step = (q - r).normalize();
                assert!(step.dot(radial) > 0.99, "root {r}: first step {step}");
                assert!((q.distance(r) - 0.03 / 4.0).abs() < 1e-6);
            }
        }
        // Roots spread over the whole surface: on the cylinder over its full height, in quarters.
        if kind == GenKind::FurCylinder {
            let mut quarters = [0; 4];
            for r in roots(s) {
                quarters[((r.y / 0.3 * 4.0) as usize).min(3)] += 1;
            }
            assert!(quarters.iter().all(|&q| q > 30), "{quarters:?}");
        }
    }
}

#[test]
fn taper_and_tip_transparency_per_point_by_hand() {
    let p = GenParams {
        taper: 0.25,
        tip_transparency: 2.0,
        ..fur(GenKind::FurCylinder)
    };
    let s = generate(&p).unwrap().strands;
    let thickness = s.thickness.as_ref().unwrap();
    let alpha = s.alpha.as_ref().unwrap();
    assert_eq!((thickness.len(), alpha.len()), (1000, 1000));
    // s = j/4: thickness 1 − 0.75 s, alpha exp(−2 s).
    let t_hand = [1.0, 0.8125, 0.625, 0.4375, 0.25];
    let a_hand = [1.0, 0.606_530_66, 0.367_879_44, 0.223_130_16, 0.135_335_28];
    for (k, (t, a)) in thickness.chunks_exact(5).zip(alpha.chunks_exact(5)).enumerate() {
        for j in 0..5 {
            assert!((t[j] - t_hand[j]).abs() < 1e-6, "strand {k} point {j}: {}", t[j]);
            assert!((a[j] - a_hand[j]).abs() < 1e-6, "strand {k} point {j}: {}", a[j]);
        }
    }
    // The style does not move the strands.
    assert_eq!(
        s.points,
        generate(&fur(GenKind::FurCylinder)).unwrap().strands.points
    );
    // Any kind takes it (here a patch), and only the array that is not neutral is written.
    let patch = generate(&GenParams {
        kind: GenKind::Patch,
        taper: 0.5,
        ..fur(GenKind::Patch)
    })
    .unwrap()
    .strands;
    assert_eq!(patch.alpha, None);
    let t = patch.thickness.unwrap();
    assert_eq!((t[0], t[2], t[4]), (1.0, 0.75, 0.5));
}

#[test]
fn style_multiplies_existing_arrays_and_a_single_point_strand_is_all_root() {
    let mut s = Strands {
        points: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
        counts: vec![3, 1],
        thickness: Some(vec![2.0; 4]),
        alpha: Some(vec![0.5; 4]),
        color: None,
    };
    guard::style(&mut s, 0.5, 1.0);
    assert_eq!(s.thickness.unwrap(), vec![2.0, 1.5, 1.0, 2.0]);
    let a = s.alpha.unwrap();
    let hand = [0.5, 0.5 * 0.606_530_66, 0.5 * 0.367_879_44, 0.5];
    for (x, h) in a.iter().zip(hand) {
        assert!((x - h).abs() < 1e-6, "{a:?}");
    }
}

#[test]
fn guard_hairs_are_deterministic_from_the_seed() {
    for kind in [GenKind::FurCylinder, GenKind::FurHat] {
        let p = GenParams {
            style: HairStyle::Wavy,
            clumps: 20,
            taper: 0.3,
            tip_transparency: 1.5,
            ..fur(kind)
        };
        let a = generate(&p).unwrap();
        assert_eq!(a, generate(&p).unwrap(), "{kind:?}");
        let bits = |s: &Strands| {
            s.points
                .iter()
                .map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&a.strands), bits(&generate(&p).unwrap().strands));
        let other = generate(&GenParams { seed: 2, ..p.clone() }).unwrap();
        assert_ne!(
            roots(&a.strands),
            roots(&other.strands),
            "{kind:?}: another seed, other roots"
        );
    }
}

#[test]
fn bad_taper_and_tip_transparency_are_refused_naming_the_key() {
    let d = fur(GenKind::FurHat);
    let cases = [
        (
            GenParams {
                taper: -0.1,
                ..d.clone()
            },
            "taper",
        ),
        (
            GenParams {
                taper: 1.5,
                ..d.clone()
            },
            "taper",
        ),
        (
            GenParams {
                taper: f32::NAN,
                ..d.clone()
            },
            "taper",
        ),
        (
            GenParams {
                tip_transparency: -1.0,
                ..d.clone()
            },
            "tip_transparency",
        ),
        (
            GenParams {
                tip_transparency: f32::INFINITY,
                ..d.clone()
            },
            "tip_transparency",
        ),
        (
            GenParams {
                tip_transparency: f32::NAN,
                ..d.clone()
            },
            "tip_transparency",
        ),
    ];
    for (p, name) in cases {
        match generate(&p) {
            Err(e @ GenError::Param { param, .. }) => {
                assert_eq!(param, name);
                assert!(e.to_string().contains(name), "{e}");
            }
            other => panic!("{name}: expected a parameter error, got {other:?}"),
        }
        assert!(matches!(
            hairlab::scene::generate::guard_hairs(&p, &shapes::fur_cylinder()),
            Err(GenError::Param { .. })
        ));
    }
    // The edges of the ranges are fine.
    for p in [
        GenParams {
            taper: 0.0,
            ..d.clone()
        },
        GenParams {
            taper: 1.0,
            tip_transparency: 0.0,
            ..d.clone()
        },
        GenParams {
            tip_transparency: 60.0,
            ..d.clone()
        },
    ] {
        generate(&p).unwrap();
    }
    // A mesh with no area grows nothing, and says so.
    let flat = Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        normals: vec![Vec3::Y; 3],
        indices: vec![0, 1, 2],
        color: Vec3::ONE,
    };
    let e = hairlab::scene::generate::guard_hairs(&d, &flat).unwrap_err();
    assert_eq!(e, GenError::NoMeshArea);
    assert!(e.to_string().contains("no triangles of non-zero area"), "{e}");
}

#[test]
fn hairlab_gen_writes_fur_kinds_and_refuses_a_bad_taper() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("x.hair");
    let f = f.to_str().unwrap();
    let o = hairlab(&[
        "gen",
        "fur-cylinder",
        "--strands",
        "30",
        "--segments",
        "3",
        "--set",
        "taper=0.5",
        "--set",
        "tip_transparency=1",
        "--out",
        f,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let written = read_hair_file(std::path::Path::new(f))
        .unwrap()
        .to_strands()
        .unwrap();
    let expected = generate(&GenParams {
        kind: GenKind::FurCylinder,
        strands: 30,
        segments: 3,
        taper: 0.5,
        tip_transparency: 1.0,
        ..GenParams::default()
    })
    .unwrap()
    .strands;
    assert_eq!(
        (&written.points, &written.counts, &written.thickness),
        (&expected.points, &expected.counts, &expected.thickness)
    );
    assert_eq!(written.thickness.as_ref().unwrap()[3], 0.5);
    // The file stores transparency = 1 − alpha: equal to f32 rounding.
    let (a, b) = (written.alpha.unwrap(), expected.alpha.unwrap());
    assert_eq!(a.len(), b.len());
    assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-6));
    let bad = dir.path().join("bad.hair");
    let o = hairlab(&[
        "gen",
        "fur-hat",
        "--set",
        "taper=2",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_fails(&o, &["taper", "[0, 1]"]);
    assert!(!bad.exists(), "no output file on error");
}
