//! The light the scene's meshes bounce onto the hair, under the fibres model (`render.hair_model = fibres`;
//! docs/truth.md, "The fibres model"). The path-traced truth lights the hair with the floor's and the head's
//! bounce as well as the light (on `default`, the side the camera sees takes most of its light from the floor);
//! the absorber model stands in for it with a constant ambient term. Here it is a light probe, as engines place
//! one for their hair: the mean radiance that reaches the hair from the lit meshes, over [`DIRECTIONS`]
//! directions from each of up to [`POINTS`] points spread over the strands. A ray that meets a mesh triangle
//! (either side) brings that point's Lambert radiance under the light, `albedo × light × max(n·l, 0)` (the
//! irradiance `π × light` times `albedo / π`, as `shaders/mesh.wgsl` and the path tracer light a mesh), the
//! light blocked by the meshes (a shadow ray) and by the hair in front of the mesh towards the light, which
//! passes `max(e^(−n), T_f)` of it through `n` fibres as the eye pass lights a mesh under the hair
//! ([`fibre_transport::arriving`] at right angles; the count from a voxel density of the strands,
//! [`HairDensity`]): a scalp under a dark lock sends next to nothing, one under a blond lock the light its
//! fibres pass on. A ray that meets no mesh brings nothing (the scene has no environment light). The hair
//! sends what arrives on times one fibre's albedo `ā_f + ā_b` at right angles ([`hair_response`]): light
//! arriving alike from every side leaves a fibre as it left the one fibre, forward and back. Left out: the
//! hair between the mesh and the strand point (on the lattice the probe's nodes average the inside of a lock
//! with its surface, which the eye sees: docs/truth.md), and the light the hair scatters onto the meshes.

use glam::Vec3;

use super::fibre_transport;
use super::hair_density::HairDensity;

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

/// The hair the probe's light crosses: its density and its fibres' absorption `σ_a`.
pub struct Hair<'a> {
    pub density: &'a HairDensity,
    pub sigma_a: Vec3,
}

/// The mean radiance the lit `triangles` send to `p` through `hair` (linear RGB, per unit of the light's
/// colour × intensity as `light` gives it) over [`DIRECTIONS`] directions.
fn at_point(triangles: &[Triangle], hair: &Hair, p: Vec3, light: &impl Fn(Vec3) -> Arrival) -> Vec3 {
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
            let towards_light = hair.density.crossed(at, l.to_light, l.distance);
            let lit = fibre_transport::arriving((-towards_light).exp(), 0.0, hair.sigma_a, towards_light);
            sum += t.albedo * l.radiance * cos * lit;
        }
    }
    sum / DIRECTIONS as f32
}

/// The probe over the hair: [`NODES`]³ radiances (linear RGB) on a lattice spanning the strands' bounds
/// `min`..`max`, each the mean of the points nearest to it (the mean of all where none is), read trilinearly
/// ([`Grid::at`]; the eye pass's `bounce_at` in `shaders/common/mesh_bounce.wgsl`, which `frame.bounce_*`
/// carries).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub min: Vec3,
    pub max: Vec3,
    /// Node `(x, y, z)` at `(z · NODES + y) · NODES + x`.
    pub values: [Vec3; NODES * NODES * NODES],
}

