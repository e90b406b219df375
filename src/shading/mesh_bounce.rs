//! The light the scene's meshes bounce onto the hair, under the fibres model (`render.hair_model = fibres`;
//! docs/truth.md, "The fibres model"). The path-traced truth lights the hair with the floor's and the head's
//! bounce as well as the light (on `default`, the side the camera sees takes most of its light from the floor);
//! the absorber model stands in for it with a constant ambient term. Here it is a light probe, as engines place
//! one for their hair: the mean radiance that reaches the hair from the lit meshes, over [`DIRECTIONS`]
//! directions from each of up to [`POINTS`] points spread over the strands. A ray that meets a mesh triangle
//! (either side) brings that point's Lambert radiance under the light, `albedo × light × max(n·l, 0)` (the
//! irradiance `π × light` times `albedo / π`, as `shaders/mesh.wgsl` and the path tracer light a mesh), the
//! light blocked by the meshes (a shadow ray; the hair's own shadow on them is left out); a ray that meets
//! none brings nothing (the scene has no environment light). The hair sends that radiance on times one
//! fibre's albedo `ā_f + ā_b` at right angles ([`hair_response`]): light arriving alike from every side leaves
//! a thin lock of fibres as it left the one fibre, forward and back (the truth's locks over a lit floor are
//! lit mostly through them); the hair's occlusion of its own inside is left out.

use glam::Vec3;

/// Strand points the probe averages over, at most.
pub const POINTS: usize = 256;
/// Directions per point (a Fibonacci sphere).
pub const DIRECTIONS: usize = 32;
/// Nodes a side of the probe's [`Grid`] over the strands' bounds.
pub const NODES: usize = 4;

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

/// The mean radiance the lit `triangles` send to `p` (linear RGB, per unit of the light's colour × intensity
/// as `light` gives it) over [`DIRECTIONS`] directions.
fn at_point(triangles: &[Triangle], p: Vec3, light: &impl Fn(Vec3) -> Arrival) -> Vec3 {
    let mut sum = Vec3::ZERO;
    {
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
    sum / DIRECTIONS as f32
}

/// The probe over the hair: [`NODES`]³ luminances on a lattice spanning the strands' bounds `min`..`max`, each
/// the mean of the points nearest to it (the mean of all where none is), read trilinearly ([`Grid::at`]; the
/// eye pass's `bounce_at` in `shaders/common/mesh_bounce.wgsl`, which `frame.bounce_*` carries).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub min: Vec3,
    pub max: Vec3,
    /// Node `(x, y, z)` at `(z · NODES + y) · NODES + x`.
    pub values: [f32; NODES * NODES * NODES],
}

impl Grid {
    /// The probe of `triangles` at up to [`POINTS`] of `points` (see [`spread`]) under `light`.
    pub fn measure(triangles: &[Triangle], points: &[Vec3], light: impl Fn(Vec3) -> Arrival) -> Grid {
        let (min, max) = points
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        let mut grid = Grid {
            min,
            max,
            values: [0.0; NODES * NODES * NODES],
        };
        let samples = spread(points);
        if samples.is_empty() || triangles.is_empty() {
            return Grid {
                min: Vec3::ZERO,
                max: Vec3::ONE,
                ..grid
            };
        }
        let mut sums = [(0.0f32, 0u32); NODES * NODES * NODES];
        for &p in &samples {
            let v = luminance(at_point(triangles, p, &light));
            let node = grid.nearest_node(p);
            sums[node].0 += v;
            sums[node].1 += 1;
        }
        let mean = sums.iter().map(|s| s.0).sum::<f32>() / samples.len() as f32;
        for (v, (sum, n)) in grid.values.iter_mut().zip(sums) {
            *v = if n > 0 { sum / n as f32 } else { mean };
        }
        grid
    }

    /// The lattice coordinate of `p`, clamped to `[0, NODES − 1]` per axis.
    fn lattice(&self, p: Vec3) -> Vec3 {
        let span = (self.max - self.min).max(Vec3::splat(1e-6));
        ((p - self.min) / span).clamp(Vec3::ZERO, Vec3::ONE) * (NODES - 1) as f32
    }

    fn nearest_node(&self, p: Vec3) -> usize {
        let t = self.lattice(p).round();
        ((t.z as usize * NODES) + t.y as usize) * NODES + t.x as usize
    }

