//! Procedural hair: determinism, counts, geometry of heads and patches, clumping, styles, validation.

use glam::Vec3;
use hairlab::scene::generate::{
    GenError, GenKind, GenParams, HEAD_RADII, HairStyle, MAX_POINTS, generate, generate_on_scalp,
};
use hairlab::scene::{Mesh, Scene, Strands};

fn small(kind: GenKind, style: HairStyle) -> GenParams {
    GenParams {
        kind,
        style,
        strands: 300,
        segments: 12,
        clumps: 0,
        floor: false,
        ..GenParams::default()
    }
}

fn strands_of(s: &Strands) -> Vec<&[Vec3]> {
    s.ranges().map(|(start, n)| &s.points[start..start + n]).collect()
}

fn polyline_length(p: &[Vec3]) -> f32 {
    p.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Distance of `q` from the line through `a` along unit `dir`.
fn distance_to_line(q: Vec3, a: Vec3, dir: Vec3) -> f32 {
    (q - a).reject_from_normalized(dir).length()
}

fn bits(s: &Scene) -> Vec<u32> {
    let strands = &s.strands;
    let colors = strands.color.iter().flatten();
    let meshes = s.meshes.iter().flat_map(|m| m.positions.iter().chain(&m.normals));
    strands
        .points
        .iter()
        .chain(colors)
        .chain(meshes)
        .flat_map(|v| v.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn default_params_give_72k_segments_on_a_head() {
    let p = GenParams::default();
    assert_eq!(
        (p.kind, p.style, p.strands, p.segments, p.seed, p.floor),
        (GenKind::Head, HairStyle::Wavy, 3000, 24, 1, true)
    );
    let s = generate(&p).expect("defaults are valid");
    assert_eq!(s.strands.strand_count(), 3000);
    assert_eq!(s.strands.segment_count(), 72_000);
    assert_eq!(s.meshes.len(), 2, "head and floor");
}

#[test]
fn same_seed_is_bit_identical_and_other_seeds_differ() {
    for kind in [GenKind::Head, GenKind::Patch] {
        let p = GenParams {
            kind,
            strands: 500,
            clumps: 20,
            floor: true,
            ..GenParams::default()
        };
        let (a, b) = (generate(&p).expect("valid"), generate(&p).expect("valid"));
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.strands.counts, b.strands.counts);
        let c = generate(&GenParams { seed: 2, ..p.clone() }).expect("valid");
        let roots = |s: &Scene| strands_of(&s.strands).iter().map(|p| p[0]).collect::<Vec<_>>();
        let (ra, rc) = (roots(&a), roots(&c));
        let same_roots = ra.iter().zip(&rc).filter(|(x, y)| x == y).count();
        assert_eq!(same_roots, 0, "{kind:?}: another seed moves every root");
    }
}

#[test]
fn counts_follow_strands_density_and_segments() {
    for kind in [GenKind::Head, GenKind::Patch] {
        let p = GenParams {
            kind,
            strands: 100,
            density: 1.5,
            segments: 10,
            strand_colors: true,
            ..small(kind, HairStyle::Wavy)
        };
        let s = generate(&p).expect("valid").strands;
        assert_eq!(s.strand_count(), 150);
        assert!(s.counts.iter().all(|&c| c == 11));
        assert_eq!(s.point_count(), 150 * 11);
        assert_eq!(s.segment_count(), 1500);
        assert_eq!(s.color.as_ref().map(Vec::len), Some(1650));
        assert_eq!((s.alpha.as_ref(), s.thickness.as_ref()), (None, None));
    }
}

#[test]
fn all_points_are_finite() {
    for kind in [GenKind::Head, GenKind::Patch] {
        for style in [HairStyle::Straight, HairStyle::Wavy, HairStyle::Curly] {
            let p = GenParams {
                clumps: 30,
                floor: true,
                ..small(kind, style)
            };
            let s = generate(&p).expect("valid");
            assert!(
                s.strands.points.iter().all(|q| q.is_finite()),
                "{kind:?} {style:?}"
            );
            assert!(s.meshes.iter().flat_map(|m| &m.positions).all(|q| q.is_finite()));
        }
    }
}

#[test]
fn unclumped_strands_have_the_requested_length_and_even_spacing() {
    for kind in [GenKind::Head, GenKind::Patch] {
        for style in [HairStyle::Straight, HairStyle::Wavy, HairStyle::Curly] {
            let p = GenParams {
                length: 0.3,
                segments: 20,
                ..small(kind, style)
            };
            let s = generate(&p).expect("valid").strands;
            for strand in strands_of(&s) {
                let len = polyline_length(strand);
                assert!((len - 0.3).abs() < 0.003, "{kind:?} {style:?}: length {len}");
                for w in strand.windows(2) {
                    let seg = w[0].distance(w[1]);
                    assert!(
                        (seg - 0.015).abs() < 0.015 * 1e-3,
                        "{kind:?} {style:?}: segment {seg}"
                    );
                }
            }
        }
    }
}

#[test]
fn head_roots_lie_on_the_ellipsoid_and_off_the_face() {
    let s = generate(&GenParams {
        clumps: 40,
        ..small(GenKind::Head, HairStyle::Wavy)
    })
    .expect("valid")
    .strands;
    for strand in strands_of(&s) {
        let root = strand[0];
        let f = (root / HEAD_RADII).length();
        assert!((f - 1.0).abs() < 1e-5, "root {root} is off the surface: {f}");
        let face = root.z > 0.5 * HEAD_RADII.z && root.y < 0.0;
        assert!(!face, "root {root} is on the face");
    }
}

#[test]
fn head_hair_stays_outside_the_head() {
    let s = generate(&GenParams::default()).expect("valid").strands;
    let inside = s
        .points
        .iter()
        .filter(|q| (**q / HEAD_RADII).length() < 1.0 - 1e-5)
        .count();
    assert_eq!(inside, 0);
}

#[test]
fn head_hair_droops_with_gravity() {
    let p = GenParams {
        gravity: 1.0,
        ..small(GenKind::Head, HairStyle::Straight)
    };
    let s = generate(&p).expect("valid").strands;
    let below = strands_of(&s)
        .iter()
        .filter(|q| q[q.len() - 1].y < q[0].y)
        .count();
    assert_eq!(below, s.strand_count(), "every tip hangs below its root");
    let flat = generate(&GenParams { gravity: 0.0, ..p }).expect("valid").strands;
    let mean_tip_y =
        |s: &Strands| strands_of(s).iter().map(|q| q[q.len() - 1].y).sum::<f32>() / s.strand_count() as f32;
    assert!(
        mean_tip_y(&s) < mean_tip_y(&flat) - 0.05,
        "{} vs {}",
        mean_tip_y(&s),
        mean_tip_y(&flat)
    );
}

#[test]
fn head_mesh_is_a_closed_outward_ellipsoid() {
    let s = generate(&GenParams {
        floor: false,
        ..small(GenKind::Head, HairStyle::Wavy)
    })
    .expect("valid");
    assert_eq!(s.meshes.len(), 1);
    let head = &s.meshes[0];
    // 40 × 24 quads, less one triangle per quad in the top and bottom rings.
    assert_eq!(head.indices.len() / 3, 40 * 24 * 2 - 2 * 40);
    assert_eq!(head.normals.len(), head.positions.len());
    for q in &head.positions {
        assert!(((*q / HEAD_RADII).length() - 1.0).abs() < 1e-5);
    }
    for t in head.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| head.positions[t[k] as usize]);
        let n = (b - a).cross(c - a);
        assert!(n.length() > 0.0, "degenerate triangle");
        assert!(n.dot(a + b + c) > 0.0, "triangle winds inwards");
    }
    for (q, n) in head.positions.iter().zip(&head.normals) {
        assert!(n.dot(*q) > 0.0 && (n.length() - 1.0).abs() < 1e-5);
    }
}

