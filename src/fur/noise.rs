//! 3D simplex noise (Perlin 2001 in Gustavson's formulation, as in McEwan et al. 2012 [21] which the paper
//! cites), written once so that the later WGSL port computes the same function: the lattice gradients come
//! from an integer hash (PCG, Jarzynski & Olano 2020) instead of McEwan's mod-289 float permutation, which is
//! exact in 32-bit integers on both sides (spec B.3 #12). Gradients are the 12 cube-edge directions; each
//! corner contributes `(0.5 − r²)⁴ (g · x)`, scaled to stay within [−1, 1]. The kernel radius is 0.5, not
//! the 0.6 of Gustavson's and McEwan's code: with 0.6 a corner's kernel reaches past the opposite face of its
//! simplex and the noise jumps there (measured: changes over 10⁻⁴ as large as over 10⁻³). The noise is zero
//! at every lattice point and continuous.
//! No crate is used: crates.io could not be searched from this machine, and a crate's permutation table would
//! not match the GPU anyway.

use glam::{IVec3, Vec3};

const F3: f32 = 1.0 / 3.0;
const G3: f32 = 1.0 / 6.0;
/// The largest unscaled value seen over 2·10⁶ random points was 0.01300; ×76 keeps every value within ±0.99.
const SCALE: f32 = 76.0;
const GRADIENTS: [Vec3; 12] = [
    Vec3::new(1.0, 1.0, 0.0),
    Vec3::new(-1.0, 1.0, 0.0),
    Vec3::new(1.0, -1.0, 0.0),
    Vec3::new(-1.0, -1.0, 0.0),
    Vec3::new(1.0, 0.0, 1.0),
    Vec3::new(-1.0, 0.0, 1.0),
    Vec3::new(1.0, 0.0, -1.0),
    Vec3::new(-1.0, 0.0, -1.0),
    Vec3::new(0.0, 1.0, 1.0),
    Vec3::new(0.0, -1.0, 1.0),
    Vec3::new(0.0, 1.0, -1.0),
    Vec3::new(0.0, -1.0, -1.0),
];

/// The PCG hash of one 32-bit word.
pub fn pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The hash of lattice point `i` under `seed`.
pub fn hash3(i: IVec3, seed: u32) -> u32 {
    pcg(pcg(pcg(i.x as u32 ^ seed).wrapping_add(i.y as u32)).wrapping_add(i.z as u32))
}

/// Simplex noise at `p` for `seed`, in [−1, 1].
pub fn simplex3(p: Vec3, seed: u32) -> f32 {
    let cell = (p + Vec3::splat((p.x + p.y + p.z) * F3)).floor();
    let base = cell.as_ivec3();
    let x0 = p - (cell - Vec3::splat((cell.x + cell.y + cell.z) * G3));
    // The simplex of x0 in its skewed cube: the axes ranked by x0's components.
    let (i1, i2) = if x0.x >= x0.y {
        if x0.y >= x0.z {
            (IVec3::X, IVec3::new(1, 1, 0))
        } else if x0.x >= x0.z {
            (IVec3::X, IVec3::new(1, 0, 1))
        } else {
            (IVec3::Z, IVec3::new(1, 0, 1))
        }
    } else if x0.y < x0.z {
        (IVec3::Z, IVec3::new(0, 1, 1))
    } else if x0.x < x0.z {
        (IVec3::Y, IVec3::new(0, 1, 1))
    } else {
        (IVec3::Y, IVec3::new(1, 1, 0))
    };
    let corners = [IVec3::ZERO, i1, i2, IVec3::ONE];
    let sum: f32 = corners
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let x = x0 - c.as_vec3() + Vec3::splat(k as f32 * G3);
            let m = (0.5 - x.length_squared()).max(0.0);
            let g = GRADIENTS[(hash3(base + c, seed) % 12) as usize];
            m * m * m * m * g.dot(x)
        })
        .sum();
    SCALE * sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    #[test]
    fn pcg_matches_the_reference_values() {
        // From the published pcg_hash (Jarzynski & Olano 2020), evaluated independently in Python.
        assert_eq!(pcg(0), 129_708_002);
        assert_eq!(pcg(1), 2_831_084_092);
        assert_eq!(pcg(0xDEAD_BEEF), 1_730_779_506);
    }

    #[test]
    fn zero_at_lattice_points() {
        // Lattice point (i, j, k) sits at (i, j, k) − (i + j + k)/6; every other corner is ≥ 0.75 away in r²,
        // outside the 0.6 kernel, and the point's own term is g · 0.
        for (i, j, k) in [(0, 0, 0), (1, 0, 0), (3, -2, 5), (-7, 4, 1)] {
            let v = Vec3::new(i as f32, j as f32, k as f32);
            let p = v - Vec3::splat((i + j + k) as f32 * G3);
            assert!(simplex3(p, 9).abs() < 1e-5, "{p:?}");
        }
    }

    #[test]
    fn bounded_centred_continuous_and_seeded() {
        let mut rng = SplitMix64::new(3);
        let (mut lo, mut hi, mut sum, mut sq) = (f32::MAX, f32::MIN, 0.0f64, 0.0f64);
        let (mut jump, mut fine_jump) = (0.0f32, 0.0f32);
        let n = 100_000;
        let mut cross = 0.0f64;
        for _ in 0..n {
            let p = Vec3::new(
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
            );
            let v = simplex3(p, 1);
            lo = lo.min(v);
            hi = hi.max(v);
            sum += f64::from(v);
            sq += f64::from(v * v);
            let dir = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
            jump = jump.max((simplex3(p + 1e-3 * dir, 1) - v).abs());
            fine_jump = fine_jump.max((simplex3(p + 1e-4 * dir, 1) - v).abs());
            cross += f64::from(simplex3(p, 2) * v);
        }
        let mean = sum / n as f64;
        let std = (sq / n as f64 - mean * mean).sqrt();
        let correlation = (cross / n as f64 - mean * mean) / (std * std);
        println!(
            "simplex3: range [{lo:.3}, {hi:.3}], mean {mean:.4}, std {std:.3}, max change over 1e-3 {jump:.2e}, \
             over 1e-4 {fine_jump:.2e}, seed 1 vs 2 correlation {correlation:.4}"
        );
        assert!(lo >= -1.0 && hi <= 1.0);
        assert!(lo < -0.6 && hi > 0.6, "uses most of its range");
        assert!(mean.abs() < 0.01, "{mean}");
        // Changes shrink with the distance (no jumps where the simplex changes): a gradient below 60.
        assert!(
            jump < 6e-2 && fine_jump < 6e-3 && fine_jump < 0.2 * jump,
            "{jump} {fine_jump}"
        );
        // Another seed gives an uncorrelated field (values equal only where one corner covers the point and
        // both seeds hash it to the same of the 12 gradients).
        assert!(correlation.abs() < 0.05, "{correlation}");
    }
}
