//! The `[fur]` settings (spec B.12) and the fur of a scene built from them: the scene's first mesh (the
//! growth surface: the cylinder, the hat, a loaded scalp) welded and extruded into the shell, its volume and
//! the march parameters, with the CPU preprocessing times Table 1 reports (rows 1–2). The paper gives none
//! of the values; the defaults are [`ShellParams::default`], [`VolumeParams::default`] and
//! [`MarchParams::for_shell`], each documented where it is defined.

use std::time::Instant;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::march::{Emit, MAX_STEPS, MarchParams, STEPS_PER_THICKNESS};
use super::mesh::FurMesh;
use super::shell::{Levels, MAX_LAYERS, Shell, ShellParams};
use super::volume::{Clumps, Volume, VolumeParams};
use crate::scene::Scene;

/// Which halves of the fur are drawn (Fig. 9 a/b/c).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FurMode {
    /// No shell: the scene's strands go through the selected eye transparency technique.
    #[default]
    Off,
    /// The volumetric shell alone (the undercoat).
    Implicit,
    /// The guard hairs alone (the scene's strands), in the typed lists.
    Explicit,
    /// Both, combined in the typed lists.
    Hybrid,
}

impl FurMode {
    pub const ALL: [FurMode; 4] = [
        FurMode::Off,
        FurMode::Implicit,
        FurMode::Explicit,
        FurMode::Hybrid,
    ];

    pub fn word(self) -> &'static str {
        match self {
            FurMode::Off => "off",
            FurMode::Implicit => "implicit",
            FurMode::Explicit => "explicit",
            FurMode::Hybrid => "hybrid",
        }
    }

    pub fn shell(self) -> bool {
        matches!(self, FurMode::Implicit | FurMode::Hybrid)
    }

    pub fn strands(self) -> bool {
        matches!(self, FurMode::Explicit | FurMode::Hybrid)
    }
}

/// How shell fragments meet the explicit ones (§3.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Blending {
    /// One shell fragment per ray, blended like any other.
    Naive,
    /// One shell fragment per ray, its alpha reduced by the explicit fragments behind it (eq. 4).
    Simplified,
    /// One fragment per group of `group_steps` march steps; `group_steps = 1` is the reference.
    #[default]
    Virtual,
}

impl Blending {
    pub const ALL: [Blending; 3] = [Blending::Naive, Blending::Simplified, Blending::Virtual];

    pub fn word(self) -> &'static str {
        match self {
            Blending::Naive => "naive",
            Blending::Simplified => "simplified",
            Blending::Virtual => "virtual",
        }
    }
}

/// What the fur's resolve shows (spec B.12's inspection views).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FurView {
    /// The shaded, blended image.
    #[default]
    Shaded,
    /// Each fragment coloured by its type (guard hair yellow, shell blue, virtual cyan), blended as shaded.
    Types,
    /// Fragments per pixel, blue through green to red at the frame's deepest list.
    Fragments,
}

impl FurView {
    pub const ALL: [FurView; 3] = [FurView::Shaded, FurView::Types, FurView::Fragments];

    pub fn word(self) -> &'static str {
        match self {
            FurView::Shaded => "shaded",
            FurView::Types => "types",
            FurView::Fragments => "fragments",
        }
    }
}

