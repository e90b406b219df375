//! The hierarchy's queries against a loop over every primitive, and the slab test on rays that lie in a box's planes.

use super::*;
use crate::pathtrace::fibre::tests::random_segment;
use crate::rng::SplitMix64;

fn random_scene(rng: &mut SplitMix64, n: usize) -> Vec<Segment> {
    (0..n)
        .map(|_| {
            let mut s = random_segment(rng);
            s.ra *= 0.1;
            s.rb *= 0.1;
            s.b = s.a + (s.b - s.a) * 0.2;
            s
        })
        .collect()
}

/// `n` small triangles about the origin.
fn random_triangles(rng: &mut SplitMix64, n: usize) -> Vec<Triangle> {
    (0..n)
        .map(|_| {
            let mut v = || Vec3::new(rng.normal(), rng.normal(), rng.normal());
            Triangle {
                p0: v() * 0.5,
                e1: v() * 0.1,
                e2: v() * 0.1,
                albedo: Vec3::ONE,
            }
        })
        .collect()
}

fn random_ray(rng: &mut SplitMix64) -> Ray {
    let o = Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 2.0;
    let target = Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 0.4;
    Ray::new(o, target - o)
}

/// Every primitive's own full test (the line test included) of `ray` within `(0, t_max)`, in index order.
fn brute_force(bvh: &Bvh, ray: &Ray, t_max: f32) -> Vec<Hit> {
    let n = bvh.segments.len();
    (0..n + bvh.triangle_count())
        .filter_map(|i| {
            let hit = match bvh.segments.get(i) {
                Some(s) => s.intersect(ray, 0.0, t_max),
                None => bvh.triangles[i - n].intersect(ray, 0.0, t_max),
            };
            hit.map(|h| Hit {
                primitive: i as u32,
                ..h
            })
        })
        .collect()
}

#[test]
fn queries_equal_brute_force() {
    let mut rng = SplitMix64::new(7);
    let triangles = random_triangles(&mut rng, 300);
    let bvh = Bvh::with_triangles(random_scene(&mut rng, 3000), triangles);
    let mut hits = 0;
    for _ in 0..3000 {
        let ray = random_ray(&mut rng);
        let t_max = rng.range(1.0, 6.0);
        let all = brute_force(&bvh, &ray, t_max);
        let brute = all.iter().copied().reduce(|a, b| if b.t < a.t { b } else { a });
        let got = bvh.closest_hit(&ray, t_max);
        assert_eq!(got.map(|h| (h.primitive, h.t)), brute.map(|h| (h.primitive, h.t)));
        assert_eq!(bvh.any_hit(&ray, t_max), brute.is_some());
        let mut sorted = all.clone();
        sorted.sort_by(|a, b| a.t.total_cmp(&b.t));
        let listed = bvh.all_hits(&ray, t_max);
        assert_eq!(listed.len(), sorted.len());
        assert!(listed.iter().zip(&sorted).all(|(a, b)| a.t == b.t));
        hits += brute.is_some() as usize;
    }
    assert!(hits > 500, "only {hits} rays hit");
}