    /// The luminance at `p`: trilinear between the nodes, the edge held beyond the bounds.
    pub fn at(&self, p: Vec3) -> f32 {
        let t = self.lattice(p);
        let cell = |x: f32| (x.floor() as usize).min(NODES - 2);
        let (i, j, k) = (cell(t.x), cell(t.y), cell(t.z));
        let f = t - Vec3::new(i as f32, j as f32, k as f32);
        let v = |x: usize, y: usize, z: usize| self.values[(z * NODES + y) * NODES + x];
        let lerp = |a: f32, b: f32, w: f32| a + (b - a) * w;
        let plane = |z: usize| {
            lerp(
                lerp(v(i, j, z), v(i + 1, j, z), f.x),
                lerp(v(i, j + 1, z), v(i + 1, j + 1, z), f.x),
                f.y,
            )
        };
        lerp(plane(k), plane(k + 1), f.z)
    }

    /// The grid as the frame uniforms carry it: `values` four to a vector.
    pub fn packed(&self) -> [[f32; 4]; NODES * NODES * NODES / 4] {
        std::array::from_fn(|q| std::array::from_fn(|c| self.values[4 * q + c]))
    }
}

/// What a hair point of colour `colour` sends to the eye per unit of the probe's radiance: the fibre's albedo
/// `ā_f + ā_b` at right angles to the light (`fibre_transport::attenuation`).
pub fn hair_response(colour: Vec3) -> Vec3 {
    let (f, b) = super::fibre_transport::attenuation(0.0, super::marschner::absorption(colour));
    f + b
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
    /// 32 directions); a grey floor scales it; a roof between the floor and the light leaves the floor dark and,
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
        let point = Vec3::new(0.0, 0.0, 1.0);
        let white = at_point(&floor(1.0, 0.0), point, &sun);
        assert!((white - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{white}");
        let grey = at_point(&floor(0.4, 0.0), point, &sun);
        assert!((grey - Vec3::splat(0.2)).abs().max_element() < 1e-6, "{grey}");
        let mut roofed = floor(1.0, 0.0).to_vec();
        roofed.extend(floor(1.0, 2.0));
        assert_eq!(at_point(&roofed, point, &sun), Vec3::ZERO);
        assert_eq!(at_point(&[], point, &sun), Vec3::ZERO);
    }

    /// The grid spans the points; points above a lit floor read 0.5 (half their sphere at radiance 1) at and
    /// between their nodes; with no mesh it reads zero; a ramp of node values is read linearly between nodes,
    /// its edges held beyond the bounds, and packed four to a vector.
    #[test]
    fn the_grid_keeps_where_the_light_comes_from() {
        let floor = |z: f32| {
            let s = 1e4;
            [
                Triangle {
                    a: Vec3::new(-s, -s, z),
                    b: Vec3::new(s, -s, z),
                    c: Vec3::new(-s, s, z),
                    albedo: Vec3::ONE,
                },
                Triangle {
                    a: Vec3::new(s, -s, z),
                    b: Vec3::new(s, s, z),
                    c: Vec3::new(-s, s, z),
                    albedo: Vec3::ONE,
                },
            ]
        };
        let points: Vec<Vec3> = (0..8)
            .map(|k| Vec3::new((k % 2) as f32, 0.0, 1.0 + (k / 2) as f32))
            .collect();
        let grid = Grid::measure(&floor(0.0), &points, sun);
        assert_eq!(
            (grid.min, grid.max),
            (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 4.0))
        );
        // Every point sees the floor over half its sphere: 0.5 everywhere.
        for p in &points {
            assert!((grid.at(*p) - 0.5).abs() < 1e-6, "{p}: {}", grid.at(*p));
        }
        let none = Grid::measure(&[], &points, sun);
        assert_eq!(none.at(Vec3::ZERO), 0.0);
        let mut ramp = grid;
        for (n, v) in ramp.values.iter_mut().enumerate() {
            *v = (n % NODES) as f32;
        }
        assert!((ramp.at(Vec3::new(0.5, 0.0, 2.0)) - 1.5).abs() < 1e-6);
        assert_eq!(ramp.at(Vec3::new(-3.0, 0.0, 2.0)), 0.0);
        assert_eq!(ramp.at(Vec3::new(7.0, 0.0, 2.0)), 3.0);
        assert_eq!(ramp.packed()[0], [0.0, 1.0, 2.0, 3.0]);
    }

    /// `spread` keeps at most [`POINTS`], from the whole list.
    #[test]
    fn spread_samples_the_whole_list() {
        let points: Vec<Vec3> = (0..10_000).map(|k| Vec3::splat(k as f32)).collect();
        let s = spread(&points);
        assert_eq!(s.len(), POINTS);
        assert_eq!(s[0], Vec3::ZERO);
        assert!(s[POINTS - 1].x > 9900.0);
        assert_eq!(spread(&points[..3]).len(), 3);
    }
}
