//! Ray-traced texel visibility, the reference the shadow maps' visibility functions are measured against: for a
//! light-space texel, N×N jittered rays through its footprint along the light direction, every fibre crossing
//! along each ray, and `V(z)`, the fraction of rays not yet occluded at depth `z` (the deep shadow map of
//! Lokovic & Veach 2000 with the fibres as opaque cylinders). With fibres placed at random it is the Boolean
//! model's transmittance `exp(−n w L)` (Moon & Marschner 2006; Moon, Walter & Marschner 2008).

use glam::Vec3;

use super::bvh::Bvh;
use super::fibre::{Hit, Ray};
use crate::rng::SplitMix64;
use crate::scene::light_frame::LightFrame;

/// A light-space texel: the parallelogram `corner + s·edge_u + t·edge_v` (`s, t` in [0, 1)) on a plane facing
/// the light, and the unit direction the light travels (away from the light). Depth is distance from that plane.
/// `seed` seeds its rays' jitter: a map texel's row-major index ([`light_map_texel`]), so every caller (the
/// measurement, the inspector) traces the same rays through it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    pub corner: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
    pub dir: Vec3,
    pub seed: u64,
}

impl Texel {
    /// The `n × n` jittered rays through the footprint, stratum `(i, j)` jittered by stream `i·n + j` of its seed.
    pub fn rays(&self, n: usize) -> impl Iterator<Item = Ray> + '_ {
        (0..n * n).map(move |k| {
            let mut rng = SplitMix64::stream(self.seed, k as u64);
            let s = ((k / n) as f32 + rng.unit()) / n as f32;
            let t = ((k % n) as f32 + rng.unit()) / n as f32;
            Ray::new(self.corner + s * self.edge_u + t * self.edge_v, self.dir)
        })
    }
}

/// Texel `(x, y)` (row 0 at the top, as the maps are stored) of a `side × side` hair map in a directional light's
/// orthographic `frame`: its footprint on the near plane and the light's direction. Depth along its rays is
/// distance from the near plane; the maps' normalised depth is that over `frame.far − frame.near`.
pub fn light_map_texel(frame: &LightFrame, side: u32, x: u32, y: u32) -> Texel {
    let clip_to_world = frame.world_to_clip().inverse();
    let at = |u: u32, v: u32| {
        let ndc = Vec3::new(
            2.0 * u as f32 / side as f32 - 1.0,
            1.0 - 2.0 * v as f32 / side as f32,
            0.0,
        );
        clip_to_world.project_point3(ndc)
    };
    let corner = at(x, y);
    Texel {
        corner,
        edge_u: at(x + 1, y) - corner,
        edge_v: at(x, y + 1) - corner,
        dir: -frame.to_light,
        seed: u64::from(y) * u64::from(side) + u64::from(x),
    }
}

/// Every fibre crossing along each of the texel's `n × n` rays up to `max_depth`, in order of depth per ray.
pub fn crossings(bvh: &Bvh, texel: &Texel, n: usize, max_depth: f32) -> Vec<Vec<Hit>> {
    texel.rays(n).map(|r| bvh.all_hits(&r, max_depth)).collect()
}

/// `V(z)` at each of `depths`: the fraction of the texel's `n × n` rays that cross no fibre before depth `z`.
pub fn texel_visibility(bvh: &Bvh, texel: &Texel, n: usize, depths: &[f32]) -> Vec<f32> {
    let deepest = depths.iter().copied().fold(0.0, f32::max);
    let first: Vec<f32> = crossings(bvh, texel, n, deepest)
        .iter()
        .map(|h| h.first().map_or(f32::INFINITY, |h| h.t))
        .collect();
    depths
        .iter()
        .map(|&z| first.iter().filter(|&&t| t >= z).count() as f32 / first.len() as f32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::fibre::Segment;

    /// A slab of random fibres along x, `n` per unit area of the (y, z) plane, width `w`, depth `L` along z; a
    /// texel 100 long in y looks along +z. The fraction of the texel not covered by any fibre has mean
    /// `p = exp(−n w L)` (the Boolean model; placing a fixed `n·A` fibres in area `A` instead of a Poisson
    /// number biases it by `p·n(wL)²/2A`, 2e-5 here) and variance `(1/Y)∫Cov(τ)dτ = 2p²((e^{nLw}−1)/(nL) − w)/Y`
    /// from its spread along y, plus at most `p(1−p)/N²` from the N² rays: σ ≈ 0.005. The test allows 4σ.
    #[test]
    fn boolean_slab_transmittance_is_exp_minus_nwl() {
        let (w, len, density, span) = (0.01f32, 1.0f32, 100.0f32, 100.0f32);
        let mut rng = SplitMix64::new(2016);
        let count = (density * (span + w) * len) as usize;
        let segments = (0..count)
            .map(|_| {
                let (y, z) = (rng.range(-0.5 * w, span + 0.5 * w), rng.range(0.0, len));
                Segment::new(Vec3::new(-1.0, y, z), Vec3::new(1.0, y, z), 0.5 * w, 0.5 * w)
            })
            .collect();
        let bvh = Bvh::new(segments);
        let texel = Texel {
            corner: Vec3::new(-0.05, 0.0, -1.0),
            edge_u: Vec3::new(0.0, span, 0.0),
            edge_v: Vec3::new(0.1, 0.0, 0.0),
            dir: Vec3::Z,
            seed: 1,
        };
        let n = 200;
        let v = texel_visibility(&bvh, &texel, n, &[0.5, len + 2.0]);
        let p = (-density * w * len).exp();
        let nl = density * len;
        let var = 2.0 * p * p * (((nl * w).exp() - 1.0) / nl - w) / span + p * (1.0 - p) / (n * n) as f32;
        let sigma = var.sqrt();
        eprintln!("slab: V = {:.4}, exp(-nwL) = {p:.4}, σ = {sigma:.4}", v[1]);
        assert_eq!(v[0], 1.0, "nothing lies before the slab");
        assert!((v[1] - p).abs() < 4.0 * sigma, "V {} vs {p} (σ {sigma})", v[1]);
    }

    /// Strands along x across a unit texel at distinct depths, side by side in y with edges on the strata
    /// boundaries of a 16 × 16 texel: each one takes exactly its share of the rays, so V steps by its coverage.
    #[test]
    fn non_overlapping_strands_step_by_their_coverage() {
        // (first stratum row, rows covered, depth)
        let strands = [(1usize, 3usize, 2.0f32), (6, 1, 4.0), (9, 5, 6.0)];
        let n = 16;
        let segments = strands
            .iter()
            .map(|&(row, rows, z)| {
                let r = 0.5 * rows as f32 / n as f32;
                let y = row as f32 / n as f32 + r;
                Segment::new(Vec3::new(-1.0, y, z), Vec3::new(2.0, y, z), r, r)
            })
            .collect();
        let bvh = Bvh::new(segments);
        let texel = Texel {
            corner: Vec3::ZERO,
            edge_u: Vec3::Y,
            edge_v: Vec3::X,
            dir: Vec3::Z,
            seed: 5,
        };
        let v = texel_visibility(&bvh, &texel, n, &[1.0, 3.0, 5.0, 7.0]);
        let mut expected = 1.0;
        let mut want = vec![1.0];
        for &(_, rows, _) in &strands {
            expected -= rows as f32 / n as f32;
            want.push(expected);
        }
        assert_eq!(v, want);
        let hits = crossings(&bvh, &texel, n, 10.0);
        assert_eq!(hits.iter().map(Vec::len).sum::<usize>(), 9 * n);
    }
}