#[test]
fn floor_lies_under_everything() {
    let s = generate(&GenParams {
        floor: true,
        ..small(GenKind::Head, HairStyle::Wavy)
    })
    .expect("valid");
    let floor = s.meshes.last().expect("floor");
    assert_eq!(floor.positions.len(), 4);
    let y = floor.positions[0].y;
    assert!(floor.positions.iter().all(|q| q.y == y));
    let lowest = s
        .strands
        .points
        .iter()
        .chain(&s.meshes[0].positions)
        .map(|q| q.y)
        .fold(f32::INFINITY, f32::min);
    assert!(y < lowest, "floor {y} vs lowest {lowest}");
    let [a, b, c] = [0, 1, 2].map(|k| floor.positions[floor.indices[k] as usize]);
    assert!((b - a).cross(c - a).y > 0.0, "floor faces up");

    let patch = generate(&GenParams {
        floor: true,
        ..small(GenKind::Patch, HairStyle::Wavy)
    })
    .expect("valid");
    assert_eq!(patch.meshes.len(), 1);
    assert!(patch.meshes[0].positions.iter().all(|q| q.y == 0.0));
}

#[test]
fn patch_strands_grow_up_from_a_square() {
    let p = GenParams {
        length: 0.2,
        ..small(GenKind::Patch, HairStyle::Straight)
    };
    let s = generate(&p).expect("valid").strands;
    let half = 0.2 * 0.6 / 2.0;
    for strand in strands_of(&s) {
        let root = strand[0];
        assert_eq!(root.y, 0.0);
        assert!(
            root.x.abs() <= half && root.z.abs() <= half,
            "root {root} outside the square"
        );
        assert!(
            strand.windows(2).all(|w| w[1].y > w[0].y),
            "strand does not rise monotonically"
        );
        assert!(strand[strand.len() - 1].y > 0.9 * 0.2);
    }
}

