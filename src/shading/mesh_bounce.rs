//! The light that reaches the hair other than from the light itself, under the fibres model
//! (`render.hair_model = fibres`; docs/truth.md, "The fibres model"): what the scene's meshes bounce and what
//! the fibres scatter to each other. The path-traced truth lights the hair with the floor's and the head's
//! bounce and with light scattered from fibre to fibre many times; the absorber model stands in for both with a
//! constant ambient term. Here it is a light probe, as engines place one for their hair: the mean radiance
//! arriving over [`DIRECTIONS`] directions at each of up to [`POINTS`] points spread over the strands. Along
//! each direction the point sees the hair in front (a voxel density of the strands, [`HairDensity`]: `e^(−N)`
//! of the rays cross none of its `N` fibres) and, behind it, the mesh triangle the ray meets (either side):
//! its Lambert radiance under the light, `albedo × light × max(n·l, 0)` (the irradiance `π × light` times
//! `albedo / π`, as `shaders/mesh.wgsl` and the path tracer light a mesh), blocked by the meshes (a shadow
//! ray) and passed through the `n` fibres in front of it towards the light as `max(e^(−n), T_f)`
//! ([`fibre_transport::arriving`] at right angles), plus the hair's light on it: its albedo times the hair's
//! radiance there times the part of its hemisphere the hair covers (`1 − e^(−N)` along its normal; a scalp
//! under a lock is lit by the lock). A ray that meets no mesh brings nothing past the hair (the scene has no
//! environment light). What the hair itself sends is [`hair_scatter`]'s fixed point. The means land on an
//! [`NODES`]³ lattice over the strands, which the eye pass reads trilinearly; a hair fragment sends what
//! arrives on times one fibre's albedo `ā_f + ā_b` at right angles ([`hair_response`]): light arriving alike
//! from every side leaves a fibre as it left the one fibre, forward and back. Left out: the direction the light
//! arrives from (the probe is a mean over the sphere) and a lock's inside against its surface within one
//! lattice cell.

use glam::Vec3;

use super::fibre_transport;
use super::hair_density::HairDensity;
use super::hair_scatter::{self, View};

/// Strand points the probe averages over, at most.
pub const POINTS: usize = 512;
/// Directions per point (a Fibonacci sphere).
pub const DIRECTIONS: usize = 32;
/// Nodes a side of the probe's [`Grid`] over the strands' bounds.
pub const NODES: usize = 8;

/// Where the probe's light comes from (`render.probe`, under the fibres model).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Probe {
    /// This module's estimate: the meshes' light through a voxel density of the strands and the fixed point of
    /// the fibres' scattering ([`Grid::measure`]).
    #[default]
    Voxels,
    /// The path tracer's gather at the points of the hair's skin (`pathtrace::probe`): the light arriving through
    /// the fibres themselves, every scattering event, as ray-traced irradiance probes are baked, kept with the
    /// directions it comes from (`probe_light`).
    Traced,
}

impl Probe {
    pub const ALL: [Probe; 2] = [Probe::Voxels, Probe::Traced];

    /// The name people read (panels, reports).
    pub fn label(self) -> &'static str {
        match self {
            Probe::Voxels => "Voxels",
            Probe::Traced => "Path-traced",
        }
    }

    /// One line for a tooltip.
    pub fn description(self) -> &'static str {
        match self {
            Probe::Voxels => {
                "the meshes' light through a voxel density of the strands, the fibres' scattering a fixed point"
            }
            Probe::Traced => {
                "the path tracer's light arriving at the hair's skin, by its directions (slower, CPU)"
            }
        }
    }
}

/// Where a ray from a probe point meets the meshes: the distance, the triangle's unit normal on the side the ray
/// meets and its albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    pub distance: f32,
    pub normal: Vec3,
    pub albedo: Vec3,
}

/// The scene's meshes as the probe's rays meet them (a hierarchy over their triangles,
/// `pathtrace::mesh_rays::MeshBvh`, so that the probe's 16 384 rays and their shadow rays cost the log of the
/// triangles, not their number), both sides of a triangle alike.
pub trait MeshRays {
    /// The nearest triangle along the unit `dir` from `origin`, farther than 1e-5.
    fn nearest(&self, origin: Vec3, dir: Vec3) -> Option<MeshHit>;
    /// Whether a triangle lies along the unit `dir` from `origin` between 1e-5 and `max`.
    fn blocked(&self, origin: Vec3, dir: Vec3, max: f32) -> bool;
}

