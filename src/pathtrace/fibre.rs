//! Round fibres for the path-traced reference: each strand segment is a cone between its two points whose radius
//! runs linearly from one end's to the other's, closed by the end spheres, as Embree's (and Mitsuba 3's) "round
//! linear curves". A segment's solid is the points whose distance to the segment is below the radius at the
//! nearest point of the segment (what the tests solve by brute force); a strand is the union of its segments'
//! solids, so a crossing of one segment's surface inside a neighbour's solid (the joint sphere where the strand
//! runs on, a cone's wall on the inside of a bend) is not a crossing of the strand and is not reported. The root finding runs in f64 about the ray's closest approach, so hair-thin radii far from the
//! origin keep their precision. Only crossings into a fibre count, as in Embree and Mitsuba 3, which cull curve
//! back faces: a ray leaving a fibre's surface inwards passes out of it (the BSDF stands for the walk inside).

use glam::{DVec3, Vec3};

use crate::scene::{Aabb, Strands};

/// A ray: `dir` is unit length, so `t` is a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    /// The ray from `origin` along `dir` (normalised here).
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir: dir.normalize(),
        }
    }
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// One round fibre segment from `a` (radius `ra`) to `b` (radius `rb`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub a: Vec3,
    pub b: Vec3,
    pub ra: f32,
    pub rb: f32,
    /// The strand's point before `a` and its radius (`None` where the strand starts).
    pub prev: Option<(Vec3, f32)>,
    /// The strand's point after `b` and its radius (`None` where the strand ends).
    pub next: Option<(Vec3, f32)>,
}

/// Distance from `p` to the segment `a`–`b` less the radius at the segment's nearest point: negative inside.
fn field(a: DVec3, b: DVec3, ra: f64, rb: f64, p: DVec3) -> f64 {
    let ab = b - a;
    let x = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + x * ab)).length() - (ra + x * (rb - ra))
}

/// A ray's crossing of a fibre surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    pub point: Vec3,
    /// Unit fibre tangent, `a` to `b` (the BSDF frame's x).
    pub tangent: Vec3,
    /// Unit outward surface normal.
    pub normal: Vec3,
    /// Signed offset of the ray across the fibre in [-1, 1] (pbrt's curve `h`, the BSDF's azimuthal parameter):
    /// the normal's part across the tangent, along `normalize(tangent × dir)`.
    pub h: f32,
    /// Index of the primitive (the segment, or the triangle after the segments) in the hierarchy it came from.
    pub primitive: u32,
    /// The fibre's radius at the hit (0 on a triangle): what [`Hit::offset`] takes a fraction of.
    pub radius: f32,
    /// What was hit.
    pub surface: Surface,
}

/// A ray leaving a fibre starts this fraction of the fibre's radius off its surface ([`Hit::offset`]).
const OFFSET_OF_RADIUS: f32 = 1e-3;
/// ... but no less than this many `f32` epsilons of the hit point's largest coordinate: the point is rounded to
/// `f32` once (half an ulp a coordinate), and so is the offset point (half an ulp more), under a unit error each
/// of `|p| · ε`; four keep the ray's origin on its side of the surface with room to spare.
const OFFSET_ULPS: f32 = 4.0;

impl Hit {
    /// How far off the surface, along the normal to the side it leaves by, a ray leaving this hit starts: on a
    /// fibre [`OFFSET_OF_RADIUS`] of its radius, at least [`OFFSET_ULPS`] `f32` epsilons of `|p|` (hair-thin
    /// fibres far from the origin: a fixed offset there would jump past the fibre, or past its neighbours); on a
    /// triangle `10⁻⁵ · (1 + |p|)`.
    pub fn offset(&self) -> f32 {
        let scale = self.point.abs().max_element();
        match self.surface {
            Surface::Fibre => (OFFSET_OF_RADIUS * self.radius).max(OFFSET_ULPS * f32::EPSILON * scale),
            Surface::Mesh { .. } => 1e-5 * (1.0 + scale),
        }
    }
}

/// The surface a ray met: a fibre (Chiang et al.'s BSDF) or a mesh triangle (Lambertian, seen from both sides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    Fibre,
    Mesh { albedo: Vec3 },
}

/// The radius of `strands`' point `i` under `render.strand_width = width`: half its width, `width` times its
/// thickness (1 without a thickness array), as the rasteriser reads it; the Mitsuba export writes it too.
pub fn radius(strands: &Strands, width: f32, i: usize) -> f32 {
    0.5 * width * strands.thickness.as_ref().map_or(1.0, |t| t[i])
}