/// `[fur]`: the fur of the scene's first mesh and how it is rendered.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FurSettings {
    pub mode: FurMode,
    pub blending: Blending,
    pub view: FurView,
    /// Simplified blending's attenuation `a` of eq. (4) times the shell height (scale-free).
    pub attenuation: f32,
    /// Virtual fragments: march steps per fragment `k`.
    pub group_steps: u32,
    /// Shell height `h_0`, world units.
    pub height: f32,
    /// Layers per prism `n_l`.
    pub layers: u32,
    /// Highest subdivision level `d_max` (dynamic resolution picks each face's level from its area).
    pub max_level: u32,
    /// March steps per (smallest) shell height.
    pub steps_per_thickness: u32,
    /// Step cap per shell fragment.
    pub max_steps: u32,
    /// Early exit when the eye transmittance falls below this (0: never).
    pub epsilon_t: f32,
    /// Steps of each light march (0: unattenuated light).
    pub light_steps: u32,
    /// Optical depth `σ_0 h_0` of a full-height column of density 1.
    pub density: f32,
    /// Undercoat colour (Kajiya–Kay base, linear).
    pub colour: [f32; 3],
    /// Guard hairs' base darkening `β` ([`super::darkening`]): the multiple of the undercoat's extinction
    /// `σ_0` a guard hair is darkened by below the shell's top (1: the undercoat's own; 0: off).
    pub base_darkening: f32,
    /// Directional lights of the guard hairs' environment ([`super::environment`]; the paper's 16): 1 is the
    /// scene's light alone; the undercoat always takes the scene's light.
    pub env_lights: u32,
    /// An equirectangular map the environment's lights are sampled from ([`super::env_map`]: Radiance `.hdr` or
    /// sRGB PNG, twice as wide as high); none: the procedural sky ([`super::environment::Sky`]).
    pub env_map: Option<std::path::PathBuf>,
    /// Clump noise frequency, cycles per world unit.
    pub noise_frequency: f32,
    /// Clump threshold in [-1, 1] (higher: thinner clumps).
    pub noise_threshold: f32,
    /// Half width of the clumps' soft edge.
    pub noise_softness: f32,
}

impl Default for FurSettings {
    fn default() -> Self {
        let shell = ShellParams::default();
        let clumps = VolumeParams::default()
            .clumps
            .expect("the default volume has clumps");
        let Levels::Dynamic { max } = shell.levels else {
            unreachable!("the default shell uses dynamic levels")
        };
        FurSettings {
            mode: FurMode::Off,
            blending: Blending::Virtual,
            view: FurView::Shaded,
            attenuation: 4.0,
            group_steps: 4,
            height: shell.height,
            layers: shell.layers,
            max_level: max,
            steps_per_thickness: STEPS_PER_THICKNESS,
            max_steps: MAX_STEPS,
            epsilon_t: super::march::EPSILON_T,
            light_steps: 8,
            density: 8.0,
            colour: [0.45, 0.3, 0.2],
            base_darkening: 1.0,
            env_lights: 1,
            env_map: None,
            noise_frequency: clumps.frequency,
            noise_threshold: clumps.threshold,
            noise_softness: clumps.softness,
        }
    }
}

/// Most subdivision levels `fur.max_level` may ask (4^8 sub-triangles a layer).
pub const MAX_LEVEL: u32 = 8;