/// The light at a world point: the unit direction towards it, its distance (infinite for a directional
/// light) and the radiance it brings (`colour × intensity`, the spot's cone applied).
pub struct Arrival {
    pub to_light: Vec3,
    pub distance: f32,
    pub radiance: Vec3,
}

/// The `k`-th of `n` directions of a Fibonacci sphere.
pub(crate) fn fibonacci(k: usize, n: usize) -> Vec3 {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let z = 1.0 - (2.0 * k as f32 + 1.0) / n as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = golden * k as f32;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The box around `points`.
fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

/// Up to [`POINTS`] of `points`, evenly spaced through the list.
pub fn spread(points: &[Vec3]) -> Vec<Vec3> {
    spread_over(points, POINTS)
}

/// Up to `most` of `points`, evenly spaced through the list.
pub fn spread_over(points: &[Vec3], most: usize) -> Vec<Vec3> {
    let n = points.len().min(most);
    (0..n).map(|k| points[k * points.len() / n]).collect()
}

/// The hair the probe's light crosses: its density and its fibres' absorption `σ_a`.
pub struct Hair<'a> {
    pub density: &'a HairDensity,
    pub sigma_a: Vec3,
}

/// The Lambert radiance of the mesh `hit` at `at`, under `light`: the light [`reaching`] it (shadowed by the
/// meshes, through the fibres in front of it towards the light) times `albedo × cos`.
fn mesh_radiance(
    meshes: &impl MeshRays,
    hair: &Hair,
    hit: &MeshHit,
    at: Vec3,
    light: &impl Fn(Vec3) -> Arrival,
) -> Vec3 {
    let cos = hit.normal.dot(light(at).to_light);
    if cos <= 0.0 {
        return Vec3::ZERO;
    }
    hit.albedo * cos * reaching(meshes, hair, at + hit.normal * 1e-4, light)
}

/// What `p` sees along each of [`DIRECTIONS`] directions: the lit mesh the direction meets and the hair in
/// front of it (per unit of the light's colour × intensity as `light` gives it).
fn views(meshes: &impl MeshRays, hair: &Hair, p: Vec3, light: &impl Fn(Vec3) -> Arrival) -> Vec<View> {
    (0..DIRECTIONS)
        .map(|k| {
            let dir = fibonacci(k, DIRECTIONS);
            let (mut mesh, mut mesh_gain, mut mesh_at, mut reach) =
                (Vec3::ZERO, Vec3::ZERO, p, f32::INFINITY);
            if let Some(hit) = meshes.nearest(p, dir) {
                mesh_at = p + dir * hit.distance;
                mesh = mesh_radiance(meshes, hair, &hit, mesh_at, light);
                let n = hit.normal;
                let over = hair.density.crossed(mesh_at + n * 1e-4, n, f32::INFINITY);
                mesh_gain = hit.albedo * (1.0 - (-over).exp());
                reach = hit.distance;
            }
            let c = hair.density.march(p, dir, reach);
            View {
                mesh,
                clear: (-c.count).exp(),
                hair_at: p + dir * c.depth,
                mesh_gain,
                mesh_at,
            }
        })
        .collect()
}

/// The light that reaches `p` (a fibre, or a mesh point just off its surface), per unit of the light's colour ×
/// intensity: `max(e^(−n), T_f)` through the `n` fibres in front of it towards the light, as the eye pass
/// lights a fibre or a mesh under the hair; nothing where a mesh is in the way.
fn reaching(meshes: &impl MeshRays, hair: &Hair, p: Vec3, light: &impl Fn(Vec3) -> Arrival) -> Vec3 {
    let l = light(p);
    if meshes.blocked(p, l.to_light, l.distance) {
        return Vec3::ZERO;
    }
    let n = hair.density.crossed(p, l.to_light, l.distance);
    l.radiance * fibre_transport::arriving((-n).exp(), 0.0, hair.sigma_a, n)
}

/// The probe over the hair: [`NODES`]³ radiances (linear RGB) on a lattice spanning the strands' bounds
/// `min`..`max`, each the mean of the points nearest to it (filled from its neighbours where none is,
/// [`Grid::from_points`]), read trilinearly
/// ([`Grid::at`]; the eye pass's `bounce_at` in `shaders/common/mesh_bounce.wgsl`, which `frame.bounce_*`
/// carries).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid<T = Vec3> {
    pub min: Vec3,
    pub max: Vec3,
    /// Node `(x, y, z)` at `(z · NODES + y) · NODES + x`.
    pub values: [T; NODES * NODES * NODES],
}

/// What a lattice node holds: a value that averages and interpolates linearly (a radiance, or the traced
/// probe's light, `probe_light::ProbeLight`).
pub trait Node:
    Copy
    + Default
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<f32, Output = Self>
    + std::ops::Div<f32, Output = Self>
{
}

