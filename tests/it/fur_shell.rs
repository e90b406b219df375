//! Hybrid fur, CPU half (spec Part B, FT-U1..U5, U9; FC-5, FC-8, FC-11): the generated head welds to a
//! closed manifold, the paper's cylinder and hat counts, bad meshes fixed and counted, the neighbour walk
//! against brute-force point location, sub-edge neighbours, dynamic resolution and eqs. (1)–(3).

use std::collections::HashMap;

use glam::Vec3;
use hairlab::fur::index::{self, SubNeighbour, SubTriangle, sub_neighbour};
use hairlab::fur::mesh::{FurMesh, NONE, edge_of};
use hairlab::fur::shell::{Levels, Shell, ShellParams, Walk};
use hairlab::rng::SplitMix64;
use hairlab::scene::Mesh;
use hairlab::scene::fur_shapes as shapes;
use hairlab::scene::generate::{GenKind, GenParams, generate};

fn head_mesh() -> Mesh {
    let p = GenParams {
        kind: GenKind::Head,
        strands: 10,
        segments: 2,
        clumps: 0,
        floor: false,
        ..GenParams::default()
    };
    generate(&p).unwrap().meshes.remove(0)
}

fn assert_symmetric(m: &FurMesh) {
    for (f, nb) in m.neighbours.iter().enumerate() {
        for (e, &g) in nb.iter().enumerate() {
            if g == NONE {
                continue;
            }
            let (a, b) = edge_of(m.faces[f], e);
            let h = m.edge_index(g as usize, a, b).expect("neighbour shares the edge");
            assert_eq!(m.neighbours[g as usize][h], f as u32, "face {f} edge {e}");
            assert_eq!(
                edge_of(m.faces[g as usize], h),
                (b, a),
                "face {f} edge {e} wound the same way"
            );
        }
    }
}

