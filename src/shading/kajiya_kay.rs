//! Kajiya–Kay hair shading (Kajiya & Kay 1989, "Rendering Fur with Three Dimensional Textures"): a diffuse term
//! `∝ sin(τ, l)` and a specular term `cos(angle between the reflected cone and the eye)^p`. The CPU model of
//! `shaders/common/kajiya_kay.wgsl`, also the fur's phase function (`fur::march`).

use glam::Vec3;

/// Diffuse weight, specular weight and exponent, as `shaders/common/kajiya_kay.wgsl`.
const DIFFUSE: f32 = 0.75;
const SPECULAR: f32 = 0.35;
const EXPONENT: f32 = 60.0;

/// Kajiya–Kay shading of a strand with unit `tangent` lit from `to_light`, seen from `to_eye`.
pub fn kajiya_kay(tangent: Vec3, to_light: Vec3, to_eye: Vec3, base: Vec3) -> Vec3 {
    let t_l = tangent.dot(to_light).clamp(-1.0, 1.0);
    let t_e = tangent.dot(to_eye).clamp(-1.0, 1.0);
    let sin_tl = (1.0 - t_l * t_l).sqrt();
    let sin_te = (1.0 - t_e * t_e).sqrt();
    let specular = SPECULAR * (t_l * t_e + sin_tl * sin_te).max(0.0).powf(EXPONENT);
    base * (DIFFUSE * sin_tl) + Vec3::splat(specular)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kajiya_kay_by_hand() {
        // τ ⟂ l and τ ⟂ e: sin = 1, the cone term cos = 1 ⇒ 0.75·base + 0.35.
        let c = kajiya_kay(Vec3::Y, Vec3::X, Vec3::Z, Vec3::new(1.0, 0.5, 0.0));
        assert!(
            (c - Vec3::new(1.1, 0.725, 0.35)).abs().max_element() < 1e-6,
            "{c}"
        );
        // τ ∥ l: no diffuse; the cone term is t_l·t_e = 0 ⇒ black.
        assert_eq!(kajiya_kay(Vec3::X, Vec3::X, Vec3::Z, Vec3::ONE), Vec3::ZERO);
    }
}