impl<T> Node for T where
    T: Copy
        + Default
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f32, Output = T>
        + std::ops::Div<f32, Output = T>
{
}

impl Grid {
    /// The probe of `meshes` through `hair` at up to [`POINTS`] of `points` (see [`spread`]) under `light`.
    pub fn measure(
        meshes: &impl MeshRays,
        hair: &Hair,
        points: &[Vec3],
        light: impl Fn(Vec3) -> Arrival,
    ) -> Grid {
        let samples = spread(points);
        if samples.is_empty() {
            return Grid::over(points, &[], &[]);
        }
        let (min, max) = bounds(points);
        let seen: Vec<Vec<View>> = samples.iter().map(|&p| views(meshes, hair, p, &light)).collect();
        let (forward, backward) = fibre_transport::attenuation(0.0, hair.sigma_a);
        let direct: Vec<Vec3> = samples
            .iter()
            .map(|&p| backward * reaching(meshes, hair, p, &light) / 4.0)
            .collect();
        let arriving = hair_scatter::incident(&direct, &seen, forward + backward, |values| {
            let grid = Grid::from_points(min, max, &samples, values);
            move |p| grid.at(p)
        });
        Grid::from_points(min, max, &samples, &arriving)
    }
}

impl<T: Node> Grid<T> {
    /// The lattice over the bounds of `points` (the strands') whose nodes hold the mean of the `values` at
    /// `at` nearest to them ([`Grid::from_points`]); zero with no points.
    pub fn over(points: &[Vec3], at: &[Vec3], values: &[T]) -> Grid<T> {
        if at.is_empty() {
            return Grid {
                min: Vec3::ZERO,
                max: Vec3::ONE,
                values: [T::default(); NODES * NODES * NODES],
            };
        }
        let (min, max) = bounds(points);
        Grid::from_points(min, max, at, values)
    }

    /// The lattice over `min`..`max` whose nodes hold the mean of the `values` of the `points` nearest to them;
    /// a node no point is nearest to (inside the head, beyond a lock's edge) takes the mean of its filled
    /// neighbours along the axes, filled outwards from the points (zero where there are none), so that no
    /// value reaches a node from far away.
    pub(crate) fn from_points(min: Vec3, max: Vec3, points: &[Vec3], values: &[T]) -> Grid<T> {
        let mut grid = Grid {
            min,
            max,
            values: [T::default(); NODES * NODES * NODES],
        };
        let mut sums = [(T::default(), 0u32); NODES * NODES * NODES];
        for (&p, &v) in points.iter().zip(values) {
            let node = grid.nearest_node(p);
            sums[node].0 = sums[node].0 + v;
            sums[node].1 += 1;
        }
        let mut filled: Vec<bool> = sums.iter().map(|s| s.1 > 0).collect();
        for (v, (sum, n)) in grid.values.iter_mut().zip(sums) {
            if n > 0 {
                *v = sum / n as f32;
            }
        }
        while filled.iter().any(|f| !f) && filled.iter().any(|f| *f) {
            let before = filled.clone();
            for n in 0..NODES * NODES * NODES {
                if before[n] {
                    continue;
                }
                let (x, y, z) = (n % NODES, n / NODES % NODES, n / (NODES * NODES));
                let (mut sum, mut count) = (T::default(), 0);
                for (axis, at) in [x, y, z].into_iter().enumerate() {
                    let stride = NODES.pow(axis as u32);
                    for m in [(at > 0).then(|| n - stride), (at + 1 < NODES).then(|| n + stride)]
                        .into_iter()
                        .flatten()
                    {
                        if before[m] {
                            sum = sum + grid.values[m];
                            count += 1;
                        }
                    }
                }
                if count > 0 {
                    grid.values[n] = sum / count as f32;
                    filled[n] = true;
                }
            }
        }
        grid
    }

