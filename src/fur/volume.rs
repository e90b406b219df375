//! The undercoat's volume data (spec §3.2, B.3 #11–13): per sub-element a density `ρ ∈ [0, 1]` and a unit
//! tangent `τ`, generated from the 3D simplex noise of [`super::noise`] at the sub-element's centre.
//!
//! The paper applies "a 2D noise texture ... across all volumetric layers" with "an increasing randomization
//! of uv-coordinates as we approach the topmost layers", and randomises "the interpolated, smoothed vertex
//! normals towards the topmost volume layers" into tangents. The project's meshes have no UVs, so every field
//! here is evaluated at the centre projected onto the base triangle, `x_base = Σ λ_k P_k` (constant across
//! layers, the paper's 2D texture), and the uv randomisation becomes a 3D offset:
//!
//! - clumps `C = smoothstep(θ − ε, θ + ε, N(f·x_base + w^γ·J·r))`, `r` a random unit vector per sub-element;
//! - density control `D = 1 − v_d·(½ + ½ N(f_d·x_base))` (the paper's density texture, procedural);
//! - length control `ℓ = 1 − v_ℓ·(½ + ½ N(f_ℓ·x_base))`: hair ends at shell height `ℓ`, so `ρ = 0` above it;
//! - `ρ = D·C` where `w ≤ ℓ`, else 0; `τ = normalize(N_interp + w·J_t·r')`, `N_interp = Σ λ_k N_k`.
//!
//! `w` is the centre's shell height `(i_l + ½)/n_l`. The random vectors are hashed from the bits of the
//! sub-element's centre (its shell-space point), not from its global index, so the volume does not depend on
//! the order of the mesh's triangles (FC-6). The paper gives none of the constants; [`VolumeParams::default`]
//! says what was chosen and why.

use glam::{IVec3, Vec3};

use super::index::SubTriangle;
use super::noise::{hash3, pcg, simplex3};
use super::shell::Shell;

/// Seeds of the independent fields (any distinct words).
const SEED_CLUMPS: u32 = 0x1f12_3bb5;
const SEED_DENSITY: u32 = 0x5d7a_91c3;
const SEED_LENGTH: u32 = 0x9e37_79b9;
const SEED_JITTER: u32 = 0x2545_f491;
const SEED_TANGENT: u32 = 0x6c8e_9cf5;

/// The clump (cone) field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clumps {
    /// Noise frequency `f`, cycles per world unit.
    pub frequency: f32,
    /// Threshold `θ` on the noise (in [−1, 1]): higher means thinner clumps.
    pub threshold: f32,
    /// Half width `ε` of the smoothstep around `θ`.
    pub softness: f32,
    /// uv-randomisation amplitude `J` at the top, world units.
    pub jitter: f32,
    /// Exponent `γ` of the jitter's growth with height `w^γ`.
    pub jitter_power: f32,
}

/// Volume parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeParams {
    /// The clump field; `None` makes `C = 1` (a homogeneous medium, used for hand-computed tests).
    pub clumps: Option<Clumps>,
    /// Density variation `v_d ∈ [0, 1]` (0 = uniform density).
    pub density_variation: f32,
    /// Frequency `f_d` of the density control.
    pub density_frequency: f32,
    /// Length variation `v_ℓ ∈ [0, 1)` (0 = every hair reaches the top of the shell).
    pub length_variation: f32,
    /// Frequency `f_ℓ` of the length control.
    pub length_frequency: f32,
    /// Tangent randomisation `J_t` at the top (0 = tangents along the smoothed normal).
    pub tangent_jitter: f32,
}

impl Default for VolumeParams {
    /// For a 1 cm shell (the default [`super::shell::ShellParams`]): clumps 2.5 mm apart (`f` = 400/m, about
    /// the cone spacing of the paper's Fig. 2 relative to the hair length), `θ = 0` (half the base covered),
    /// `ε = 0.15` (soft cone flanks), `J` = 1.25 mm growing as `w²` (bases stay clumped, tips spread into
    /// cones); density varying by 30 % over 2 cm patches and length by 40 % over 3 cm (fur is never even);
    /// tangents tilted by up to 0.5 at the tips (the undercoat stands, then frizzes).
    fn default() -> Self {
        VolumeParams {
            clumps: Some(Clumps {
                frequency: 400.0,
                threshold: 0.0,
                softness: 0.15,
                jitter: 0.00125,
                jitter_power: 2.0,
            }),
            density_variation: 0.3,
            density_frequency: 50.0,
            length_variation: 0.4,
            length_frequency: 33.0,
            tangent_jitter: 0.5,
        }
    }
}