/// Undirected edges of a raw index list used by exactly one triangle.
fn raw_boundary_edges(indices: &[u32]) -> usize {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in indices.chunks_exact(3) {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    uses.values().filter(|&&n| n == 1).count()
}

#[test]
fn the_generated_head_welds_to_a_closed_manifold() {
    let raw = head_mesh();
    // 25 latitude rows × 41 longitudes (seam column and poles duplicated), 2·40 pole + 2·40·22 band faces.
    assert_eq!(raw.positions.len(), 25 * 41);
    assert_eq!(raw.indices.len() / 3, 1840);
    let raw_boundary = raw_boundary_edges(&raw.indices);
    assert!(
        raw_boundary > 0,
        "the unwelded head has seam and pole boundary edges"
    );
    let m = FurMesh::build("head", &raw).unwrap();
    // Welded: two poles + 23 inner rows × 40.
    assert_eq!(m.report.welded_vertices, 2 + 23 * 40);
    assert_eq!(m.faces.len(), 1840);
    assert_eq!(m.edge_count(), 1840 * 3 / 2);
    assert_eq!(m.euler_characteristic(), 2);
    assert_eq!(m.report.boundary_edges, 0);
    assert!(
        m.neighbours.iter().flatten().all(|&g| g != NONE),
        "every edge has two faces"
    );
    assert_eq!(m.report.flipped_faces, 0, "the head is wound outward");
    assert_eq!(m.report.warning("head"), None);
    assert_symmetric(&m);
    // Smoothed normals agree with the analytic ellipsoid normals the generator wrote (at the welded vertices).
    let worst = raw
        .positions
        .iter()
        .zip(&raw.normals)
        .map(|(p, n)| {
            let v = m.positions.iter().position(|q| q.distance(*p) < 1e-6).unwrap();
            m.normals[v].dot(*n)
        })
        .fold(1.0f32, f32::min);
    println!("head: {raw_boundary} raw boundary edges, worst normal cosine vs analytic {worst:.5}");
    assert!(worst > 0.99, "{worst}");
}

#[test]
fn the_paper_cylinder_has_3584_triangles_and_the_hat_5632() {
    let c = FurMesh::build("fur-cylinder", &shapes::fur_cylinder()).unwrap();
    assert_eq!(c.faces.len(), 3584); // Table 1
    assert_eq!(c.report.welded_vertices, 64 * 29);
    assert_eq!(c.euler_characteristic(), 0);
    assert_eq!(c.report.boundary_edges, 2 * 64);
    assert_eq!(c.report.flipped_faces, 0);
    assert_symmetric(&c);
    // The hat: 44 profile segments × 64 around, each a full quad ring (Table 1's 5632 = 2·64·44), an annulus
    // from the crown's vent hole to the brim's rim: 45 rings of 64 vertices, two boundary loops of 64 edges.
    let h = FurMesh::build("fur-hat", &shapes::fur_hat()).unwrap();
    assert_eq!(h.faces.len(), 2 * 64 * 44);
    assert_eq!(h.faces.len(), 5632); // Table 1
    assert_eq!(h.report.welded_vertices, 45 * 64);
    assert_eq!(h.report.degenerate_faces, 0);
    assert_eq!(h.euler_characteristic(), 0);
    assert_eq!(h.report.boundary_edges, 2 * 64);
    assert_eq!(h.report.flipped_faces, 0);
    assert_eq!(h.report.warning("fur-hat"), None);
    assert_symmetric(&h);
    for (name, m) in [("fur-cylinder", c), ("fur-hat", h)] {
        let s = Shell::build(m, &ShellParams::default()).unwrap();
        let hist = s.levels.iter().fold([0usize; 9], |mut h, &d| {
            h[d as usize] += 1;
            h
        });
        println!(
            "{name}: {} sub-elements ({} B at 16 B each), levels histogram {hist:?}, {:?}",
            s.sub_elements,
            s.sub_elements * 16,
            s.report
        );
        assert!(s.sub_elements > 0);
        // Only the concave crown–brim junction (y ≈ 0, r ≈ 0.095: the hat's 128 shrunk vertices are its ring
        // and the brim's first) is tighter than the 1 cm shell; the vent hole's rim is not.
        let shrunk: Vec<Vec3> = s
            .heights
            .iter()
            .zip(&s.mesh.positions)
            .filter(|(h, _)| **h < s.height)
            .map(|(_, p)| *p)
            .collect();
        assert!(
            shrunk
                .iter()
                .all(|p| p.y < 0.01 && (p.x.hypot(p.z) - 0.095).abs() < 0.01),
            "{name}: {shrunk:?}"
        );
    }
}

#[test]
fn inconsistent_windings_are_fixed_and_counted_and_non_manifold_edges_cut() {
    let clean = shapes::cylinder(0.04, 0.3, 16, 6);
    let mut rng = SplitMix64::new(10);
    let mut flipped = clean.clone();
    let mut expect = 0;
    for t in flipped.indices.chunks_exact_mut(3) {
        // A minority (about a quarter) of faces, so the majority winding is the outward one.
        if rng.unit() < 0.25 {
            t.swap(1, 2);
            expect += 1;
        }
    }
    assert!(expect > 0);
    let m = FurMesh::build("scrambled", &flipped).unwrap();
    let reference = FurMesh::build("clean", &clean).unwrap();
    assert_eq!(m.report.flipped_faces, expect);
    assert_eq!(m.faces, reference.faces);
    assert_eq!(m.neighbours, reference.neighbours);
    assert!(
        m.report
            .warning("scrambled")
            .unwrap()
            .contains(&format!("{expect} faces re-oriented"))
    );
    // A duplicated face makes its three edges non-manifold (three faces each): cut and reported.
    let mut dup = clean.clone();
    let first: Vec<u32> = dup.indices[..3].to_vec();
    dup.indices.extend(first);
    let m = FurMesh::build("dup", &dup).unwrap();
    assert_eq!(m.report.non_manifold_edges, 3);
    assert_eq!(m.report.inconsistent_edges, 0);
    let w = m.report.warning("dup").unwrap();
    assert!(
        w.contains("'dup'") && w.contains("3 edges are non-manifold or inconsistently wound"),
        "{w}"
    );
}

/// A random point inside prism `f`: uniform barycentrics and height.
fn random_inside(s: &Shell, rng: &mut SplitMix64) -> (usize, Vec3) {
    let f = rng.int(0, s.mesh.faces.len() - 1);
    let (u, v) = (rng.unit(), rng.unit());
    let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
    let w = rng.range(0.05, 0.95);
    (f, s.point(f, [1.0 - u - v, u, v], w))
}

fn random_direction(rng: &mut SplitMix64) -> Vec3 {
    Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize()
}

/// Whether barycentric point `l` lies in the closed lattice triangle `t` at level `d` (geometric test).
fn contains(t: &SubTriangle, d: u32, l: [f32; 3]) -> bool {
    let n = (1u32 << d) as f32;
    let eps = 1e-5;
    // Up: λ_x·n ≥ a_x for all x; down: λ_x·n ≤ a_x + 1 for all x.
    (0..3).all(|x| {
        let v = l[x] * n;
        if t.up {
            v >= t.cell[x] as f32 - eps
        } else {
            v <= t.cell[x] as f32 + 1.0 + eps
        }
    })
}

#[test]
fn fc5_the_neighbour_walk_matches_brute_force_point_location_at_every_level() {
    let head = FurMesh::build("head", &head_mesh()).unwrap();
    let params = |d| ShellParams {
        height: 0.01,
        layers: 8,
        cell: None,
        levels: Levels::Uniform(d),
    };
    let shells: Vec<Shell> = (0..=6)
        .map(|d| Shell::build(head.clone(), &params(d)).unwrap())
        .collect();
    let s = &shells[0];
    let mut rng = SplitMix64::new(5);
    let (rays, step) = (600, 0.01 / 8.0);
    assert_eq!(s.hop_cap(), 20, "the head's poles join 40 faces");
    let (mut samples, mut hops, mut crossings, mut lost, mut mismatches) = (0usize, 0u64, 0usize, 0, 0);
    let mut max_hops = 0;
    let mut exits = [0usize; 3]; // top, base, boundary
    for ray in 0..rays {
        let (mut f, p0) = random_inside(s, &mut rng);
        let dir = random_direction(&mut rng);
        for k in 0..64 {
            let p = p0 + dir * (k as f32 * step);
            let walk = s.walk(p, f as u32, s.hop_cap());
            let brute = s.locate_brute(p);
            match walk {
                Walk::Inside { face, at, hops: h } => {
                    samples += 1;
                    hops += u64::from(h);
                    max_hops = max_hops.max(h);
                    crossings += usize::from(face as usize != f);
                    f = face as usize;
                    let Some((bf, bat)) = brute else {
                        mismatches += 1;
                        break;
                    };
                    if bf != face {
                        mismatches += 1;
                        break;
                    }
                    for (d, sd) in shells.iter().enumerate() {
                        assert_eq!(sd.sub_element(f, &at), sd.sub_element(f, &bat), "ray {ray} d {d}");
                        // And the local index is the sub-triangle that geometrically holds the point.
                        if ray < 40 {
                            let d = d as u32;
                            let (_, local, _) = sd.sub_element(f, &at);
                            assert!(
                                contains(&SubTriangle::from_index(local, d), d, at.lambda),
                                "ray {ray} d {d}"
                            );
                        }
                    }
                }
                other => {
                    match other {
                        Walk::Top { .. } => exits[0] += 1,
                        Walk::Base { .. } => exits[1] += 1,
                        Walk::Boundary { .. } => exits[2] += 1,
                        Walk::Lost { .. } => lost += 1,
                        Walk::Inside { .. } => unreachable!(),
                    }
                    if brute.is_some() {
                        mismatches += 1;
                    }
                    break;
                }
            }
        }
    }
    println!(
        "FC-5: {rays} rays, {samples} inside samples, {crossings} prism crossings, mean hops {:.3}, most hops {max_hops}, \
         exits top/base/boundary {exits:?}, lost {lost}, mismatches {mismatches}",
        hops as f64 / samples as f64
    );
    assert_eq!(mismatches, 0);
    assert_eq!(lost, 0, "no lost rays on a smooth convex mesh");
    assert!(samples > rays * 4, "{samples}");
    assert!(crossings > rays / 2, "the walk crosses prisms: {crossings}");
    assert_eq!(exits[2], 0, "the head is closed");
}

/// Barycentrics of face `g` for a point given by weights on two of its vertices.
fn on_edge(mesh: &FurMesh, g: usize, va: u32, wa: f32, vb: u32, wb: f32) -> [f32; 3] {
    std::array::from_fn(|k| {
        let v = mesh.faces[g][k];
        if v == va {
            wa
        } else if v == vb {
            wb
        } else {
            0.0
        }
    })
}

/// Pushes barycentric point `l` by `eps` towards (`sign` = 1) or away from (−1) corner `x`, keeping the sum.
fn push(l: [f32; 3], x: usize, sign: f32, eps: f32) -> [f32; 3] {
    std::array::from_fn(|y| {
        if y == x {
            l[y] + sign * eps
        } else {
            l[y] - 0.5 * sign * eps
        }
    })
}

/// Checks every sub-edge of the faces `faces` of `s` against point location just across it.
fn check_sub_edges(s: &Shell, faces: impl Iterator<Item = usize>) -> (usize, usize, usize) {
    let eps = 1e-4;
    let (mut inside, mut across, mut mixed) = (0, 0, 0);
    for f in faces {
        let d = s.levels[f];
        let n = (1u32 << d) as f32;
        for i in 0..1u32 << (2 * d) {
            let t = SubTriangle::from_index(i, d);
            let c = t.corners();
            for x in 0..3 {
                let (y, z) = ((x + 1) % 3, (x + 2) % 3);
                let mid: [f32; 3] = std::array::from_fn(|k| (c[y][k] + c[z][k]) as f32 / (2.0 * n));
                match sub_neighbour(&s.mesh, &s.levels, f, i, x) {
                    SubNeighbour::Inside(j) => {
                        inside += 1;
                        let sign = if t.up { -1.0 } else { 1.0 };
                        let l = push(mid, x, sign, eps / n);
                        assert_eq!(index::locate(l, d), j, "face {f} d {d} sub {i} edge {x}");
                    }
                    SubNeighbour::Across {
                        face: g,
                        edge: xg,
                        subs,
                    } => {
                        across += 1;
                        let g = g as usize;
                        let dg = s.levels[g];
                        mixed += usize::from(dg != d);
                        assert_eq!(s.mesh.neighbours[g][xg], f as u32);
                        let (va, vb) = edge_of(s.mesh.faces[f], x);
                        // Along the sub-edge from corner y's end (λ_z = c[y][z]/n) to corner z's end.
                        let m = subs.len().max(1);
                        let found: Vec<u32> = (0..m)
                            .map(|k| {
                                let s_z = (c[y][z] as f32 + (k as f32 + 0.5) / m as f32) / n;
                                let l = on_edge(&s.mesh, g, vb, s_z, va, 1.0 - s_z);
                                let ng = (1u32 << dg) as f32;
                                index::locate(push(l, xg, 1.0, eps / ng.max(n)), dg)
                            })
                            .collect();
                        let mut unique = found.clone();
                        unique.dedup();
                        assert_eq!(unique, subs, "face {f} d {d} sub {i} edge {x} → face {g} d {dg}");
                    }
                    SubNeighbour::Boundary => {
                        assert!(t.up && t.cell[x] == 0 && s.mesh.neighbours[f][x] == NONE);
                    }
                }
            }
        }
    }
    (inside, across, mixed)
}

#[test]
fn fc5_sub_edge_neighbours_match_point_location_inside_and_across_faces() {
    // Every level d ≤ 6 uniformly on a small tube (boundary rings included).
    let tube = FurMesh::build("tube", &shapes::cylinder(0.04, 0.1, 12, 3)).unwrap();
    for d in 0..=6 {
        let s = Shell::build(
            tube.clone(),
            &ShellParams {
                levels: Levels::Uniform(d),
                ..ShellParams::default()
            },
        )
        .unwrap();
        let (inside, across, _) = check_sub_edges(&s, 0..s.mesh.faces.len());
        assert_eq!(
            inside + across + 12 * 2 * (1 << d),
            72 * 3 * (1 << (2 * d)),
            "d {d}"
        );
    }
    // Dynamic levels on the head: neighbours at other levels (pole triangles are smaller).
    let head = FurMesh::build("head", &head_mesh()).unwrap();
    let s = Shell::build(
        head,
        &ShellParams {
            height: 0.01,
            layers: 4,
            cell: Some(0.004),
            levels: Levels::Dynamic { max: 6 },
        },
    )
    .unwrap();
    let lo = *s.levels.iter().min().unwrap();
    let hi = *s.levels.iter().max().unwrap();
    let (inside, across, mixed) = check_sub_edges(&s, 0..s.mesh.faces.len());
    println!(
        "head, dynamic: levels {lo}..={hi}, {inside} inside and {across} across sub-edges, {mixed} across levels"
    );
    assert!(lo < hi && mixed > 0, "the head should mix levels");
}

#[test]
fn fc11_eq_2_is_a_bijection_onto_4_to_the_d() {
    for d in 0..=8u32 {
        let n = 1u32 << d;
        let mut seen = vec![false; (n * n) as usize];
        // Enumerate the sub-triangles from the lattice directly: upward cells sum to n − 1, downward to n − 2.
        for (sum, off) in [(n - 1, 1.0 / 3.0), (n.wrapping_sub(2), 2.0 / 3.0)] {
            if d == 0 && off > 0.5 {
                continue;
            }
            for a0 in 0..=sum {
                for a1 in 0..=sum - a0 {
                    let a2 = sum - a0 - a1;
                    let l = [a0, a1, a2].map(|a| (a as f32 + off) / n as f32);
                    let i = index::locate(l, d) as usize;
                    assert!(i < seen.len(), "d {d}: {i} out of range");
                    assert!(!seen[i], "d {d}: index {i} twice");
                    seen[i] = true;
                }
            }
        }
        assert!(seen.iter().all(|&s| s), "d {d}: not onto");
    }
}

#[test]
fn eq_3_global_indices_are_a_bijection_under_dynamic_resolution() {
    let head = FurMesh::build("head", &head_mesh()).unwrap();
    let s = Shell::build(
        head,
        &ShellParams {
            height: 0.01,
            layers: 3,
            cell: Some(0.006),
            levels: Levels::Dynamic { max: 6 },
        },
    )
    .unwrap();
    let mut seen = vec![false; s.sub_elements as usize];
    for f in 0..s.mesh.faces.len() {
        for l in 0..s.layers {
            for i in 0..1u32 << (2 * s.levels[f]) {
                let g = index::global_index(s.offsets[f], l, s.levels[f], i) as usize;
                assert!(!seen[g], "face {f} layer {l} sub {i}");
                seen[g] = true;
            }
        }
    }
    assert!(seen.iter().all(|&x| x));
    println!(
        "eq. 3: {} sub-elements over {} faces",
        s.sub_elements,
        s.mesh.faces.len()
    );
}

#[test]
fn fc8_sub_elements_per_triangle_follow_its_area() {
    let cell = 0.004f64;
    let cell_area = cell * cell * 3f64.sqrt() / 4.0;
    let params = ShellParams {
        height: 0.01,
        layers: 4,
        cell: Some(cell as f32),
        levels: Levels::Dynamic { max: 8 },
    };
    let head = Shell::build(FurMesh::build("head", &head_mesh()).unwrap(), &params).unwrap();
    let mut area_sum = 0.0;
    for f in 0..head.mesh.faces.len() {
        let a = f64::from(head.mesh.face_area(f));
        area_sum += a;
        let per_layer = 4f64.powi(head.levels[f] as i32);
        // 4^d is the smallest power of four reaching area / cell area: within one 4× step of it.
        assert!(per_layer >= a / cell_area || head.levels[f] == 8, "face {f}");
        assert!(per_layer < 4.0 * a / cell_area || head.levels[f] == 0, "face {f}");
    }
    let total = head.sub_elements as f64;
    let ideal = area_sum * f64::from(params.layers) / cell_area;
    println!(
        "FC-8 head: {total} sub-elements, area × n_l / cell area = {ideal:.0}, ratio {:.3}",
        total / ideal
    );
    assert!((1.0..4.0).contains(&(total / ideal)));
    // Refining the cylinder 4× (twice around, twice along) keeps the total within 2×.
    let coarse = Shell::build(
        FurMesh::build("c", &shapes::cylinder(0.04, 0.3, 64, 28)).unwrap(),
        &params,
    )
    .unwrap();
    let fine = Shell::build(
        FurMesh::build("c4", &shapes::cylinder(0.04, 0.3, 128, 56)).unwrap(),
        &params,
    )
    .unwrap();
    let ratio = fine.sub_elements as f64 / coarse.sub_elements as f64;
    println!(
        "FC-8 cylinder: {} → {} sub-elements refined 4× (ratio {ratio:.3}), levels {} → {}",
        coarse.sub_elements, fine.sub_elements, coarse.levels[0], fine.levels[0]
    );
    assert!((0.5..=2.0).contains(&ratio), "{ratio}");
}

#[test]
fn shell_height_is_continuous_across_shared_lateral_faces() {
    let head = FurMesh::build("head", &head_mesh()).unwrap();
    let s = Shell::build(head, &ShellParams::default()).unwrap();
    let mut rng = SplitMix64::new(7);
    let (mut worst_w, mut worst_l) = (0.0f32, 0.0f32);
    for _ in 0..2000 {
        let f = rng.int(0, s.mesh.faces.len() - 1);
        let e = rng.int(0, 2);
        let g = s.mesh.neighbours[f][e] as usize;
        let (w, t) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        // A point on f's lateral face over edge e at height w: between corners e + 1 and e + 2 of q(w).
        let mut l = [0.0; 3];
        l[(e + 1) % 3] = 1.0 - t;
        l[(e + 2) % 3] = t;
        let p = s.point(f, l, w);
        let (a, b) = (s.locate(p, f), s.locate(p, g));
        let (va, _) = edge_of(s.mesh.faces[f], e);
        let opposite = s.mesh.faces[g]
            .iter()
            .position(|v| !s.mesh.faces[f].contains(v))
            .unwrap();
        worst_w = worst_w.max((a.w - w).abs()).max((b.w - w).abs());
        worst_l = worst_l.max(a.lambda[e].abs()).max(b.lambda[opposite].abs());
        let kg = s.mesh.faces[g].iter().position(|&v| v == va).unwrap();
        worst_l = worst_l.max((b.lambda[kg] - (1.0 - t)).abs());
    }
    println!("lateral faces: worst |Δw| {worst_w:.2e}, worst barycentric error {worst_l:.2e}");
    assert!(worst_w < 1e-4 && worst_l < 1e-4, "{worst_w} {worst_l}");
}