    /// Where node `n` (at `(z · NODES + y) · NODES + x`) of the lattice `min`..`max` lies.
    pub(crate) fn node_position(min: Vec3, max: Vec3, n: usize) -> Vec3 {
        let (x, y, z) = (n % NODES, n / NODES % NODES, n / (NODES * NODES));
        min + (max - min) * Vec3::new(x as f32, y as f32, z as f32) / (NODES - 1) as f32
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

    /// The value at `p`: trilinear between the nodes, the edge held beyond the bounds.
    pub fn at(&self, p: Vec3) -> T {
        let t = self.lattice(p);
        let cell = |x: f32| (x.floor() as usize).min(NODES - 2);
        let (i, j, k) = (cell(t.x), cell(t.y), cell(t.z));
        let f = t - Vec3::new(i as f32, j as f32, k as f32);
        let v = |x: usize, y: usize, z: usize| self.values[(z * NODES + y) * NODES + x];
        let lerp = |a: T, b: T, w: f32| a + (b - a) * w;
        let plane = |z: usize| {
            lerp(
                lerp(v(i, j, z), v(i + 1, j, z), f.x),
                lerp(v(i, j + 1, z), v(i + 1, j + 1, z), f.x),
                f.y,
            )
        };
        lerp(plane(k), plane(k + 1), f.z)
    }
}

/// What a hair point of colour `colour` sends to the eye per unit of the probe's radiance: the fibre's albedo
/// `ā_f + ā_b` at right angles to the light (`fibre_transport::attenuation`).
pub fn hair_response(colour: Vec3) -> Vec3 {
    let (f, b) = fibre_transport::attenuation(0.0, super::marschner::absorption(colour));
    f + b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::mesh_rays::MeshBvh;
    use crate::pathtrace::triangle::Triangle;

    /// The meshes' light alone at `p`, through the hair in front of them.
    fn meshes_alone(meshes: &MeshBvh, hair: &Hair, p: Vec3, light: &impl Fn(Vec3) -> Arrival) -> Vec3 {
        let seen = views(meshes, hair, p, light);
        seen.iter().map(|v| v.mesh * v.clear).sum::<Vec3>() / DIRECTIONS as f32
    }

    /// The square `[−half, half]²` at height `z`, of one albedo, as two triangles.
    fn square(half: f32, z: f32, albedo: f32) -> Vec<Triangle> {
        let corner = |x: f32, y: f32| Vec3::new(x * half, y * half, z);
        [
            [corner(-1.0, -1.0), corner(1.0, -1.0), corner(-1.0, 1.0)],
            [corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
        ]
        .map(|[a, b, c]| Triangle {
            p0: a,
            e1: b - a,
            e2: c - a,
            albedo: Vec3::splat(albedo),
        })
        .to_vec()
    }

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
        let floor = |albedo: f32, z: f32| square(1e4, z, albedo);
        let point = Vec3::new(0.0, 0.0, 1.0);
        let empty = HairDensity::empty();
        let hair = Hair {
            density: &empty,
            sigma_a: Vec3::ZERO,
        };
        let white = meshes_alone(&MeshBvh::new(floor(1.0, 0.0)), &hair, point, &sun);
        assert!((white - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{white}");
        let grey = meshes_alone(&MeshBvh::new(floor(0.4, 0.0)), &hair, point, &sun);
        assert!((grey - Vec3::splat(0.2)).abs().max_element() < 1e-6, "{grey}");
        let mut roofed = floor(1.0, 0.0);
        roofed.extend(floor(1.0, 2.0));
        assert_eq!(
            meshes_alone(&MeshBvh::new(roofed), &hair, point, &sun),
            Vec3::ZERO
        );
        assert_eq!(
            meshes_alone(&MeshBvh::new(Vec::new()), &hair, point, &sun),
            Vec3::ZERO
        );
    }

    /// The grid spans the points; points above a lit floor read 0.5 (half their sphere at radiance 1) at and
    /// between their nodes; with no mesh it reads zero; a ramp of node values is read linearly between nodes,
    /// its edges held beyond the bounds, and packed four to a vector.
    #[test]
    fn the_grid_keeps_where_the_light_comes_from() {
        let points: Vec<Vec3> = (0..8)
            .map(|k| Vec3::new((k % 2) as f32, 0.0, 1.0 + (k / 2) as f32))
            .collect();
        let empty = HairDensity::empty();
        let hair = Hair {
            density: &empty,
            sigma_a: Vec3::ZERO,
        };
        let grid = Grid::measure(&MeshBvh::new(square(1e4, 0.0, 1.0)), &hair, &points, sun);
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
        let none = Grid::measure(&MeshBvh::new(Vec::new()), &hair, &points, sun);
        assert_eq!(none.at(Vec3::ZERO), Vec3::ZERO);
        let mut ramp = grid;
        for (n, v) in ramp.values.iter_mut().enumerate() {
            *v = Vec3::new((n % NODES) as f32, 1.0, 2.0 * (n % NODES) as f32);
        }
        let last = (NODES - 1) as f32;
        let mid = ramp.at(Vec3::new(0.5, 0.0, 2.0));
        assert!(
            (mid - Vec3::new(0.5 * last, 1.0, last)).abs().max_element() < 1e-6,
            "{mid}"
        );
        assert_eq!(ramp.at(Vec3::new(-3.0, 0.0, 2.0)), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(
            ramp.at(Vec3::new(7.0, 0.0, 2.0)),
            Vec3::new(last, 1.0, 2.0 * last)
        );
    }

    /// A floor under a layer of hair, lit from straight above: the floor's light comes through the layer as
    /// `max(e^(−n), d_f ā_f^n)` of it, so a point between the layer and the floor reads `0.5 × lit` (the half
    /// sphere of radiance 1 the bare floor gives), per channel, within 3 %; a darker fibre passes less.
    #[test]
    fn hair_between_the_floor_and_the_light_dims_the_floor_by_its_transport() {
        let floor = MeshBvh::new(square(1e4, 0.0, 1.0));
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
                let got = meshes_alone(&floor, &hair, Vec3::new(0.0, 0.0, z), &sun);
                assert!(
                    (got - 0.5 * lit).abs().max_element() <= 0.03 * lit.max_element(),
                    "{got} vs {lit}"
                );
            }
            let got = meshes_alone(&floor, &hair, Vec3::new(0.0, 0.0, 0.2), &sun);
            assert!(got.cmplt(last).all(), "{got} not below {last}");
            last = got;
        }
    }

    /// A layer of fibres lit from straight above with no mesh anywhere lights itself: its probe is the light
    /// its fibres scatter to each other, positive inside the layer, more for blond fibres than dark ones, and
    /// redder than one fibre's albedo for brown ones (light scattered many times takes the colour many times);
    /// with a roof between the light and the layer (its underside away from the light) there is none.
    #[test]
    fn a_layer_of_hair_lights_itself() {
        let mut points = Vec::new();
        for i in 0..201 {
            for j in 0..21 {
                let (y, z) = (-1.0 + i as f32 * 0.01, 0.5 + j as f32 * 0.01);
                points.extend([Vec3::new(-1.0, y, z), Vec3::new(1.0, y, z)]);
            }
        }
        let density = HairDensity::from_strands(&points, (0..201 * 21).map(|n| (2 * n, 2)), |_| 0.004);
        let probe = |colour: Vec3, meshes: Vec<Triangle>| {
            let hair = Hair {
                density: &density,
                sigma_a: super::super::marschner::absorption(colour),
            };
            Grid::measure(&MeshBvh::new(meshes), &hair, &points, sun).at(Vec3::new(0.0, 0.0, 0.6))
        };
        let (blond, brown) = (Vec3::new(0.8, 0.62, 0.38), Vec3::new(0.3, 0.19, 0.11));
        let (light, dark) = (probe(blond, Vec::new()), probe(brown, Vec::new()));
        assert!(dark.cmpgt(Vec3::ZERO).all(), "{dark}");
        assert!(light.cmpgt(dark).all(), "{light} vs {dark}");
        let one = hair_response(brown);
        assert!(dark.x / dark.z > one.x / one.z, "{dark} vs one fibre's {one}");
        assert_eq!(probe(blond, square(5.0, 2.0, 1.0)), Vec3::ZERO);
    }

    /// A node no point is nearest to takes its value from the filled nodes next to it, not from far away: with
    /// points of value 1 on the lattice's `x = 0` face and 3 on its far face, the nodes between read 1 up to
    /// the middle and 3 beyond it (the mean of all points would read 2 everywhere between); with no points the
    /// lattice is zero.
    #[test]
    fn empty_nodes_take_their_neighbours_values() {
        let side = |x: f32| {
            (0..NODES * NODES).map(move |n| {
                let (j, k) = ((n % NODES) as f32, (n / NODES) as f32);
                Vec3::new(x, j, k) / (NODES - 1) as f32
            })
        };
        let points: Vec<Vec3> = side(0.0).chain(side((NODES - 1) as f32)).collect();
        let values: Vec<Vec3> = (0..points.len())
            .map(|n| Vec3::splat(if n < NODES * NODES { 1.0 } else { 3.0 }))
            .collect();
        let grid = Grid::from_points(Vec3::ZERO, Vec3::ONE, &points, &values);
        for x in 0..NODES {
            let want = if x < NODES / 2 { 1.0 } else { 3.0 };
            let at = Vec3::new(x as f32, 2.0, 5.0) / (NODES - 1) as f32;
            assert_eq!(grid.at(at), Vec3::splat(want), "node {x}");
        }
        let none: Grid = Grid::from_points(Vec3::ZERO, Vec3::ONE, &[], &[]);
        assert_eq!(none.values, [Vec3::ZERO; NODES * NODES * NODES]);
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