/// The segments of `strands`, strand after strand (segment `i` of the result is the `i`-th of
/// [`Strands::segment_count`]), each point's radius [`radius`].
pub fn segments(strands: &Strands, width: f32) -> Vec<Segment> {
    segments_of(&strands.points, strands.ranges(), |i| radius(strands, width, i))
}

/// The segments of the polylines `ranges` (first point, point count) over `points`, strand after strand, point
/// `i`'s radius `radius(i)`: [`segments`] for strands held otherwise (the renderer's vertices).
pub fn segments_of(
    points: &[Vec3],
    ranges: impl Iterator<Item = (usize, usize)>,
    radius: impl Fn(usize) -> f32,
) -> Vec<Segment> {
    let mut out = Vec::new();
    for (first, count) in ranges {
        let last = (first + count).saturating_sub(1);
        for i in first..last {
            out.push(Segment {
                prev: (i > first).then(|| (points[i - 1], radius(i - 1))),
                next: (i + 1 < last).then(|| (points[i + 2], radius(i + 2))),
                ..Segment::new(points[i], points[i + 1], radius(i), radius(i + 1))
            });
        }
    }
    out
}

/// Whether the ray misses a segment `a`–`b` of radius at most `r` within `(0, t_max)`: [`misses_axis`] of
/// `b − a`. Never for `a = b`.
pub fn misses_line(a: Vec3, b: Vec3, r: f32, ray: &Ray, t_max: f32) -> bool {
    misses_axis(a, b - a, r, ray, t_max)
}

/// Whether the ray misses, within `(0, t_max)`, every point within `r` of the segment from `a` along `axis`
/// (`b − a`), which holds a segment of radius at most `r`: its line passes farther than `r` from the axis's line
/// (compared squared, no square root), or the stretch of the ray within `r` of that line lies beyond the
/// segment's ends along the axis (grown by `r`) or outside `(0, t_max)`. A bound, so it never drops a crossing:
/// the stretch is taken within 1.01 `r` and every comparison has a margin for `f32` rounding, which grows as
/// the ray turns parallel to the axis (where the stretch's ends are ill-conditioned) until nothing but the
/// distance is tested. Never for `a = b`.
#[inline(always)]
pub fn misses_axis(a: Vec3, axis: Vec3, r: f32, ray: &Ray, t_max: f32) -> bool {
    let w = ray.origin - a;
    let normal = ray.dir.cross(axis);
    let scale = 1.0 + w.abs().max_element() + axis.abs().max_element();
    let (n2, c) = (normal.length_squared(), axis.length_squared());
    if n2 <= 1e-12 * c {
        return false;
    }
    let reach = r + 1e-5 * scale;
    let distance = w.dot(normal);
    if distance * distance > reach * reach * n2 {
        return true;
    }
    // The ray's closest approach to the axis's line, `s` in units of `axis` from `a`, `t` along the ray; the
    // stretch within `1.01 reach` of the line is `t ± dt` (`n2 = c sin²θ`), `s ± ds` along the axis.
    let (b, dw, aw) = (ray.dir.dot(axis), ray.dir.dot(w), axis.dot(w));
    let s = (aw - b * dw) / n2;
    let t = s * b - dw;
    let wide = 1.01 * reach;
    let dt = ((wide * wide * n2 - distance * distance) * c).sqrt() / n2;
    let ds = dt * b.abs() / c;
    let margin = 1e-5 * scale * c / n2;
    let pad = (reach + margin) / c.sqrt();
    s + ds < -pad || s - ds > 1.0 + pad || t + dt < -margin || t - dt > t_max + margin
}

/// The roots of `a t² + 2 hb t + c` (stable form; a linear equation when `a` is 0), non-finite ones dropped.
fn roots(a: f64, hb: f64, c: f64) -> [f64; 2] {
    let disc = hb * hb - a * c;
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    let q = -(hb + hb.signum() * disc.sqrt());
    [q / a, c / q]
}

impl Segment {
    /// A lone segment: a strand of its own, capped at both ends.
    pub fn new(a: Vec3, b: Vec3, ra: f32, rb: f32) -> Segment {
        Segment {
            a,
            b,
            ra,
            rb,
            prev: None,
            next: None,
        }
    }