/// A ray parallel to two planes of a box and lying in one of them (`0 × ∞` in the slab test) meets the closed
/// box, with the entry and exit its other axes give; a ray just outside the face does not. Lanes: the unit
/// cube, a flat box in the plane x = 0 (an axis-aligned triangle's), the cube beside it on x, and the cube
/// below it on z.
#[test]
fn a_ray_lying_in_a_face_meets_the_box() {
    let boxes = [
        (Vec3::ZERO, Vec3::ONE),
        (Vec3::ZERO, Vec3::new(0.0, 1.0, 1.0)),
        (Vec3::X, Vec3::new(2.0, 1.0, 1.0)),
        (Vec3::NEG_Z, Vec3::new(1.0, 1.0, 0.0)),
    ];
    let mut node = Node4 {
        min: [Vec4::ZERO; 3],
        max: [Vec4::ZERO; 3],
        first: [0; 4],
        count: [1; 4],
    };
    for (lane, (lo, hi)) in boxes.iter().enumerate() {
        for axis in 0..3 {
            node.min[axis][lane] = lo[axis];
            node.max[axis][lane] = hi[axis];
        }
    }
    let down = |x: f32| Vec3::new(x, 0.0, -1.0);
    // (origin, direction, per lane: (entry, exit) where met). Down from z = 2, the cubes are met from 1 to
    // 2 and the one below from 2 to 3; along an edge from z = 5, from 4 to 5.
    type Met = [Option<(f32, f32)>; 4];
    let cases: [(Vec3, Vec3, Met); 6] = [
        (
            Vec3::new(1.0, 0.5, 2.0),
            down(0.0),
            [Some((1.0, 2.0)), None, Some((1.0, 2.0)), Some((2.0, 3.0))],
        ),
        (
            Vec3::new(1.0, 0.5, 2.0),
            down(-0.0),
            [Some((1.0, 2.0)), None, Some((1.0, 2.0)), Some((2.0, 3.0))],
        ),
        (
            Vec3::new(0.0, 0.5, 2.0),
            down(0.0),
            [Some((1.0, 2.0)), Some((1.0, 2.0)), None, Some((2.0, 3.0))],
        ),
        (
            Vec3::new(0.0, 0.5, 2.0),
            down(-0.0),
            [Some((1.0, 2.0)), Some((1.0, 2.0)), None, Some((2.0, 3.0))],
        ),
        (
            Vec3::new(1.0, 1.0, 5.0),
            Vec3::new(-0.0, 0.0, -1.0),
            [Some((4.0, 5.0)), None, Some((4.0, 5.0)), Some((5.0, 6.0))],
        ),
        (
            Vec3::new(1.000_001, 0.5, 2.0),
            down(0.0),
            [None, None, Some((1.0, 2.0)), None],
        ),
    ];
    for (origin, dir, want) in cases {
        let inv = dir.recip();
        let (near, far) = slab4(
            &node,
            origin.to_array().map(Vec4::splat),
            inv.to_array().map(Vec4::splat),
        );
        for (lane, w) in want.iter().enumerate() {
            let got = (near[lane] <= far[lane]).then_some((near[lane], far[lane]));
            let ok = match (got, w) {
                (Some((n, f)), Some((wn, wf))) => n == *wn && (f - wf).abs() <= 1e-6 * wf,
                (None, None) => true,
                _ => false,
            };
            assert!(ok, "{origin} along {dir}, lane {lane}: {got:?}, want {w:?}");
        }
    }
}

