//! The light the scene's meshes bounce onto the hair, under the fibres model (`render.hair_model = fibres`;
//! docs/truth.md, "The fibres model"). The path-traced truth lights the hair with the floor's and the head's
//! bounce as well as the light (on `default`, the side the camera sees takes most of its light from the floor);
//! the absorber model stands in for it with a constant ambient term. Here it is a light probe, as engines place
//! one for their hair: the mean radiance that reaches the hair from the lit meshes, over [`DIRECTIONS`]
//! directions from each of up to [`POINTS`] points spread over the strands. A ray that meets a mesh triangle
//! (either side) brings that point's Lambert radiance under the light, `albedo × light × max(n·l, 0)` (the
//! irradiance `π × light` times `albedo / π`, as `shaders/mesh.wgsl` and the path tracer light a mesh), the
//! light blocked by the meshes (a shadow ray; the hair's own shadow on them is left out); a ray that meets
//! none brings nothing (the scene has no environment light). The hair sends `colour ×` that radiance back:
//! a volume of fibres whose multiply-scattered albedo is its colour (Chiang et al. 2016's colour inversion,
//! which the path tracer's fibre follows), lit alike from every side; the hair's occlusion of its own inside
//! is left out.

use glam::Vec3;

/// Strand points the probe averages over, at most.
pub const POINTS: usize = 32;
/// Directions per point (a Fibonacci sphere).
pub const DIRECTIONS: usize = 64;

/// A mesh triangle and its albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub a: Vec3,
    pub b: Vec3,
    pub c: Vec3,
    pub albedo: Vec3,
}

/// The light at a world point: the unit direction towards it, its distance (infinite for a directional
/// light) and the radiance it brings (`colour × intensity`, the spot's cone applied).
pub struct Arrival {
    pub to_light: Vec3,
    pub distance: f32,
    pub radiance: Vec3,
}

/// The `k`-th of `n` directions of a Fibonacci sphere.
fn fibonacci(k: usize, n: usize) -> Vec3 {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let z = 1.0 - (2.0 * k as f32 + 1.0) / n as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = golden * k as f32;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Distance along `dir` from `origin` to `t`, if the ray meets it in `(1e-5, max)` (Möller & Trumbore 1997).
fn hit(t: &Triangle, origin: Vec3, dir: Vec3, max: f32) -> Option<f32> {
    let (e1, e2) = (t.b - t.a, t.c - t.a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - t.a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let d = e2.dot(q) * inv;
    (d > 1e-5 && d < max).then_some(d)
}

/// The nearest triangle along the ray and its distance.
fn nearest(triangles: &[Triangle], origin: Vec3, dir: Vec3) -> Option<(&Triangle, f32)> {
    triangles
        .iter()
        .filter_map(|t| hit(t, origin, dir, f32::INFINITY).map(|d| (t, d)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Up to [`POINTS`] of `points`, evenly spaced through the list.
pub fn spread(points: &[Vec3]) -> Vec<Vec3> {
    let n = points.len().min(POINTS);
    (0..n).map(|k| points[k * points.len() / n]).collect()
}

/// The mean radiance the lit `triangles` send to `points` (linear RGB, per unit of the light's colour ×
/// intensity as `light` gives it), over [`DIRECTIONS`] directions a point; zero with no point or no triangle.
pub fn radiance(triangles: &[Triangle], points: &[Vec3], light: impl Fn(Vec3) -> Arrival) -> Vec3 {
    if points.is_empty() || triangles.is_empty() {
        return Vec3::ZERO;
    }
    let mut sum = Vec3::ZERO;
    for &p in points {
        for k in 0..DIRECTIONS {
            let dir = fibonacci(k, DIRECTIONS);
            let Some((t, d)) = nearest(triangles, p, dir) else {
                continue;
            };
            let at = p + dir * d;
            let mut n = (t.b - t.a).cross(t.c - t.a).normalize_or_zero();
            if n.dot(dir) > 0.0 {
                n = -n;
            }
            let l = light(at);
            let cos = n.dot(l.to_light);
            if cos <= 0.0 {
                continue;
            }
            let from = at + n * 1e-4;
            if triangles
                .iter()
                .any(|s| hit(s, from, l.to_light, l.distance).is_some())
            {
                continue;
            }
            sum += t.albedo * l.radiance * cos;
        }
    }
    sum / (points.len() * DIRECTIONS) as f32
}

/// Rec. 709 luminance of linear `c`: the probe's one value in the frame uniforms (`frame.hair_ambient`).
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sun(_: Vec3) -> Arrival {
        Arrival {
            to_light: Vec3::Z,
            distance: f32::INFINITY,
            radiance: Vec3::ONE,
        }
    }

    /// A point above an infinite-like white floor lit straight from above sees the floor over half its sphere
    /// at radiance 1 (albedo 1 × light 1 × cos 1): a mean of 1/2 (the Fibonacci sphere's half, exactly 32 of
    /// 64 directions); a grey floor scales it; a roof between the floor and the light leaves the floor dark and,
    /// lit from above with its underside away from the light, sends nothing either.
    #[test]
    fn a_lit_floor_fills_half_the_sphere() {
        let floor = |albedo: f32, z: f32| {
            let s = 1e4;
            [
                Triangle {
                    a: Vec3::new(-s, -s, z),
                    b: Vec3::new(s, -s, z),
                    c: Vec3::new(-s, s, z),
                    albedo: Vec3::splat(albedo),
                },
                Triangle {
                    a: Vec3::new(s, -s, z),
                    b: Vec3::new(s, s, z),
                    c: Vec3::new(-s, s, z),
                    albedo: Vec3::splat(albedo),
                },
            ]
        };
        let point = [Vec3::new(0.0, 0.0, 1.0)];
        let white = radiance(&floor(1.0, 0.0), &point, sun);
        assert!((white - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{white}");
        let grey = radiance(&floor(0.4, 0.0), &point, sun);
        assert!((grey - Vec3::splat(0.2)).abs().max_element() < 1e-6, "{grey}");
        let mut roofed = floor(1.0, 0.0).to_vec();
        roofed.extend(floor(1.0, 2.0));
        assert_eq!(radiance(&roofed, &point, sun), Vec3::ZERO);
        assert_eq!(radiance(&[], &point, sun), Vec3::ZERO);
    }

    /// `spread` keeps at most [`POINTS`], from the whole list.
    #[test]
    fn spread_samples_the_whole_list() {
        let points: Vec<Vec3> = (0..1000).map(|k| Vec3::splat(k as f32)).collect();
        let s = spread(&points);
        assert_eq!(s.len(), POINTS);
        assert_eq!(s[0], Vec3::ZERO);
        assert!(s[POINTS - 1].x > 900.0);
        assert_eq!(spread(&points[..3]).len(), 3);
    }
}
