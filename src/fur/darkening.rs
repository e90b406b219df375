//! Local self-shadowing of guard hairs (Andersen et al. 2016 §3.1: "an exponentially increasing darkening of
//! hair strands near the base mesh", after Neulander & van de Panne 1998 and Neulander 2004). The paper states
//! the model's form but no parameters; ours ties it to the undercoat: a guard-hair point at height `y` above
//! the base lies under `max(h_0 − y, 0)` of undercoat of extinction `σ_0 = fur.density / fur.height`, and its
//! shading is scaled by that column's transmittance `exp(−β σ_0 max(h_0 − y, 0))`, `β = fur.base_darkening`
//! (1: the undercoat's own density, 0: off). The CPU model of `guard_darkening` in
//! `shaders/common/guard_darkening.wgsl`; the heights are the strand vertices' `base_height`.

use glam::Vec3;

/// Each point's height above its strand's root along the root's direction (the first segment's: generated
/// guard hairs start along the base normal), clamped at 0; a single point or a zero-length first segment has
/// height 0 throughout.
pub fn base_heights(strand: &[Vec3]) -> Vec<f32> {
    let (Some(&root), Some(&next)) = (strand.first(), strand.get(1)) else {
        return vec![0.0; strand.len()];
    };
    let Some(normal) = (next - root).try_normalize() else {
        return vec![0.0; strand.len()];
    };
    strand.iter().map(|p| (*p - root).dot(normal).max(0.0)).collect()
}

/// The darkening factor at height `height` under undercoat `shell_height` thick of extinction `sigma` (per world
/// unit, already times `β`): `exp(−sigma · max(shell_height − height, 0))`, 1 above the undercoat.
pub fn darkening(height: f32, shell_height: f32, sigma: f32) -> f32 {
    crate::visibility::transmittance(sigma * (shell_height - height).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heights_follow_the_root_direction_and_clamp_below_the_root() {
        let strand = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 2.5, 3.0),
            Vec3::new(1.5, 3.0, 3.0),
            Vec3::new(3.0, 1.0, 3.0),
        ];
        assert_eq!(base_heights(&strand), vec![0.0, 0.5, 1.0, 0.0]);
        assert_eq!(base_heights(&strand[..1]), vec![0.0]);
        assert_eq!(base_heights(&[Vec3::ONE, Vec3::ONE]), vec![0.0, 0.0]);
    }

    /// By hand: half-way up a 1 cm undercoat of σ_0 = 800 / m: exp(−800 · 0.005) = exp(−4); at the root
    /// exp(−8); at and above the shell's top 1.
    #[test]
    fn darkening_is_the_undercoat_column_transmittance() {
        assert!((darkening(0.005, 0.01, 800.0) - (-4.0f32).exp()).abs() < 1e-7);
        assert!((darkening(0.0, 0.01, 800.0) - (-8.0f32).exp()).abs() < 1e-8);
        assert_eq!(darkening(0.01, 0.01, 800.0), 1.0);
        assert_eq!(darkening(0.03, 0.01, 800.0), 1.0);
        assert_eq!(darkening(0.0, 0.01, 0.0), 1.0);
    }
}