/// `closest_hit`, `any_hit`, `any_mesh_hit_from` and `all_hits` through the hierarchy equal a loop over every
/// primitive for rays the slab test finds hard: rays lying in a plane of a node's box (one direction component ±0
/// and the origin's coordinate on the box's face), rays along a box's edge, and rays straight down a floor and
/// into a wall of axis-aligned triangles along their shared edges, among random and axis-aligned fibres.
#[test]
fn queries_equal_brute_force_for_rays_in_box_planes() {
    let mut rng = SplitMix64::new(11);
    let mut segments = random_scene(&mut rng, 800);
    for k in 0..300 {
        let grid = |rng: &mut SplitMix64| (rng.range(-8.0, 8.0) as i32) as f32 / 8.0;
        let a = Vec3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
        let mut step = Vec3::ZERO;
        step[k % 3] = 0.25;
        segments.push(Segment::new(a, a + step, 0.01, 0.01));
    }
    // A floor at z = -1.25 and a wall at x = -1.25, each 8 × 8 squares a quarter wide cut into two triangles.
    let mut triangles = Vec::new();
    for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i as f32 * 0.25 - 1.0, j as f32 * 0.25 - 1.0))) {
        let corners: [fn(f32, f32) -> Vec3; 2] =
            [|u, v| Vec3::new(u, v, -1.25), |u, v| Vec3::new(-1.25, u, v)];
        for corner in corners {
            let (p, e1, e2) = (corner(i, j), corner(i + 0.25, j), corner(i, j + 0.25));
            let q = corner(i + 0.25, j + 0.25);
            for (p0, a, b) in [(p, e1, e2), (q, e2, e1)] {
                triangles.push(Triangle {
                    p0,
                    e1: a - p0,
                    e2: b - p0,
                    albedo: Vec3::ONE,
                });
            }
        }
    }
    let bvh = Bvh::with_triangles(segments, triangles);
    let lanes: Vec<(Vec3, Vec3)> = bvh
        .nodes
        .iter()
        .flat_map(|n| {
            (0..4).filter(|&l| n.count[l] != UNUSED).map(move |l| {
                (
                    Vec3::new(n.min[0][l], n.min[1][l], n.min[2][l]),
                    Vec3::new(n.max[0][l], n.max[1][l], n.max[2][l]),
                )
            })
        })
        .collect();
    let zero = |rng: &mut SplitMix64| if rng.unit() < 0.5 { 0.0 } else { -0.0 };
    let (mut rays, mut hits) = (0, [0usize; 3]);
    for (kind, met) in hits.iter_mut().enumerate() {
        for _ in 0..2000 {
            let ray = match kind {
                // In a plane of a node's box: the face's coordinate, the rest of the origin about the box.
                0 | 1 => {
                    let (lo, hi) = lanes[(rng.unit() * lanes.len() as f32) as usize % lanes.len()];
                    let mut o = lo
                        + (hi - lo)
                            * Vec3::new(rng.range(-0.5, 1.5), rng.range(-0.5, 1.5), rng.range(-0.5, 1.5));
                    let mut d = Vec3::new(rng.normal(), rng.normal(), rng.normal());
                    let axis = (rng.unit() * 3.0) as usize % 3;
                    let face = |rng: &mut SplitMix64, a: usize| if rng.unit() < 0.5 { lo[a] } else { hi[a] };
                    o[axis] = face(&mut rng, axis);
                    d[axis] = zero(&mut rng);
                    if kind == 1 {
                        // Along an edge: a second face's coordinate, only the third axis moving.
                        let other = (axis + 1 + (rng.unit() < 0.5) as usize) % 3;
                        o[other] = face(&mut rng, other);
                        d[other] = zero(&mut rng);
                    }
                    Ray::new(o, d)
                }
                // Straight down onto the floor or into the wall along the triangles' shared edges.
                _ => {
                    let line = (rng.range(0.0, 9.0) as i32) as f32 * 0.25 - 1.0;
                    let free = rng.range(-1.0, 1.0);
                    if rng.unit() < 0.5 {
                        Ray::new(
                            Vec3::new(line, free, 3.0),
                            Vec3::new(zero(&mut rng), zero(&mut rng), -1.0),
                        )
                    } else {
                        Ray::new(
                            Vec3::new(3.0, free, line),
                            Vec3::new(-1.0, zero(&mut rng), zero(&mut rng)),
                        )
                    }
                }
            };
            let t_max = if rng.unit() < 0.5 {
                f32::INFINITY
            } else {
                rng.range(0.5, 6.0)
            };
            let all = brute_force(&bvh, &ray, t_max);
            let brute = all.iter().map(|h| h.t).reduce(f32::min);
            let got = bvh.closest_hit(&ray, t_max);
            assert_eq!(got.map(|h| h.t), brute, "{ray:?} within {t_max}");
            if let Some(h) = got {
                assert!(
                    all.iter().any(|b| (b.primitive, b.t) == (h.primitive, h.t)),
                    "{ray:?}"
                );
            }
            assert_eq!(
                bvh.any_hit(&ray, t_max),
                brute.is_some(),
                "{ray:?} within {t_max}"
            );
            let meshes = all.iter().any(|h| h.primitive as usize >= bvh.segments.len());
            assert_eq!(
                bvh.any_mesh_hit_from(&ray, t_max, NO_PRIMITIVE),
                meshes,
                "{ray:?} within {t_max}"
            );
            let mut sorted: Vec<f32> = all.iter().map(|h| h.t).collect();
            sorted.sort_by(f32::total_cmp);
            let listed: Vec<f32> = bvh.all_hits(&ray, t_max).iter().map(|h| h.t).collect();
            assert_eq!(listed, sorted, "{ray:?} within {t_max}");
            rays += 1;
            *met += brute.is_some() as usize;
        }
    }
    eprintln!(
        "{rays} rays; hits in a plane {}, along an edge {}, down the seams {}",
        hits[0], hits[1], hits[2]
    );
    assert!(hits.iter().all(|&h| h > 400), "hits {hits:?}");
}