impl FurSettings {
    /// Range checks, each naming its key.
    pub fn validate(&self) -> Result<(), super::InvalidParam> {
        let finite = |key: &str, v: f32, ok: bool, rule: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(super::InvalidParam::new(&format!("fur.{key}"), v, rule))
            }
        };
        finite(
            "attenuation",
            self.attenuation,
            self.attenuation >= 0.0,
            "must be finite and ≥ 0",
        )?;
        finite("height", self.height, self.height > 0.0, "must be finite and > 0")?;
        finite(
            "epsilon_t",
            self.epsilon_t,
            (0.0..1.0).contains(&self.epsilon_t),
            "must be in [0, 1)",
        )?;
        finite(
            "density",
            self.density,
            self.density >= 0.0,
            "must be finite and ≥ 0",
        )?;
        finite(
            "base_darkening",
            self.base_darkening,
            self.base_darkening >= 0.0,
            "must be finite and ≥ 0",
        )?;
        finite(
            "noise_frequency",
            self.noise_frequency,
            self.noise_frequency > 0.0,
            "must be finite and > 0",
        )?;
        finite(
            "noise_threshold",
            self.noise_threshold,
            (-1.0..=1.0).contains(&self.noise_threshold),
            "must be in [-1, 1]",
        )?;
        finite(
            "noise_softness",
            self.noise_softness,
            self.noise_softness > 0.0,
            "must be finite and > 0",
        )?;
        for c in self.colour {
            finite(
                "colour",
                c,
                c >= 0.0,
                "must hold three finite non-negative numbers",
            )?;
        }
        let count = |key: &str, v: u32, lo: u32, hi: u32| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(super::InvalidParam::new(
                    &format!("fur.{key}"),
                    v,
                    &format!("must be in {lo}..={hi}"),
                ))
            }
        };
        count("group_steps", self.group_steps, 1, MAX_STEPS)?;
        count("layers", self.layers, 1, MAX_LAYERS)?;
        count("max_level", self.max_level, 0, MAX_LEVEL)?;
        count("steps_per_thickness", self.steps_per_thickness, 1, 1024)?;
        count("max_steps", self.max_steps, 1, 4096)?;
        count("light_steps", self.light_steps, 0, 256)?;
        count(
            "env_lights",
            self.env_lights,
            1,
            super::environment::MAX_ENV_LIGHTS as u32,
        )
    }

    pub fn shell_params(&self) -> ShellParams {
        ShellParams {
            height: self.height,
            layers: self.layers,
            cell: None,
            levels: Levels::Dynamic { max: self.max_level },
        }
    }

    pub fn volume_params(&self) -> VolumeParams {
        let clumps = Clumps {
            frequency: self.noise_frequency,
            threshold: self.noise_threshold,
            softness: self.noise_softness,
            ..VolumeParams::default()
                .clumps
                .expect("the default volume has clumps")
        };
        VolumeParams {
            clumps: Some(clumps),
            ..VolumeParams::default()
        }
    }

    /// The march through `shell` lit from `to_light` with radiance `light`, emitting as the blending asks. The
    /// step is the nominal height `h_0` over `steps_per_thickness`, not the smallest height as
    /// [`MarchParams::for_shell`] takes it: prisms shrunk at a concave junction would shrink the step everywhere
    /// (measured on fur-hat, whose crown-brim junction shrinks to 0.17 h_0: 7561 of 10782 rays stopped at
    /// `max_steps` with the smallest height, at 320×240).
    pub fn march_params(&self, shell: &Shell, to_light: Vec3, light: Vec3) -> MarchParams {
        let base = MarchParams::for_shell(shell);
        let step = shell.height / self.steps_per_thickness as f32;
        MarchParams {
            sigma: self.density / self.height,
            step,
            max_steps: self.max_steps,
            epsilon_t: self.epsilon_t,
            light_steps: self.light_steps,
            light_step: step,
            to_light,
            light,
            colour: Vec3::from_array(self.colour),
            emit: match self.blending {
                Blending::Virtual => Emit::Virtual(self.group_steps),
                Blending::Naive | Blending::Simplified => Emit::Shell,
            },
            ..base
        }
    }

    /// The guard hairs' base darkening per world unit: `β σ_0 = base_darkening · density / height`.
    pub fn guard_sigma(&self) -> f32 {
        self.base_darkening * self.density / self.height
    }

    /// Simplified blending's `a` per world unit.
    pub fn attenuation_per_unit(&self) -> f32 {
        self.attenuation / self.height
    }
}

/// A scene's fur: the shell and volume on its first mesh, with what building them cost (Table 1 rows 1–2 on
/// the CPU; row 2's upload is the GPU state's).
#[derive(Clone, Debug)]
pub struct FurScene {
    pub shell: Shell,
    pub volume: Volume,
    /// Table 1 row 1: weld, orient, neighbours, normals, prisms (ms).
    pub process_ms: f64,
    /// Warnings of the mesh and shell builds (fixed windings, shrunk prisms), each naming the mesh.
    pub warnings: Vec<String>,
    /// The map of `fur.env_map`, read once (none: the procedural sky).
    pub env_map: Option<std::sync::Arc<super::env_map::EnvMap>>,
}

