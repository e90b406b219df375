//! The light the hair scatters onto itself, for the fibres model's probe (`shading::mesh_bounce`; docs/truth.md,
//! "The fibres model"). The path-traced truth lets light scatter from fibre to fibre as often as it likes; in a
//! light-coloured lock most of the light in its shadowed side has come that way (the truth's
//! `multiple-scattering` step). Here each probe point sees, along each of the probe's directions, the meshes'
//! light through the hair in front of them, the part `e^(−N)` of the rays that cross none of its `N` fibres,
//! and the hair itself for the rest, `1 − e^(−N)`, at the radiance its fibres leave with where the ray first
//! meets them; a mesh adds the hair's radiance times its albedo and the part of its hemisphere the hair covers.
//! A fibre leaves with `ā = ā_f + ā_b` of the mean radiance `Ī` arriving from around it, and with what it
//! scatters backwards of the light that reaches it, `ā_b l T / 4` (a collimated irradiance `π l T` that a
//! cylinder sends on as a mean radiance over its orientations and the directions, `T = max(e^(−n), T_f)`
//! through the `n` fibres in front). Its forward scattering of that light is not a source here: it goes on
//! along the light as `T_f`, dual scattering's global term, which the eye pass already shades (taken as a source
//! too it lit `back-lit`'s hair 1.4–1.7× the truth). The two make a fixed point, `L = D + ā Ī(L)`, found
//! by iteration ([`incident`]); the probe is `Ī`, what a hair fragment then scatters as it scattered one
//! fibre's light.

use glam::Vec3;

/// Iterations of the fixed point: each multiplies the error by at most `ā` times the mean over the directions
/// of `1 − e^(−N)` plus a mesh's gain times `e^(−N)`, below 1 (32 rounds leave 0.9³² ≈ 0.03 of the first
/// round's error at a ratio of 0.9, 0.7³² ≈ 1e-5 at 0.7).
pub const ITERATIONS: usize = 32;

/// What a probe point sees along one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The radiance of the mesh the direction meets (zero where it meets none), before the hair in front of it.
    pub mesh: Vec3,
    /// The chance the ray crosses no fibre before the mesh (or leaving the hair), `e^(−N)`.
    pub clear: f32,
    /// Where it first meets a fibre, on average.
    pub hair_at: Vec3,
    /// The mesh's albedo times the part of its hemisphere the hair covers: the mesh adds this times the hair's
    /// radiance at [`View::mesh_at`] (zero where the direction meets no mesh).
    pub mesh_gain: Vec3,
    /// Where the direction meets the mesh.
    pub mesh_at: Vec3,
}

/// The mean radiance arriving at each probe point (its `views`) when the points' fibres leave with `direct`
/// (what they scatter back of the light, `ā_b l T / 4`) plus `albedo` times what arrives: the fixed point over
/// [`ITERATIONS`] rounds, starting from `direct`. `field` turns the points' leaving radiances into a radiance
/// at any place (the probe's lattice), read where each view meets the hair.
pub fn incident<G: Fn(Vec3) -> Vec3>(
    direct: &[Vec3],
    views: &[Vec<View>],
    albedo: Vec3,
    field: impl Fn(&[Vec3]) -> G,
) -> Vec<Vec3> {
    let gather = |read: &G, views: &[View]| {
        views
            .iter()
            .map(|v| {
                let mesh = v.mesh + v.mesh_gain * read(v.mesh_at);
                mesh * v.clear + read(v.hair_at) * (1.0 - v.clear)
            })
            .sum::<Vec3>()
            / views.len().max(1) as f32
    };
    let mut leaving = direct.to_vec();
    let mut arriving = vec![Vec3::ZERO; direct.len()];
    for _ in 0..ITERATIONS {
        let read = field(&leaving);
        for ((a, l), (v, d)) in arriving
            .iter_mut()
            .zip(leaving.iter_mut())
            .zip(views.iter().zip(direct))
        {
            *a = gather(&read, v);
            *l = *d + albedo * *a;
        }
    }
    arriving
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points that all see the same: a mesh of radiance `M` that the hair lights with gain `g` through hair that
    /// lets `c` of the rays by, the hair's mean leaving radiance `L` (the field reads the points' mean) for the
    /// rest. The fixed point of `L = D + ā ((M + g L) c + L (1 − c))` is
    /// `L = (D + ā M c) / (1 − ā (g c + 1 − c))` and the arriving radiance `Ī = (M + g L) c + L (1 − c)`, per
    /// channel; after [`ITERATIONS`] rounds within `1e-4` of it for a lossy fibre and a nearly lossless one
    /// (ā 0.95, contraction 0.95 × 0.6 = 0.57: 0.57³² ≈ 1e-8), with and without the mesh's gain. With no hair
    /// (`c = 1`) and no gain the probe is the meshes' radiance alone, whatever the fibres leave with.
    #[test]
    fn the_fixed_point_is_the_closed_form() {
        let mesh = Vec3::new(0.5, 0.3, 0.1);
        let direct = Vec3::new(0.2, 0.1, 0.05);
        let mean = |values: &[Vec3]| {
            let m = values.iter().sum::<Vec3>() / values.len() as f32;
            move |_: Vec3| m
        };
        for (albedo, gain) in [
            (Vec3::new(0.9, 0.7, 0.4), Vec3::ZERO),
            (Vec3::splat(0.95), Vec3::ZERO),
            (Vec3::new(0.9, 0.7, 0.4), Vec3::new(0.2, 0.15, 0.1)),
        ] {
            let clear = 0.4;
            let view = View {
                mesh,
                clear,
                hair_at: Vec3::ZERO,
                mesh_gain: gain,
                mesh_at: Vec3::ONE,
            };
            let views = vec![vec![view; 8]; 5];
            let got = incident(&[direct; 5], &views, albedo, mean);
            let leaving = (direct + albedo * mesh * clear)
                / (Vec3::ONE - albedo * (gain * clear + Vec3::splat(1.0 - clear)));
            let expected = (mesh + gain * leaving) * clear + leaving * (1.0 - clear);
            for g in &got {
                assert!((*g - expected).abs().max_element() < 1e-4, "{g} vs {expected}");
            }
        }
        let bare = View {
            mesh,
            clear: 1.0,
            hair_at: Vec3::ZERO,
            mesh_gain: Vec3::ZERO,
            mesh_at: Vec3::ONE,
        };
        for g in incident(&[direct; 5], &vec![vec![bare; 8]; 5], Vec3::splat(0.9), mean) {
            assert!((g - mesh).abs().max_element() < 1e-6, "{g}");
        }
    }
}
