//! The path tracer's numerics on hair-thin fibres far from the origin: a ray leaving a hit starts a small
//! fraction of the fibre's radius off it, on the side it leaves by, and never meets its own fibre again.

use glam::Vec3;
use hairlab::pathtrace::bvh::Bvh;
use hairlab::pathtrace::fibre::{Ray, Segment};
use hairlab::rng::SplitMix64;

/// Distance from `p` to the segment less its radius there, in f64: negative inside.
fn field(s: &Segment, p: Vec3) -> f64 {
    let (a, b, p) = (s.a.as_dvec3(), s.b.as_dvec3(), p.as_dvec3());
    let ab = b - a;
    let x = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (p - (a + x * ab)).length() - (s.ra as f64 + x * (s.rb - s.ra) as f64)
}

fn unit(rng: &mut SplitMix64) -> Vec3 {
    Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize()
}

/// Fibres 10⁻⁴ in radius, 1 mm long, 5 to 8 units from the origin on every axis (where an `f32` step is
/// 5 × 10⁻⁷), each alone: rays at random points of them hit, and from each hit a ray towards a random direction
/// on either side (towards a light, or a sampled bounce into the fibre) starts within r/10 of the surface, outside
/// the fibre when it leaves outwards and inside when it enters, and meets no fibre (back faces are culled, so
/// an entering ray passes out). Measured: offsets 2.7 × 10⁻⁶ to 3.8 × 10⁻⁶ (r/37 to r/26).
#[test]
fn a_ray_leaving_a_thin_fibre_far_out_starts_just_off_it_and_misses_it() {
    let mut rng = SplitMix64::new(43);
    let r = 1e-4f32;
    let segments: Vec<Segment> = (0..50)
        .map(|_| {
            let c = Vec3::new(rng.range(5.0, 8.0), -rng.range(5.0, 8.0), rng.range(5.0, 8.0));
            let half = unit(&mut rng) * 5e-4;
            Segment::new(c - half, c + half, r, r * rng.range(0.7, 1.0))
        })
        .collect();
    let bvh = Bvh::new(segments.clone());
    let (mut hits, mut outwards, mut inwards) = (0, 0, 0);
    let (mut least, mut most) = (f32::MAX, 0.0f32);
    for _ in 0..4000 {
        let s = &segments[(rng.unit() * segments.len() as f32) as usize % segments.len()];
        let dir = unit(&mut rng);
        let target = s.a.lerp(s.b, rng.unit()) + unit(&mut rng) * r * 0.9 * rng.unit();
        let Some(hit) = bvh.closest_hit(&Ray::new(target - 0.01 * dir, dir), f32::INFINITY) else {
            continue;
        };
        hits += 1;
        let own = &segments[hit.primitive as usize];
        let offset = hit.offset();
        assert!(offset > 0.0 && offset < 0.1 * r, "offset {offset} for radius {r}");
        (least, most) = (least.min(offset), most.max(offset));
        for _ in 0..4 {
            let w = unit(&mut rng);
            let side = hit.normal.dot(w).signum();
            // Where the integrator's `leave` starts the ray.
            let origin = hit.point + offset * side * hit.normal;
            let f = field(own, origin);
            assert!(
                f * side as f64 > 0.0,
                "the ray along {w} starts at {f:e} from the surface, on the wrong side"
            );
            let again = bvh.closest_hit(&Ray::new(origin, w), f32::INFINITY);
            assert!(again.is_none(), "a ray leaving {hit:?} along {w} meets {again:?}");
            if side > 0.0 { outwards += 1 } else { inwards += 1 }
        }
    }
    eprintln!(
        "{hits} hits, {outwards} rays out and {inwards} in; offsets {least:e} to {most:e} (r/{:.0} to r/{:.0})",
        r / least,
        r / most
    );
    assert!(
        hits > 3000 && outwards > 5000 && inwards > 5000,
        "{hits} hits, {outwards} out, {inwards} in"
    );
}
