//! Round fibres for the path-traced reference: each strand segment is a cone between its two points whose radius
//! runs linearly from one end's to the other's, closed by the end spheres, as Embree's (and Mitsuba 3's) "round
//! linear curves". A segment owns the part of its end spheres beyond its end planes, so two segments meeting at a
//! vertex are joined by that vertex's sphere without gaps, and the solid of a segment is exactly the points whose
//! distance to the segment is below the radius at the nearest point of the segment (what the test solves by
//! brute force). The root finding runs in f64 about the ray's closest approach, so hair-thin radii far from the
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
    pub segment: u32,
    /// What was hit.
    pub surface: Surface,
}

/// The surface a ray met: a fibre (Chiang et al.'s BSDF) or a mesh triangle (Lambertian, seen from both sides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    Fibre,
    Mesh { albedo: Vec3 },
}

/// The segments of `strands`, strand after strand (segment `i` of the result is the `i`-th of
/// [`Strands::segment_count`]). A point's width is `width` times its thickness (1 without a thickness array), as
/// the rasteriser reads `render.strand_width`; the radius is half the width.
pub fn segments(strands: &Strands, width: f32) -> Vec<Segment> {
    let radius = |i: usize| 0.5 * width * strands.thickness.as_ref().map_or(1.0, |t| t[i]);
    let mut out = Vec::with_capacity(strands.segment_count());
    for (first, count) in strands.ranges() {
        for i in first..(first + count).saturating_sub(1) {
            out.push(Segment {
                a: strands.points[i],
                b: strands.points[i + 1],
                ra: radius(i),
                rb: radius(i + 1),
            });
        }
    }
    out
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
        let mut best: Option<(f64, DVec3)> = None;
        let mut consider = |t: f64, n: DVec3| {
            if t > lo && t < hi && n.dot(d) < 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, n));
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
                    consider(t, (w - r * g * u).normalize());
                }
            }
        }
        for (c, r, beyond) in [(a, ra, -1.0), (b, rb, 1.0)] {
            let q = o - c;
            let hb = q.dot(d);
            for t in roots(d.dot(d), hb, q.dot(q) - r * r) {
                let x = along(t);
                let owned = len == 0.0 || (beyond < 0.0 && x < 0.0) || (beyond > 0.0 && x > len);
                if t.is_finite() && owned {
                    consider(t, (q + t * d) / r);
                }
            }
        }
        let (t, n) = best?;
        let t = (t0 + t) as f32;
        let (tangent, normal) = (u.as_vec3(), n.as_vec3().normalize());
        let across = tangent.cross(ray.dir).normalize_or_zero();
        let n_perp = (normal - normal.dot(tangent) * tangent).normalize_or_zero();
        Some(Hit {
            t,
            point: ray.at(t),
            tangent,
            normal,
            h: n_perp.dot(across).clamp(-1.0, 1.0),
            segment: 0,
            surface: Surface::Fibre,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// Distance from `p` to the segment less the radius at the segment's nearest point: negative inside.
    pub(crate) fn field(s: &Segment, p: Vec3) -> f64 {
        let (a, b, p) = (s.a.as_dvec3(), s.b.as_dvec3(), p.as_dvec3());
        let ab = b - a;
        let x = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (a + x * ab)).length() - (s.ra as f64 + x * (s.rb - s.ra) as f64)
    }

    pub(crate) fn random_segment(rng: &mut SplitMix64) -> Segment {
        let mut v = || Vec3::new(rng.normal(), rng.normal(), rng.normal());
        let a = v() * 0.5;
        let b = a + v() * 0.4;
        Segment {
            a,
            b,
            ra: rng.range(0.02, 0.2),
            rb: rng.range(0.02, 0.2),
        }
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

    #[test]
    fn h_runs_across_a_cylinder() {
        let s = Segment {
            a: Vec3::new(-1.0, 0.0, 0.0),
            b: Vec3::new(1.0, 0.0, 0.0),
            ra: 0.5,
            rb: 0.5,
        };
        for y in [-0.4f32, 0.0, 0.25] {
            let hit = s
                .intersect(&Ray::new(Vec3::new(0.0, y, 5.0), -Vec3::Z), 0.0, 10.0)
                .unwrap();
            assert!((hit.h.abs() - y.abs() / 0.5).abs() < 1e-5, "{y}: {}", hit.h);
            assert!((hit.t - (5.0 - (0.25 - y * y).sqrt())).abs() < 1e-5);
        }
    }
}