impl VolumeParams {
    /// A homogeneous medium: `ρ = 1` everywhere, tangents along the smoothed normal.
    pub fn uniform() -> Self {
        VolumeParams {
            clumps: None,
            density_variation: 0.0,
            density_frequency: 1.0,
            length_variation: 0.0,
            length_frequency: 1.0,
            tangent_jitter: 0.0,
        }
    }

    /// Checks the parameters; the error names the key.
    pub fn validate(&self) -> Result<(), super::InvalidParam> {
        let bad = |key: &str, v: f32, rule: &str| Err(super::InvalidParam::new(key, v, rule));
        let unit = |v: f32| v.is_finite() && (0.0..=1.0).contains(&v);
        if !unit(self.density_variation) {
            return bad(
                "fur.density_variation",
                self.density_variation,
                "must be in [0, 1]",
            );
        }
        if !(self.length_variation.is_finite() && (0.0..1.0).contains(&self.length_variation)) {
            return bad("fur.length_variation", self.length_variation, "must be in [0, 1)");
        }
        if !(self.tangent_jitter.is_finite() && self.tangent_jitter >= 0.0) {
            return bad(
                "fur.tangent_jitter",
                self.tangent_jitter,
                "must be finite and ≥ 0",
            );
        }
        if let Some(c) = self.clumps {
            if !(c.frequency.is_finite() && c.frequency > 0.0) {
                return bad("fur.noise_frequency", c.frequency, "must be finite and > 0");
            }
            if !(c.softness.is_finite() && c.softness > 0.0) {
                return bad("fur.noise_softness", c.softness, "must be finite and > 0");
            }
            if !c.threshold.is_finite() {
                return bad("fur.noise_threshold", c.threshold, "must be finite");
            }
            if !(c.jitter.is_finite() && c.jitter >= 0.0) {
                return bad("fur.noise_jitter", c.jitter, "must be finite and ≥ 0");
            }
        }
        Ok(())
    }
}

/// One sub-element's volume data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Density `ρ ∈ [0, 1]`.
    pub density: f32,
    /// Unit hair tangent `τ`.
    pub tangent: Vec3,
}