/// Why a scene's fur cannot be built; the message names the key or the mesh.
#[derive(Debug, thiserror::Error)]
pub enum FurSceneError {
    #[error(transparent)]
    Invalid(#[from] super::InvalidParam),
    #[error("fur.mode = {mode}: the scene has no mesh to grow fur on")]
    NoMesh { mode: &'static str },
    #[error(transparent)]
    Mesh(#[from] super::mesh::MeshError),
    #[error(transparent)]
    Shell(#[from] super::shell::ShellError),
    #[error(transparent)]
    EnvMap(#[from] super::env_map::EnvMapError),
}

impl FurScene {
    /// The fur of `scene`'s first mesh; `None` when `s.mode` is off. An error names the key or the mesh.
    pub fn build(scene: &Scene, s: &FurSettings) -> Result<Option<FurScene>, FurSceneError> {
        if s.mode == FurMode::Off {
            return Ok(None);
        }
        s.validate()?;
        let Some(mesh) = scene.meshes.first() else {
            return Err(FurSceneError::NoMesh { mode: s.mode.word() });
        };
        let start = Instant::now();
        let name = "the scene's first mesh";
        let fur_mesh = FurMesh::build(name, mesh)?;
        let mut warnings: Vec<String> = fur_mesh.report.warning(name).into_iter().collect();
        let shell = Shell::build(fur_mesh, &s.shell_params())?;
        warnings.extend(shell.report.warning(name));
        let volume = Volume {
            params: s.volume_params(),
        };
        volume.params.validate()?;
        let env_map = match &s.env_map {
            Some(path) => Some(std::sync::Arc::new(super::env_map::EnvMap::load(path)?)),
            None => None,
        };
        Ok(Some(FurScene {
            shell,
            volume,
            process_ms: start.elapsed().as_secs_f64() * 1e3,
            warnings,
            env_map,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_name_their_key() {
        assert_eq!(FurSettings::default().validate(), Ok(()));
        let bad = |f: fn(&mut FurSettings)| {
            let mut s = FurSettings::default();
            f(&mut s);
            s.validate().unwrap_err().to_string()
        };
        assert_eq!(
            bad(|s| s.height = f32::NAN),
            "invalid fur.height = NaN: must be finite and > 0"
        );
        assert_eq!(
            bad(|s| s.group_steps = 0),
            "invalid fur.group_steps = 0: must be in 1..=256"
        );
        assert_eq!(
            bad(|s| s.layers = 300),
            "invalid fur.layers = 300: must be in 1..=256"
        );
        assert_eq!(
            bad(|s| s.attenuation = -1.0),
            "invalid fur.attenuation = -1: must be finite and ≥ 0"
        );
        assert_eq!(
            bad(|s| s.epsilon_t = 1.0),
            "invalid fur.epsilon_t = 1: must be in [0, 1)"
        );
        assert_eq!(
            bad(|s| s.env_lights = 0),
            "invalid fur.env_lights = 0: must be in 1..=64"
        );
        assert_eq!(
            bad(|s| s.base_darkening = -0.5),
            "invalid fur.base_darkening = -0.5: must be finite and ≥ 0"
        );
        assert_eq!(
            bad(|s| s.colour = [0.1, f32::INFINITY, 0.1]),
            "invalid fur.colour = inf: must hold three finite non-negative numbers"
        );
    }

    #[test]
    fn settings_round_trip_through_toml_with_words() {
        let s = FurSettings {
            mode: FurMode::Hybrid,
            blending: Blending::Simplified,
            ..FurSettings::default()
        };
        let text = toml::to_string(&s).unwrap();
        assert!(
            text.contains("mode = \"hybrid\"") && text.contains("blending = \"simplified\""),
            "{text}"
        );
        assert_eq!(toml::from_str::<FurSettings>(&text).unwrap(), s);
    }
}