impl Grid {
    /// The probe of `triangles` through `hair` at up to [`POINTS`] of `points` (see [`spread`]) under `light`.
    pub fn measure(
        triangles: &[Triangle],
        hair: &Hair,
        points: &[Vec3],
        light: impl Fn(Vec3) -> Arrival,
    ) -> Grid {
        let (min, max) = points
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        let mut grid = Grid {
            min,
            max,
            values: [Vec3::ZERO; NODES * NODES * NODES],
        };
        let samples = spread(points);
        if samples.is_empty() || triangles.is_empty() {
            return Grid {
                min: Vec3::ZERO,
                max: Vec3::ONE,
                ..grid
            };
        }
        let mut sums = [(Vec3::ZERO, 0u32); NODES * NODES * NODES];
        for &p in &samples {
            let v = at_point(triangles, hair, p, &light);
            let node = grid.nearest_node(p);
            sums[node].0 += v;
            sums[node].1 += 1;
        }
        let mean = sums.iter().map(|s| s.0).sum::<Vec3>() / samples.len() as f32;
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

    /// The radiance at `p`: trilinear between the nodes, the edge held beyond the bounds.
    pub fn at(&self, p: Vec3) -> Vec3 {
        let t = self.lattice(p);
        let cell = |x: f32| (x.floor() as usize).min(NODES - 2);
        let (i, j, k) = (cell(t.x), cell(t.y), cell(t.z));
        let f = t - Vec3::new(i as f32, j as f32, k as f32);
        let v = |x: usize, y: usize, z: usize| self.values[(z * NODES + y) * NODES + x];
        let lerp = |a: Vec3, b: Vec3, w: f32| a + (b - a) * w;
        let plane = |z: usize| {
            lerp(
                lerp(v(i, j, z), v(i + 1, j, z), f.x),
                lerp(v(i, j + 1, z), v(i + 1, j + 1, z), f.x),
                f.y,
            )
        };
        lerp(plane(k), plane(k + 1), f.z)
    }

    /// The grid as the frame uniforms carry it: one node a vector (rgb, w unused).
    pub fn packed(&self) -> [[f32; 4]; NODES * NODES * NODES] {
        std::array::from_fn(|n| self.values[n].extend(0.0).to_array())
    }
}

/// What a hair point of colour `colour` sends to the eye per unit of the probe's radiance: the fibre's albedo
/// `ā_f + ā_b` at right angles to the light (`fibre_transport::attenuation`).
pub fn hair_response(colour: Vec3) -> Vec3 {
    let (f, b) = super::fibre_transport::attenuation(0.0, super::marschner::absorption(colour));
    f + b
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
        let empty = HairDensity::empty();
        let hair = Hair {
            density: &empty,
            sigma_a: Vec3::ZERO,
        };
        let white = at_point(&floor(1.0, 0.0), &hair, point, &sun);
        assert!((white - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{white}");
        let grey = at_point(&floor(0.4, 0.0), &hair, point, &sun);
        assert!((grey - Vec3::splat(0.2)).abs().max_element() < 1e-6, "{grey}");
        let mut roofed = floor(1.0, 0.0).to_vec();
        roofed.extend(floor(1.0, 2.0));
        assert_eq!(at_point(&roofed, &hair, point, &sun), Vec3::ZERO);
        assert_eq!(at_point(&[], &hair, point, &sun), Vec3::ZERO);
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
        let empty = HairDensity::empty();
        let hair = Hair {
            density: &empty,
            sigma_a: Vec3::ZERO,
        };
        let grid = Grid::measure(&floor(0.0), &hair, &points, sun);
        assert_eq!(
            (grid.min, grid.max),
            (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 4.0))
        );
        // Every point sees the floor over half its sphere: 0.5 everywhere.
        for p in &points {
            assert!(
                (grid.at(*p) - Vec3::splat(0.5)).abs().max_element() < 1e-6,
                "{p}: {}",
                grid.at(*p)
            );
        }
        let none = Grid::measure(&[], &hair, &points, sun);
        assert_eq!(none.at(Vec3::ZERO), Vec3::ZERO);
        let mut ramp = grid;
        for (n, v) in ramp.values.iter_mut().enumerate() {
            *v = Vec3::new((n % NODES) as f32, 1.0, 2.0 * (n % NODES) as f32);
        }
        let mid = ramp.at(Vec3::new(0.5, 0.0, 2.0));
        assert!(
            (mid - Vec3::new(1.5, 1.0, 3.0)).abs().max_element() < 1e-6,
            "{mid}"
        );
        assert_eq!(ramp.at(Vec3::new(-3.0, 0.0, 2.0)), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(ramp.at(Vec3::new(7.0, 0.0, 2.0)), Vec3::new(3.0, 1.0, 6.0));
        assert_eq!(ramp.packed()[1], [1.0, 1.0, 2.0, 0.0]);
    }

    /// A floor under a layer of hair, lit from straight above: the floor's light comes through the layer as
    /// `max(e^(−n), d_f ā_f^n)` of it, so a point between the layer and the floor reads `0.5 × lit` (the half
    /// sphere of radiance 1 the bare floor gives), per channel, within 3 %; a darker fibre passes less.
    #[test]
    fn hair_between_the_floor_and_the_light_dims_the_floor_by_its_transport() {
        let s = 1e4;
        let floor = [
            Triangle {
                a: Vec3::new(-s, -s, 0.0),
                b: Vec3::new(s, -s, 0.0),
                c: Vec3::new(-s, s, 0.0),
                albedo: Vec3::ONE,
            },
            Triangle {
                a: Vec3::new(s, -s, 0.0),
                b: Vec3::new(s, s, 0.0),
                c: Vec3::new(-s, s, 0.0),
                albedo: Vec3::ONE,
            },
        ];
        // A wide layer of fibres along x between z = 0.5 and 0.7, 20 wide: a 2001 × 21 grid of fibres 0.01
        // apart, each 0.004 wide: a vertical ray crosses (π/4) × 21 × 0.4 = 6.6 fibres on average. Every
        // direction of the lower half sphere from the points below meets the floor under it.
        let mut points = Vec::new();
        for i in 0..2001 {
            for j in 0..21 {
                let (y, z) = (-10.0 + i as f32 * 0.01, 0.5 + j as f32 * 0.01);
                points.extend([Vec3::new(-10.0, y, z), Vec3::new(10.0, y, z)]);
            }
        }
        let fibres = 2001 * 21;
        let density = HairDensity::from_strands(&points, (0..fibres).map(|n| (2 * n, 2)), |_| 0.004);
        let n = density.crossed(Vec3::new(0.0, 0.0, 0.1), Vec3::Z, f32::INFINITY);
        assert!((n - 6.6).abs() < 0.5, "{n}");
        let mut last = Vec3::INFINITY;
        for colour in [Vec3::new(0.8, 0.6, 0.4), Vec3::new(0.3, 0.19, 0.11)] {
            let sigma_a = super::super::marschner::absorption(colour);
            let hair = Hair {
                density: &density,
                sigma_a,
            };
            let lit = fibre_transport::arriving((-n).exp(), 0.0, sigma_a, n);
            for z in [0.1, 0.2] {
                let got = at_point(&floor, &hair, Vec3::new(0.0, 0.0, z), &sun);
                assert!(
                    (got - 0.5 * lit).abs().max_element() <= 0.03 * lit.max_element(),
                    "{got} vs {lit}"
                );
            }
            let got = at_point(&floor, &hair, Vec3::new(0.0, 0.0, 0.2), &sun);
            assert!(got.cmplt(last).all(), "{got} not below {last}");
            last = got;
        }
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