#[test]
fn full_clump_strength_gathers_tips_at_clump_centres() {
    let p = GenParams {
        clumps: 5,
        clump_strength: 1.0,
        ..small(GenKind::Patch, HairStyle::Wavy)
    };
    let s = generate(&p).expect("valid").strands;
    let mut tips: Vec<[u32; 3]> = strands_of(&s)
        .iter()
        .map(|q| q[q.len() - 1].to_array().map(f32::to_bits))
        .collect();
    tips.sort_unstable();
    tips.dedup();
    assert_eq!(tips.len(), 5);
}

#[test]
fn zero_clump_strength_translates_the_centre_shape() {
    let p = GenParams {
        clumps: 3,
        clump_strength: 0.0,
        ..small(GenKind::Patch, HairStyle::Curly)
    };
    let strands = generate(&p).expect("valid").strands;
    let all = strands_of(&strands);
    let centres = &all[..3];
    for member in &all[3..] {
        let matches_a_centre = centres.iter().any(|c| {
            c.iter()
                .zip(member.iter())
                .all(|(cq, mq)| ((*mq - member[0]) - (*cq - c[0])).length() < 1e-6)
        });
        assert!(matches_a_centre, "member strand is not a translated centre");
    }
}

#[test]
fn wave_and_curl_amplitudes_match_the_parameters() {
    // Same seed: each wavy/curly strand starts like its straight twin, which is a line for a patch (no
    // gravity).
    let base = GenParams {
        segments: 200,
        wave_frequency: 3.0,
        curl_turns: 5.0,
        ..small(GenKind::Patch, HairStyle::Straight)
    };
    let straight = generate(&base).expect("valid").strands;
    let axes: Vec<(Vec3, Vec3)> = strands_of(&straight)
        .iter()
        .map(|q| (q[0], (q[q.len() - 1] - q[0]).normalize()))
        .collect();
    let max_offsets = |s: &Strands| -> Vec<f32> {
        strands_of(s)
            .iter()
            .zip(&axes)
            .map(|(q, (a, dir))| {
                q.iter()
                    .map(|x| distance_to_line(*x, *a, *dir))
                    .fold(0.0, f32::max)
            })
            .collect()
    };
    // A sine a·(sin(ωs + φ) − sin φ) over three waves reaches between a and 2a from the axis.
    let a = 0.005;
    let wavy = generate(&GenParams {
        style: HairStyle::Wavy,
        wave_amplitude: a,
        ..base.clone()
    })
    .expect("valid");
    for m in max_offsets(&wavy.strands) {
        assert!((0.95 * a..=2.05 * a).contains(&m), "wave offset {m}");
    }
    // A helix of radius r through the root reaches 2r from the root's axis.
    let r = 0.004;
    let curly = generate(&GenParams {
        style: HairStyle::Curly,
        curl_radius: r,
        ..base.clone()
    })
    .expect("valid");
    for m in max_offsets(&curly.strands) {
        assert!((1.95 * r..=2.05 * r).contains(&m), "curl offset {m}");
    }
}

