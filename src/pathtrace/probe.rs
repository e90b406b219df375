//! The fibres model's light probe path-traced (`render.probe = traced`; docs/truth.md, "The traced probe"): at
//! up to 512 strand points on the hair's skin ([`points_of`]), the light arriving along [`DIRECTIONS`] directions
//! outside the cone about the direction to the light ([`light_at`]: through the fibres themselves, every
//! scattering event, the meshes' bounce), by the directions it comes from (`shading::probe_light`), lit by the raster's light as the eye pass lights the hair, on the voxel probe's
//! lattice ([`Grid::over`]), which the eye pass reads alike. Engines bake ray-traced irradiance probes so; here
//! the path tracer that makes the truth bakes it, with its own seed, so the window's frame and the truth chain's
//! CPU model of it hold one probe. What a voxel probe cannot carry, it carries: the floor's light scattered
//! forward up through the hair, the colour of light after few events rather than many (`measure probe`), the
//! directions it arrives from.

use glam::Vec3;
use rayon::prelude::*;

use super::bsdf::FibreParams;
use super::bvh::Bvh;
use super::effects::{Effects, RasterLight};
use super::fibre::Ray;
use super::integrator::{MAX_DEPTH, TraceSettings, arriving};
use super::light::Lighting;
use super::mesh_rays::MeshBvh;
use super::triangle::Triangle;
use crate::shading::hair_cover;
use crate::shading::hair_density::HairDensity;
use crate::shading::mesh_bounce::{self, Grid, spread_over};
use crate::shading::probe_light::{self, ProbeLight, cone_cos};

/// Directions per point: at 64 the lattice's nodes (a point or two each) kept the gather's noise (the
/// reference's hair RMSE against a 64-spp truth, its noise kept, 0.103 / 0.122 against 0.096 / 0.109 at 256 on
/// `default` / `blond`); 256 reads within 0.002 of 1024.
pub const DIRECTIONS: u32 = 256;

/// The random streams' seed, fixed: the probe is part of the real-time image, not of a truth's sample.
const SEED: u64 = 0x9E37_79B9;

/// Strand points the probe considers: this many times [`mesh_bounce::POINTS`], evenly spread through the list.
const CANDIDATES: usize = 4;
/// Directions along which a candidate looks for a way out of the hair ([`points_of`]).
const OUT_DIRECTIONS: usize = 32;

/// The points the probe gathers at: up to [`mesh_bounce::POINTS`] of the strand `points` that see out of
/// everything `bvh` holds along one of [`OUT_DIRECTIONS`] directions (a Fibonacci sphere) — the hair's skin,
/// which the eye sees — evenly spread among those of [`CANDIDATES`]` × POINTS` spread through the list; all the
/// candidates where none sees out. Baked at points spread through the whole hair, the lattice read 0.87 / 1.08 /
/// 1.13 / 1.03 of the path tracer's gather at the points the camera sees on `default` / `blond` / `back-lit` /
/// `dense-coverage` ÷4, while those points read 1.04 / 1.10 / 1.02 / 1.02 of a lattice over the points of the
/// skin (docs/truth.md, "The traced probe").
pub fn points_of(bvh: &Bvh, points: &[Vec3]) -> Vec<Vec3> {
    let candidates = spread_over(points, CANDIDATES * mesh_bounce::POINTS);
    let open: Vec<Vec3> = candidates
        .par_iter()
        .copied()
        .filter(|&p| {
            (0..OUT_DIRECTIONS).any(|k| {
                !bvh.any_hit(
                    &Ray::new(p, mesh_bounce::fibonacci(k, OUT_DIRECTIONS)),
                    f32::INFINITY,
                )
            })
        })
        .collect();
    let kept = if open.is_empty() { &candidates } else { &open };
    spread_over(kept, mesh_bounce::POINTS)
}

/// The light arriving at `p` along those of `directions` uniform directions of the sphere
/// (`integrator::arriving`'s for `stream`) outside the cone about `to_light` ([`ProbeLight`]).
pub fn light_at(
    bvh: &Bvh,
    light: &impl Lighting,
    to_light: Vec3,
    s: &TraceSettings,
    p: Vec3,
    directions: u32,
    stream: u64,
) -> ProbeLight {
    let cone = cone_cos();
    let mut out = ProbeLight::default();
    let share = 4.0 * std::f32::consts::PI / directions.max(1) as f32;
    for (w, l) in arriving(bvh, light, s, p, directions, stream) {
        if w.dot(to_light) < cone {
            out.add_rest(w, l, share);
        }
    }
    out
}