    /// The box around both end spheres, which holds the whole segment.
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: (self.a - self.ra).min(self.b - self.rb),
            max: (self.a + self.ra).max(self.b + self.rb),
        }
    }

    /// The nearest crossing into this segment with `t` in `(t_min, t_max)` (back faces culled); `segment` is
    /// set to 0.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        if misses_line(self.a, self.b, self.ra.max(self.rb), ray, t_max) {
            return None;
        }
        self.crossing(ray, t_min, t_max)
    }

    /// [`Self::intersect`] for a ray that [`misses_line`] has not ruled out.
    pub(crate) fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let d = ray.dir.as_dvec3();
        let (a, b) = (self.a.as_dvec3(), self.b.as_dvec3());
        let (ra, rb) = (self.ra as f64, self.rb as f64);
        // Solve about the ray's closest approach to the segment's middle.
        let t0 = (0.5 * (a + b) - ray.origin.as_dvec3()).dot(d);
        let o = ray.origin.as_dvec3() + t0 * d;
        let (lo, hi) = (t_min as f64 - t0, t_max as f64 - t0);
        let axis = b - a;
        let len = axis.length();
        let u = if len > 0.0 { axis / len } else { DVec3::X };
        // A point inside a neighbouring segment's solid is inside the strand (a relative margin keeps the seams
        // where two surfaces meet).
        let inside_neighbour = |p: DVec3| {
            [(self.prev, self.a, self.ra), (self.next, self.b, self.rb)]
                .into_iter()
                .any(|(n, c, r)| {
                    n.is_some_and(|(q, rq)| {
                        let (rq, rc) = (rq as f64, r as f64);
                        field(q.as_dvec3(), c.as_dvec3(), rq, rc, p) < -1e-4 * rq.min(rc)
                    })
                })
        };
        // (t, normal, radius) of the crossings into a surface within the range, in the order found.
        let mut found = [(f64::INFINITY, DVec3::ZERO, 0.0); 6];
        let mut count = 0;
        let mut consider = |t: f64, n: DVec3, r: f64| {
            if t > lo && t < hi && n.dot(d) < 0.0 {
                found[count] = (t, n, r);
                count += 1;
            }
        };
        // Position along the axis of the point at `t`.
        let along = |t: f64| (o + t * d - a).dot(u);
        if len > 0.0 {
            let g = (rb - ra) / len;
            let q = o - a;
            let (qu, du) = (q.dot(u), d.dot(u));
            let (qp, dp) = (q - qu * u, d - du * u);
            let r0 = ra + g * qu;
            let qa = dp.dot(dp) - g * g * du * du;
            let hb = qp.dot(dp) - r0 * g * du;
            let c = qp.dot(qp) - r0 * r0;
            for t in roots(qa, hb, c) {
                let x = qu + t * du;
                let r = ra + g * x;
                if t.is_finite() && (0.0..=len).contains(&x) && r > 0.0 {
                    let w = q + t * d - x * u;
                    consider(t, (w - r * g * u).normalize(), r);
                }
            }
        }
        // The sphere at `b` is the next segment's sphere at its `a`, which that segment tests: where the strand
        // runs on no thinner, what it owns beyond `b` is that segment's sphere or inside its solid.
        let next_covers_b = self.next.is_some_and(|(_, r)| r >= self.rb);
        for (c, r, beyond) in [(a, ra, -1.0), (b, rb, 1.0)] {
            if beyond > 0.0 && next_covers_b {
                continue;
            }
            let q = o - c;
            let hb = q.dot(d);
            for t in roots(d.dot(d), hb, q.dot(q) - r * r) {
                let x = along(t);
                let owned = len == 0.0 || (beyond < 0.0 && x < 0.0) || (beyond > 0.0 && x > len);
                if t.is_finite() && owned {
                    consider(t, (q + t * d) / r, r);
                }
            }
        }
        // The nearest (the first found of equals) outside the neighbours; each is tested only when it is nearest.
        let (t_near, n, r) = loop {
            let mut k = 0;
            for j in 1..count {
                if found[j].0 < found[k].0 {
                    k = j;
                }
            }
            if count == 0 || found[k].0 == f64::INFINITY {
                return None;
            }
            if !inside_neighbour(o + found[k].0 * d) {
                break found[k];
            }
            found[k].0 = f64::INFINITY;
        };
        let t = (t0 + t_near) as f32;
        let (tangent, normal) = (u.as_vec3(), n.as_vec3().normalize());
        let across = tangent.cross(ray.dir).normalize_or_zero();
        let n_perp = (normal - normal.dot(tangent) * tangent).normalize_or_zero();
        Some(Hit {
            t,
            // In f64 from the closest approach: rounded once to f32, where `ray.at(t)` rounds `t · dir` and the
            // sum, with errors of the origin's size rather than the point's.
            point: (o + t_near * d).as_vec3(),
            tangent,
            normal,
            h: n_perp.dot(across).clamp(-1.0, 1.0),
            primitive: 0,
            radius: r as f32,
            surface: Surface::Fibre,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// [`super::field`] of a segment at `p`.
    pub(crate) fn field(s: &Segment, p: Vec3) -> f64 {
        super::field(
            s.a.as_dvec3(),
            s.b.as_dvec3(),
            s.ra as f64,
            s.rb as f64,
            p.as_dvec3(),
        )
    }

    pub(crate) fn random_segment(rng: &mut SplitMix64) -> Segment {
        let mut v = || Vec3::new(rng.normal(), rng.normal(), rng.normal());
        let a = v() * 0.5;
        let b = a + v() * 0.4;
        Segment::new(a, b, rng.range(0.02, 0.2), rng.range(0.02, 0.2))
    }

    /// Brute force against the analytic solve: a march of `STEP` along each ray with the distance field, the first
    /// step inside refined by bisection. Grazing rays, whose least field value on the march lies within
    /// `GRAZE` of 0 (the march cannot tell a shallow dip from a near miss), are left out.
    #[test]
    fn intersection_matches_a_marched_brute_force() {
        const STEP: f64 = 1e-3;
        const GRAZE: f64 = 2e-3;
        const T_MAX: f64 = 4.0;
        let mut rng = SplitMix64::new(33);
        let (mut hits, mut misses, mut grazing, mut max_err) = (0, 0, 0, 0.0f64);
        for _ in 0..1500 {
            let s = random_segment(&mut rng);
            let target =
                s.a.lerp(s.b, rng.unit()) + 0.15 * Vec3::new(rng.normal(), rng.normal(), rng.normal());
            let dir = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
            let ray = Ray::new(target - 2.0 * dir, dir);
            let f = |t: f64| field(&s, ray.origin + t as f32 * ray.dir);
            if f(0.0) < GRAZE {
                continue;
            }
            let (mut least, mut entry) = (f64::MAX, None);
            let n = (T_MAX / STEP) as usize;
            for i in 1..=n {
                let t = i as f64 * STEP;
                let v = f(t);
                least = least.min(v);
                if v < 0.0 && entry.is_none() {
                    let (mut lo, mut hi) = (t - STEP, t);
                    for _ in 0..40 {
                        let mid = 0.5 * (lo + hi);
                        if f(mid) < 0.0 { hi = mid } else { lo = mid }
                    }
                    entry = Some(0.5 * (lo + hi));
                }
            }
            if least.abs() < GRAZE {
                grazing += 1;
                continue;
            }
            let hit = s.intersect(&ray, 0.0, T_MAX as f32);
            assert_eq!(hit.is_some(), entry.is_some(), "{s:?} {ray:?}");
            if let (Some(h), Some(e)) = (hit, entry) {
                hits += 1;
                max_err = max_err.max((h.t as f64 - e).abs());
                assert!((h.normal.length() - 1.0).abs() < 1e-4 && (-1.0..=1.0).contains(&h.h));
                assert!(field(&s, h.point).abs() < 1e-4, "hit point off the surface");
            } else {
                misses += 1;
            }
        }
        eprintln!("fibre: {hits} hits, {misses} misses, {grazing} grazing left out, max |Δt| {max_err:.2e}");
        assert!(hits > 300 && misses > 300, "{hits} hits, {misses} misses");
        assert!(max_err < 1e-4, "max |Δt| {max_err}");
    }

    /// A strand bent at its joints is one closed surface: a ray from outside first meets it where a march of the
    /// union's distance field first goes inside (no gap at a joint), and a ray from inside meets nothing before it
    /// leaves (no joint sphere or cone wall left inside the strand).
    #[test]
    fn a_strand_of_segments_is_one_closed_surface() {
        const STEP: f64 = 1e-3;
        const GRAZE: f64 = 2e-3;
        let mut rng = SplitMix64::new(7);
        let (mut hits, mut inside_rays) = (0, 0);
        for _ in 0..200 {
            // Bends of up to 30° between segments 0.3 to 0.6 long, 0.2 wide (sharper folds let non-neighbouring
            // segments overlap, which strands of hair do not do).
            let (mut points, mut dir) = (vec![Vec3::ZERO], Vec3::X);
            for _ in 0..3 {
                let turn = Vec3::new(rng.normal(), rng.normal(), rng.normal())
                    .reject_from(dir)
                    .normalize();
                let angle = rng.range(0.0, 30f32.to_radians());
                dir = (dir * angle.cos() + turn * angle.sin()).normalize();
                points.push(*points.last().unwrap() + dir * rng.range(0.3, 0.6));
            }
            let strands = Strands {
                counts: vec![points.len() as u32],
                points,
                ..Strands::default()
            };
            let segs = segments(&strands, 0.2);
            let union = |p: Vec3| segs.iter().map(|s| field(s, p)).fold(f64::MAX, f64::min);
            let first = |ray: &Ray| {
                segs.iter()
                    .filter_map(|s| s.intersect(ray, 0.0, 4.0))
                    .map(|h| h.t)
                    .reduce(f32::min)
            };
            for _ in 0..10 {
                let target = strands.points[1 + (rng.unit() * 2.0) as usize]
                    + 0.12 * Vec3::new(rng.normal(), rng.normal(), rng.normal());
                let dir = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
                if union(target) < -GRAZE {
                    inside_rays += 1;
                    let ray = Ray::new(target, dir);
                    let t_out = (1..4000)
                        .map(|i| i as f64 * STEP)
                        .find(|&t| union(ray.at(t as f32)) > 0.0);
                    let hit = first(&ray);
                    assert!(
                        hit.is_none_or(|t| t as f64 > t_out.unwrap() - STEP),
                        "a surface inside the strand at {hit:?}, the ray leaves at {t_out:?}"
                    );
                    continue;
                }
                let ray = Ray::new(target - 2.0 * dir, dir);
                let march: Vec<f64> = (0..4000)
                    .map(|i| union(ray.at((i as f64 * STEP) as f32)))
                    .collect();
                let least = march.iter().copied().fold(f64::MAX, f64::min);
                if march[0] < GRAZE || least.abs() < GRAZE {
                    continue;
                }
                let entry = march.iter().position(|&v| v < 0.0).map(|i| i as f64 * STEP);
                let hit = first(&ray);
                assert_eq!(hit.is_some(), entry.is_some(), "{ray:?}");
                if let (Some(h), Some(e)) = (hit, entry) {
                    assert!((h as f64 - e).abs() <= STEP, "entry at {h}, march {e}");
                    hits += 1;
                }
            }
        }
        assert!(
            hits > 300 && inside_rays > 100,
            "{hits} hits, {inside_rays} rays from inside"
        );
    }

    /// [`misses_axis`] is a bound: over random segments (thick ones near the origin, hair-thin ones 100 units
    /// off) and rays aimed about them (a fifth within a degree of the axis; `t_max` endless, or short of the
    /// segment or past it) it never rules out a crossing the exact solve finds, and it rules out most of the
    /// solve's misses.
    #[test]
    fn the_miss_test_never_drops_a_crossing() {
        let mut rng = SplitMix64::new(91);
        let (mut crossings, mut misses, mut ruled_out) = (0, 0, 0);
        for k in 0..20_000 {
            let mut s = random_segment(&mut rng);
            if k % 2 == 1 {
                let off = Vec3::splat(100.0);
                s = Segment::new(0.01 * s.a + off, 0.01 * s.b + off, 1e-3 * s.ra, 1e-3 * s.rb);
            }
            let (r, len) = (s.ra.max(s.rb), (s.b - s.a).length());
            let mut v = || Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
            let (across, random) = (v(), v());
            let target = s.a.lerp(s.b, rng.range(-0.3, 1.3)) + 1.5 * r * rng.unit() * across;
            let dir = if k % 5 == 0 {
                ((s.b - s.a).normalize() + 0.015 * random).normalize()
            } else {
                random
            };
            let back = rng.range(0.0, 3.0) * (len + r);
            let ray = Ray::new(target - back * dir, dir);
            let t_max = if k % 3 == 0 {
                f32::INFINITY
            } else {
                rng.range(0.0, 2.0) * back
            };
            let bound = misses_axis(s.a, s.b - s.a, r, &ray, t_max);
            if let Some(hit) = s.crossing(&ray, 0.0, t_max) {
                crossings += 1;
                assert!(
                    !bound,
                    "{s:?} {ray:?} t_max {t_max}: the crossing at {} ruled out",
                    hit.t
                );
            } else {
                misses += 1;
                ruled_out += bound as u32;
            }
        }
        eprintln!("{crossings} crossings, {misses} misses: {ruled_out} ruled out");
        assert!(
            crossings > 4_000 && 2 * ruled_out > misses,
            "{crossings} crossings, {ruled_out} of {misses}"
        );
    }

    #[test]
    fn h_runs_across_a_cylinder() {
        let s = Segment::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.5, 0.5);
        for y in [-0.4f32, 0.0, 0.25] {
            let hit = s
                .intersect(&Ray::new(Vec3::new(0.0, y, 5.0), -Vec3::Z), 0.0, 10.0)
                .unwrap();
            assert!((hit.h.abs() - y.abs() / 0.5).abs() < 1e-5, "{y}: {}", hit.h);
            assert!((hit.t - (5.0 - (0.25 - y * y).sqrt())).abs() < 1e-5);
        }
    }
}