#[test]
fn strand_colours_are_brown_and_constant_along_each_strand() {
    let p = GenParams {
        strand_colors: true,
        ..small(GenKind::Head, HairStyle::Wavy)
    };
    let s = generate(&p).expect("valid").strands;
    let colors = s.color.as_ref().expect("colours");
    let plain = generate(&small(GenKind::Head, HairStyle::Wavy))
        .expect("valid")
        .strands;
    assert_eq!(plain.color, None, "no colour array unless asked for");
    let mut distinct = Vec::new();
    for (start, n) in s.ranges() {
        let c = colors[start];
        assert!(colors[start..start + n].iter().all(|x| *x == c));
        assert!(c.x > c.y && c.y > c.z && c.x < 0.6, "not brown: {c}");
        distinct.push(c.to_array().map(f32::to_bits));
    }
    distinct.sort_unstable();
    distinct.dedup();
    assert!(distinct.len() > s.strand_count() / 2, "colours barely vary");
}

#[test]
fn invalid_parameters_are_rejected_with_their_name() {
    let d = small(GenKind::Head, HairStyle::Wavy);
    let cases = [
        (
            GenParams {
                segments: 0,
                ..d.clone()
            },
            "segments",
        ),
        (
            GenParams {
                segments: 65536,
                ..d.clone()
            },
            "segments",
        ),
        (
            GenParams {
                length: 0.0,
                ..d.clone()
            },
            "length",
        ),
        (
            GenParams {
                length: f32::NAN,
                ..d.clone()
            },
            "length",
        ),
        (
            GenParams {
                length: f32::INFINITY,
                ..d.clone()
            },
            "length",
        ),
        (
            GenParams {
                clump_strength: 1.5,
                ..d.clone()
            },
            "clump_strength",
        ),
        (
            GenParams {
                clump_strength: -0.1,
                ..d.clone()
            },
            "clump_strength",
        ),
        (
            GenParams {
                density: -1.0,
                ..d.clone()
            },
            "density",
        ),
        (
            GenParams {
                gravity: f32::NAN,
                ..d.clone()
            },
            "gravity",
        ),
        (
            GenParams {
                curl_radius: -0.01,
                ..d.clone()
            },
            "curl_radius",
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
    }
    assert!(matches!(
        generate(&GenParams {
            strands: 0,
            ..d.clone()
        }),
        Err(GenError::NoStrands { .. })
    ));
    assert!(matches!(
        generate(&GenParams {
            density: 0.001,
            ..d.clone()
        }),
        Err(GenError::NoStrands { .. })
    ));
    let huge = GenParams {
        strands: 1_000_000,
        segments: 100,
        ..d.clone()
    };
    assert!(matches!(
        generate(&huge),
        Err(GenError::TooManyPoints {
            points: 101_000_000,
            cap: MAX_POINTS,
            ..
        })
    ));
    // The largest segment count is fine.
    assert!(
        generate(&GenParams {
            strands: 1,
            segments: 65535,
            ..d
        })
        .is_ok()
    );
}

#[test]
fn params_read_from_toml_with_kebab_case_enums() {
    let p: GenParams = toml::from_str("kind = \"patch\"\nstyle = \"curly\"\nstrands = 42").expect("parses");
    assert_eq!(
        (p.kind, p.style, p.strands),
        (GenKind::Patch, HairStyle::Curly, 42)
    );
    assert_eq!(
        p.segments,
        GenParams::default().segments,
        "missing fields take defaults"
    );
    assert!(
        toml::from_str::<GenParams>("strandz = 3").is_err(),
        "unknown fields are rejected"
    );
    let text = toml::to_string(&GenParams::default()).expect("serialises");
    assert!(
        text.contains("kind = \"head\"") && text.contains("style = \"wavy\""),
        "{text}"
    );
    assert_eq!(
        toml::from_str::<GenParams>(&text).expect("round trip"),
        GenParams::default()
    );
}

/// Two upward quads (areas 1 and 3, at y = 0 and y = 1) and one downward quad (at y = -1).
fn scalp() -> Mesh {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(5.0, 1.0, 0.0),
        Vec3::new(5.0, 1.0, 1.0),
        Vec3::new(8.0, 1.0, 1.0),
        Vec3::new(8.0, 1.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(0.0, -1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(1.0, -1.0, 0.0),
    ];
    // Up-facing: (0,0,1) × (1,0,1) from corner 0 gives +Y; the last quad is wound the other way.
    let indices = vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 10, 9, 8, 11, 10];
    let mut m = Mesh {
        positions,
        indices,
        color: Vec3::ONE,
        ..Mesh::default()
    };
    m.compute_normals();
    m
}

#[test]
fn scalp_roots_are_area_weighted_on_upward_faces() {
    let p = GenParams {
        strands: 4000,
        segments: 4,
        length: 0.5,
        gravity: 0.0,
        ..small(GenKind::Head, HairStyle::Straight)
    };
    let mesh = scalp();
    let s = generate_on_scalp(&p, &mesh).expect("valid");
    assert_eq!(s.meshes, vec![mesh]);
    let strands = strands_of(&s.strands);
    assert_eq!(strands.len(), 4000);
    let mut on_small = 0;
    for q in &strands {
        let root = q[0];
        let within = |v: f32, lo: f32, hi: f32| (lo - 1e-5..=hi + 1e-5).contains(&v);
        let small_quad = root.y == 0.0 && within(root.x, 0.0, 1.0) && within(root.z, 0.0, 1.0);
        let big_quad = root.y == 1.0 && within(root.x, 5.0, 8.0) && within(root.z, 0.0, 1.0);
        assert!(small_quad || big_quad, "root {root} is not on an upward quad");
        on_small += usize::from(small_quad);
        // No gravity: straight up along the normal.
        assert!((q[q.len() - 1] - (root + Vec3::Y * 0.5)).length() < 1e-5);
    }
    // Expected share 1/4; binomial standard deviation ≈ 0.0068 for 4000 roots.
    let share = on_small as f32 / 4000.0;
    assert!((share - 0.25).abs() < 0.03, "share on the small quad: {share}");
}

#[test]
fn bad_scalps_are_rejected() {
    let p = small(GenKind::Head, HairStyle::Wavy);
    let mut broken = scalp();
    broken.indices.extend_from_slice(&[0, 1, 99]);
    assert!(matches!(
        generate_on_scalp(&p, &broken),
        Err(GenError::BadScalp { .. })
    ));
    let mut down = scalp();
    down.indices.drain(..12);
    assert!(matches!(generate_on_scalp(&p, &down), Err(GenError::NoScalpArea)));
}