/// The probe of the fibres `bvh` holds (with the meshes) under `light`, the fibres' BSDF `fibre`, at up to
/// [`points_of`] the strand `points`, on the lattice over their bounds.
pub fn grid(bvh: &Bvh, light: &RasterLight, fibre: FibreParams, points: &[Vec3]) -> Grid<ProbeLight> {
    let s = TraceSettings {
        width: 0,
        height: 0,
        samples: 0,
        seed: SEED,
        max_depth: MAX_DEPTH,
        fibre,
        effects: Effects::TRUTH,
    };
    let at = points_of(bvh, points);
    let values: Vec<ProbeLight> = at
        .par_iter()
        .enumerate()
        .map(|(k, &p)| light_at(bvh, light, light.toward(p).0, &s, p, DIRECTIONS, k as u64))
        .collect();
    Grid::over(points, &at, &values)
}

/// The fibres model's probe of `kind` for strands `ranges` (`(first point, point count)` into `points`, point
/// `k` of width `width(k)`) among `triangles` under `light`, the hair's linear colour `colour`: under
/// [`mesh_bounce::Probe::Traced`] the path tracer's gather ([`grid`]), else the meshes' light through a voxel
/// density of the strands (`mesh_bounce::Grid::measure`); either with the hair's cover at its nodes
/// (`shading::hair_cover::lattice`), which lights the meshes under the hair. What the window's frame
/// (`render::probe_cache`) and the truth chain's CPU model of it (`path_scene::raster_shading`) both bake.
pub fn bake(
    kind: mesh_bounce::Probe,
    light: &RasterLight,
    colour: Vec3,
    points: &[Vec3],
    ranges: &[(usize, usize)],
    width: impl Fn(usize) -> f32,
    triangles: Vec<Triangle>,
) -> Grid<ProbeLight> {
    let density = HairDensity::from_strands(points, ranges.iter().copied(), &width);
    let meshes = MeshBvh::new(triangles.clone());
    let light_grid = match kind {
        mesh_bounce::Probe::Traced => {
            let fibres = super::fibre::segments_of(points, ranges.iter().copied(), |k| 0.5 * width(k));
            let bvh = Bvh::with_triangles(fibres, triangles);
            grid(&bvh, light, super::bsdf::fibre_params(colour.to_array()), points)
        }
        mesh_bounce::Probe::Voxels => {
            let hair = mesh_bounce::Hair {
                density: &density,
                sigma_a: crate::shading::marschner::absorption(colour),
            };
            let grid = Grid::measure(&meshes, &hair, points, |p| {
                let (to_light, distance) = light.toward(p);
                mesh_bounce::Arrival {
                    to_light,
                    distance,
                    radiance: light.radiance_at(p),
                }
            });
            probe_light::isotropic(&grid)
        }
    };
    let cover = hair_cover::lattice(&density, &meshes, light_grid.min, light_grid.max);
    probe_light::covered(light_grid, &cover)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::fibre::Segment;
    use crate::pathtrace::triangle::square;

    /// Strands a unit above the middle of a lit Lambertian square 2000 wide (albedo ρ, lit along its normal by
    /// the raster's light of radiance 1: irradiance π, radiance ρ), so thin (radius 1e-6) that they hold no
    /// light: every point sees the square over 0.4997 of the sphere (`4 asin(a² / (a² + d²)) / 4π`, a = 1000,
    /// d = 1, within 0.0001 over the points), so the probe is ρ/2. The mean over 64 points of 256 directions each:
    /// relative standard error 1.1 %, measured 1.001, the tolerance 4 %. The light comes from one hemisphere,
    /// uniform over it: along the floor's normal `⟨u⟩ = −½`, `⟨u²⟩ = ⅓`, across it `0` and `⅓` (pooled over
    /// the points, within 0.02; measured −0.497, 0.331, 0.007, 0.336). The same inputs give the same lattice.
    #[test]
    fn the_traced_probe_over_a_lit_floor_is_half_its_radiance() {
        let rho = Vec3::new(0.8, 0.5, 0.25);
        let floor = square(Vec3::ZERO, Vec3::X, Vec3::Z, 1000.0, rho);
        let points: Vec<Vec3> = (0..64)
            .map(|k| Vec3::new(-1.0 + k as f32 / 32.0, 1.0, 0.01 * (k % 8) as f32))
            .collect();
        let fibres: Vec<Segment> = points
            .chunks(2)
            .map(|p| Segment::new(p[0], p[1], 1e-6, 1e-6))
            .collect();
        let bvh = Bvh::with_triangles(fibres, floor);
        let light = RasterLight {
            radiance: Vec3::ONE,
            to_light: Vec3::Y,
            spot: None,
        };
        let fibre = crate::pathtrace::bsdf::fibre_params([0.5; 3]);
        let probe = grid(&bvh, &light, fibre, &points);
        let mean = points.iter().map(|&p| probe.at(p).mean()).sum::<Vec3>() / points.len() as f32;
        let expected = rho * 0.4997;
        assert!(
            ((mean - expected) / expected).abs().max_element() < 0.04,
            "{mean} vs {expected}"
        );
        let pooled = points
            .iter()
            .map(|&p| probe.at(p))
            .fold(ProbeLight::default(), |a, b| a + b);
        let (up, up_sq) = pooled.moments_along(Vec3::Y);
        let (across, across_sq) = pooled.moments_along(Vec3::X);
        assert!(
            (up + 0.5).abs() < 0.02 && (up_sq - 1.0 / 3.0).abs() < 0.02,
            "{up} {up_sq}"
        );
        assert!(
            across.abs() < 0.02 && (across_sq - 1.0 / 3.0).abs() < 0.02,
            "{across} {across_sq}"
        );
        assert_eq!(probe, grid(&bvh, &light, fibre, &points));
    }

    /// The probe gathers on the hair's skin: in a bundle of 9 × 9 straight strands along x, each overlapping its
    /// neighbours, the points it takes in the middle third of the strands' length all lie on the 32 strands of
    /// the bundle's outer ring (a point inside sees no way out along any of the 32 directions), and it takes
    /// many; inside a closed box, where no point sees out, it takes the candidates.
    #[test]
    fn the_probe_gathers_where_the_hair_sees_out() {
        let (n, spacing, length) = (9, 0.02f32, 2.0f32);
        let (mut segments, mut points, mut ring) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..n {
            for k in 0..n {
                let strand: Vec<Vec3> = (0..=20)
                    .map(|i| Vec3::new(length * i as f32 / 20.0, j as f32 * spacing, k as f32 * spacing))
                    .collect();
                segments.extend(crate::pathtrace::fibre::segments_of(
                    &strand,
                    [(0, strand.len())].into_iter(),
                    |_| 0.6 * spacing,
                ));
                let outer = j == 0 || k == 0 || j == n - 1 || k == n - 1;
                ring.extend(std::iter::repeat_n(outer, strand.len()));
                points.extend(strand);
            }
        }
        let bvh = Bvh::new(segments);
        let at = points_of(&bvh, &points);
        let middle: Vec<bool> = at
            .iter()
            .filter(|p| p.x > length / 3.0 && p.x < 2.0 * length / 3.0)
            .map(|p| ring[points.iter().position(|q| q == p).unwrap()])
            .collect();
        assert!(
            at.len() >= 300 && middle.len() >= 100,
            "{} points, {} in the middle",
            at.len(),
            middle.len()
        );
        assert!(
            middle.iter().all(|&outer| outer),
            "a point inside the bundle was taken"
        );

        let walls = [Vec3::X, Vec3::Y, Vec3::Z]
            .into_iter()
            .flat_map(|a| {
                let (u, v) = (a.any_orthonormal_pair().0, a.any_orthonormal_pair().1);
                [a, -a].map(|c| square(c, u, v, 1.0, Vec3::ONE))
            })
            .flatten()
            .collect();
        let inside: Vec<Vec3> = (0..40)
            .map(|i| Vec3::new(-0.5 + i as f32 / 40.0, 0.1, 0.2))
            .collect();
        let fibres = inside
            .chunks(2)
            .map(|p| Segment::new(p[0], p[1], 0.01, 0.01))
            .collect();
        let boxed = Bvh::with_triangles(fibres, walls);
        assert_eq!(points_of(&boxed, &inside), inside);
    }
}