/// Hermite smoothstep.
fn smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A random unit vector from hash `h` (uniform on the sphere: z and the azimuth from two hashes).
fn random_unit(h: u32) -> Vec3 {
    let a = pcg(h);
    let b = pcg(a);
    let z = 2.0 * (a >> 8) as f32 / (1u32 << 24) as f32 - 1.0;
    let phi = std::f32::consts::TAU * (b >> 8) as f32 / (1u32 << 24) as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The volume: a function of the sub-element, evaluated on the fly (the paper's "computing densities on the
/// fly"; storing it is [`Volume::store`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    pub params: VolumeParams,
}

impl Volume {
    /// The data of sub-element (`layer`, `local`) of face `f`.
    pub fn sample(&self, shell: &Shell, f: usize, layer: u32, local: u32) -> Sample {
        let p = &self.params;
        let d = shell.levels[f];
        let lambda = SubTriangle::from_index(local, d).centroid(d);
        let w = (layer as f32 + 0.5) / shell.layers as f32;
        let face = shell.mesh.faces[f];
        let (base, _) = shell.prism(f);
        let x = lambda[0] * base[0] + lambda[1] * base[1] + lambda[2] * base[2];
        let key = shell.point(f, lambda, w).to_array().map(|c| c.to_bits() as i32);
        let key = IVec3::from_array(key);
        let length = 1.0 - p.length_variation * (0.5 + 0.5 * simplex3(x * p.length_frequency, SEED_LENGTH));
        let n: Vec3 = (0..3)
            .map(|k| lambda[k] * shell.mesh.normals[face[k] as usize])
            .sum::<Vec3>()
            .normalize();
        let tangent = (n + w * p.tangent_jitter * random_unit(hash3(key, SEED_TANGENT))).normalize();
        if w > length {
            return Sample {
                density: 0.0,
                tangent,
            };
        }
        let control =
            1.0 - p.density_variation * (0.5 + 0.5 * simplex3(x * p.density_frequency, SEED_DENSITY));
        let clumps = p.clumps.map_or(1.0, |c| {
            let offset = w.powf(c.jitter_power) * c.jitter * random_unit(hash3(key, SEED_JITTER));
            let v = simplex3((x + offset) * c.frequency, SEED_CLUMPS);
            smoothstep(c.threshold - c.softness, c.threshold + c.softness, v)
        });
        Sample {
            density: control * clumps,
            tangent,
        }
    }

    /// Every sub-element's data in global-index order (eq. 3): the stored mode, 16 B a sub-element on the GPU.
    pub fn store(&self, shell: &Shell) -> Vec<Sample> {
        (0..shell.sub_elements)
            .map(|g| {
                let (f, layer, local) = shell.split_global(g);
                self.sample(shell, f, layer, local)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fur::mesh::FurMesh;
    use crate::fur::shell::ShellParams;
    use crate::scene::fur_shapes as shapes;

    fn cylinder_shell() -> Shell {
        let m = FurMesh::build("cyl", &shapes::cylinder(0.04, 0.1, 16, 4)).unwrap();
        Shell::build(
            m,
            &ShellParams {
                height: 0.01,
                layers: 8,
                ..ShellParams::default()
            },
        )
        .unwrap()
    }

    #[test]
    fn the_uniform_volume_is_one_along_the_normal() {
        let s = cylinder_shell();
        let v = Volume {
            params: VolumeParams::uniform(),
        };
        for x in v.store(&s) {
            assert_eq!(x.density, 1.0);
        }
        // Face 0's corners are radial normals at φ = 0 and φ = τ/16; the centroid of layer 0's local 0 is
        // a convex mix of them, so the tangent is horizontal (y = 0).
        let t = v.sample(&s, 0, 0, 0).tangent;
        assert!(t.y.abs() < 1e-6 && (t.length() - 1.0).abs() < 1e-6, "{t}");
    }

    #[test]
    fn default_volume_is_in_range_varied_and_tangents_spread_towards_the_top() {
        let s = cylinder_shell();
        let v = Volume {
            params: VolumeParams::default(),
        };
        assert_eq!(v.params.validate(), Ok(()));
        let all = v.store(&s);
        assert!(all.iter().all(|x| (0.0..=1.0).contains(&x.density)));
        let empty = all.iter().filter(|x| x.density == 0.0).count();
        let full = all.iter().filter(|x| x.density > 0.5).count();
        assert!(
            empty > 0 && full > 0,
            "{empty} empty, {full} over 0.5 of {}",
            all.len()
        );
        // Mean deviation of τ from the smoothed normal, bottom layer vs top layer.
        let dev = |layer: u32| {
            let mut sum = 0.0;
            let mut n = 0;
            for f in 0..s.mesh.faces.len() {
                for i in 0..1u32 << (2 * s.levels[f]) {
                    let l = SubTriangle::from_index(i, s.levels[f]).centroid(s.levels[f]);
                    let face = s.mesh.faces[f];
                    let nn: Vec3 = (0..3).map(|k| l[k] * s.mesh.normals[face[k] as usize]).sum();
                    sum += 1.0 - v.sample(&s, f, layer, i).tangent.dot(nn.normalize());
                    n += 1;
                }
            }
            sum / n as f32
        };
        let (bottom, top) = (dev(0), dev(s.layers - 1));
        assert!(bottom < 0.01 && top > 5.0 * bottom, "bottom {bottom}, top {top}");
    }

    #[test]
    fn bad_volume_parameters_name_their_key() {
        let p = VolumeParams {
            length_variation: 1.0,
            ..VolumeParams::default()
        };
        assert_eq!(
            p.validate().unwrap_err().to_string(),
            "invalid fur.length_variation = 1: must be in [0, 1)"
        );
    }
}