/// A ray leaving a hit as the integrator starts it (off the surface by [`Hit::offset`] on its side, either
/// way) meets what it meets with its own primitive tested too: `closest_hit_from`, `any_hit_from` and
/// `any_mesh_hit_from`, which skip it where it is convex, equal the queries that test every primitive, among
/// random segments (half of them of one radius, half tapered) and triangles.
#[test]
fn a_ray_leaving_a_primitive_meets_what_the_full_queries_meet() {
    let mut rng = SplitMix64::new(19);
    let triangles = random_triangles(&mut rng, 300);
    let mut segments = random_scene(&mut rng, 3000);
    for s in segments.iter_mut().step_by(2) {
        s.rb = s.ra;
    }
    let bvh = Bvh::with_triangles(segments, triangles);
    let (mut leaving, mut met, mut meshes, mut skipped) = (0, 0, 0, 0);
    for _ in 0..3000 {
        let Some(hit) = bvh.closest_hit(&random_ray(&mut rng), f32::INFINITY) else {
            continue;
        };
        for _ in 0..4 {
            let w = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
            let origin = hit.point + hit.offset() * hit.normal.dot(w).signum() * hit.normal;
            let ray = Ray::new(origin, w);
            let t_max = rng.range(0.05, 6.0);
            let full = bvh.closest_hit(&ray, t_max);
            let skipping = bvh.closest_hit_from(&ray, t_max, hit.primitive);
            assert_eq!(
                skipping.map(|h| (h.primitive, h.t)),
                full.map(|h| (h.primitive, h.t)),
                "{ray:?} leaving {hit:?}"
            );
            assert_eq!(bvh.any_hit_from(&ray, t_max, hit.primitive), full.is_some());
            let mesh = bvh.any_mesh_hit_from(&ray, t_max, NO_PRIMITIVE);
            assert_eq!(bvh.any_mesh_hit_from(&ray, t_max, hit.primitive), mesh);
            leaving += 1;
            met += full.is_some() as usize;
            meshes += mesh as usize;
            skipped += bvh.convex(hit.primitive) as usize;
        }
    }
    eprintln!(
        "{leaving} rays leaving a hit ({skipped} a convex one), {met} meeting a primitive, {meshes} a triangle"
    );
    assert!(
        leaving > 2000 && skipped > 1000 && met > 300 && meshes > 50,
        "{leaving} {skipped} {met} {meshes}"
    );
}

/// The shadow query tests the thread's last occluder first: whatever that holds (a primitive that blocks the
/// ray, one that does not, the primitive the ray leaves, an index beyond the hierarchy), `any_hit_from` answers
/// as the loop over every primitive does, and the remembered primitive answers some of the queries alone.
#[test]
fn the_last_occluder_changes_no_shadow_answer() {
    let mut rng = SplitMix64::new(23);
    let triangles = random_triangles(&mut rng, 200);
    let bvh = Bvh::with_triangles(random_scene(&mut rng, 2000), triangles);
    let primitives = (bvh.segments.len() + bvh.triangle_count()) as u32;
    let (mut blocked, mut answered_by_last) = (0, 0);
    for k in 0..4000u32 {
        let Some(hit) = bvh.closest_hit(&random_ray(&mut rng), f32::INFINITY) else {
            continue;
        };
        let w = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        let origin = hit.point + hit.offset() * hit.normal.dot(w).signum() * hit.normal;
        let ray = Ray::new(origin, w);
        let t_max = rng.range(0.05, 6.0);
        let expected = brute_force(&bvh, &ray, t_max)
            .iter()
            .any(|h| h.primitive != hit.primitive || !bvh.convex(hit.primitive));
        let last = match k % 4 {
            0 => brute_force(&bvh, &ray, t_max).first().map_or(0, |h| h.primitive),
            1 => rng.range(0.0, primitives as f32) as u32,
            2 => hit.primitive,
            _ => primitives + k,
        };
        LAST_OCCLUDER.set(last);
        let got = bvh.any_hit_from(&ray, t_max, hit.primitive);
        assert_eq!(got, expected, "{ray:?} leaving {hit:?}, last occluder {last}");
        blocked += got as usize;
        answered_by_last += (got && LAST_OCCLUDER.get() == last && k % 4 == 0) as usize;
    }
    eprintln!("{blocked} shadow rays blocked, {answered_by_last} by the remembered primitive alone");
    assert!(
        blocked > 300 && answered_by_last > 100,
        "{blocked} {answered_by_last}"
    );
}
