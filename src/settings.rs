//! Everything a view of hairlab depends on — scene source, render settings, light, camera, shadow method — as one
//! serde struct. Presets are this struct in TOML (`presets/*.toml`); the GUI persists it between runs; the CLI
//! loads a preset and applies `--set key=value` overrides on the TOML tree before validating.

use crate::methods::{self, ParamValues, registry};
pub use crate::render::RenderSettings;
use crate::render::method::{ParamError, UnknownName};
use crate::render::transparency::{EyeTransparency, registry as techniques};
use crate::scene::generate::GenParams;
use crate::scene::{Camera, Light};
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    pub scene: SceneSettings,
    pub render: RenderSettings,
    pub light: Light,
    pub camera: Camera,
    pub method: MethodSettings,
    pub transparency: TransparencySettings,
    /// Hybrid fur on the scene's first mesh (off unless a preset asks).
    pub fur: crate::fur::settings::FurSettings,
    /// Where frame `k`'s strand points come from (still unless a preset asks).
    pub motion: crate::motion::MotionSettings,
}

/// Where the strands come from: a file when `file` is set, the generator otherwise (on `scalp`'s triangles when
/// that glTF file is given, on the generator's own ellipsoid or patch when not).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct SceneSettings {
    pub file: Option<PathBuf>,
    pub scalp: Option<PathBuf>,
    pub generator: GenParams,
}

/// The shadow method and its parameters. In TOML a choice parameter is its word (`spacing = "uniform"`); its
/// index still loads, so older numeric presets keep working.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawMethodSettings", into = "RawMethodSettings")]
pub struct MethodSettings {
    pub name: String,
    /// Parameters of the selected method; missing ones take the method's defaults.
    pub params: ParamValues,
}

/// A parameter value as TOML holds it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
enum RawValue {
    Number(f32),
    Word(String),
}

/// [`MethodSettings`] as TOML holds it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct RawMethodSettings {
    name: String,
    params: std::collections::BTreeMap<String, RawValue>,
}

impl Default for RawMethodSettings {
    fn default() -> Self {
        MethodSettings::default().into()
    }
}

/// Why a parameter's word cannot be read: the method or technique is unknown, or the key or word is not one of
/// its parameter's.
#[derive(Debug, thiserror::Error)]
pub enum WordError {
    #[error(transparent)]
    Name(#[from] UnknownName),
    #[error(transparent)]
    Param(#[from] ParamError),
}

/// A `[method]` or `[transparency]` parameter given as a word that cannot be read, naming its key.
#[derive(Debug, thiserror::Error)]
#[error("{section}.params.{key}: {error}")]
pub struct ParamWordError {
    pub section: &'static str,
    pub key: String,
    pub error: WordError,
}

/// Raw TOML parameters as values: numbers kept as they are (range checks come with [`Settings::validate`]), words
/// looked up by `word` (a choice's options); errors name the key under `section`.
fn params_from_raw(
    raw: std::collections::BTreeMap<String, RawValue>,
    section: &'static str,
    word: impl Fn(&str, &str) -> Result<f32, WordError>,
) -> Result<ParamValues, ParamWordError> {
    let mut params = ParamValues::new();
    for (k, v) in raw {
        let v = match v {
            RawValue::Number(x) => x,
            RawValue::Word(w) => word(&k, &w).map_err(|error| ParamWordError {
                section,
                key: k.clone(),
                error,
            })?,
        };
        params.insert(k, v);
    }
    Ok(params)
}

/// Values as TOML holds them: choices as their words (`spec` finds a key's parameter).
fn params_to_raw(
    params: ParamValues,
    spec: impl Fn(&str) -> Option<&'static crate::render::method::ParamSpec>,
) -> std::collections::BTreeMap<String, RawValue> {
    params
        .into_iter()
        .map(|(k, v)| {
            let raw = match spec(&k).and_then(|s| s.option(v)) {
                Some(w) => RawValue::Word(w.to_string()),
                None => RawValue::Number(v),
            };
            (k, raw)
        })
        .collect()
}

impl TryFrom<RawMethodSettings> for MethodSettings {
    type Error = ParamWordError;

    fn try_from(raw: RawMethodSettings) -> Result<Self, ParamWordError> {
        let params = params_from_raw(raw.params, "method", |k, w| {
            let method = registry::find(&raw.name)?;
            Ok(methods::parse_value(method, k, w)?)
        })?;
        Ok(MethodSettings {
            name: raw.name,
            params,
        })
    }
}

impl From<MethodSettings> for RawMethodSettings {
    fn from(m: MethodSettings) -> Self {
        let method = registry::find(&m.name).ok();
        let params = params_to_raw(m.params, |k| method.and_then(|m| methods::spec(m, k).ok()));
        RawMethodSettings { name: m.name, params }
    }
}

/// The eye transparency technique and its parameters (`[transparency]`, `--set transparency.name=…`); choices as
/// words, as for the method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawTransparencySettings", into = "RawTransparencySettings")]
pub struct TransparencySettings {
    pub name: String,
    /// Parameters of the selected technique; missing ones take the technique's defaults.
    pub params: ParamValues,
}

impl Default for TransparencySettings {
    fn default() -> Self {
        TransparencySettings {
            name: techniques::default_technique().name().into(),
            params: ParamValues::new(),
        }
    }
}

/// [`TransparencySettings`] as TOML holds it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct RawTransparencySettings {
    name: String,
    params: std::collections::BTreeMap<String, RawValue>,
}

impl Default for RawTransparencySettings {
    fn default() -> Self {
        TransparencySettings::default().into()
    }
}

impl TryFrom<RawTransparencySettings> for TransparencySettings {
    type Error = ParamWordError;

    fn try_from(raw: RawTransparencySettings) -> Result<Self, ParamWordError> {
        let params = params_from_raw(raw.params, "transparency", |k, w| {
            let technique = techniques::find(&raw.name)?;
            Ok(techniques::spec(technique, k)?.parse(w)?)
        })?;
        Ok(TransparencySettings {
            name: raw.name,
            params,
        })
    }
}

impl From<TransparencySettings> for RawTransparencySettings {
    fn from(t: TransparencySettings) -> Self {
        let technique = techniques::find(&t.name).ok();
        let params = params_to_raw(t.params, |k| technique.and_then(|t| techniques::spec(t, k).ok()));
        RawTransparencySettings { name: t.name, params }
    }
}

impl TransparencySettings {
    /// The registered technique (validated settings always have one).
    pub fn technique(&self) -> Result<&'static dyn EyeTransparency> {
        techniques::find(&self.name).map_err(|e| anyhow::anyhow!("transparency.name: {e}"))
    }
}

impl Default for MethodSettings {
    fn default() -> Self {
        MethodSettings {
            name: registry::default_method().name().into(),
            params: ParamValues::new(),
        }
    }
}

/// Built-in presets, available wherever the binary runs.
pub const BUILTIN_PRESETS: &[(&str, &str)] = &[
    ("default", include_str!("../presets/default.toml")),
    ("patch", include_str!("../presets/patch.toml")),
    ("stray-strand", include_str!("../presets/stray-strand.toml")),
    ("mixed-sizes", include_str!("../presets/mixed-sizes.toml")),
    ("many-clumps", include_str!("../presets/many-clumps.toml")),
    (
        "straight-grazing",
        include_str!("../presets/straight-grazing.toml"),
    ),
    (
        "unreal-deep-shadow",
        include_str!("../presets/unreal-deep-shadow.toml"),
    ),
    (
        "transparency-head",
        include_str!("../presets/transparency-head.toml"),
    ),
    (
        "transparency-dense",
        include_str!("../presets/transparency-dense.toml"),
    ),
    ("dense-coverage", include_str!("../presets/dense-coverage.toml")),
    ("fur-cylinder", include_str!("../presets/fur-cylinder.toml")),
    ("fur-hat", include_str!("../presets/fur-hat.toml")),
    ("wind", include_str!("../presets/wind.toml")),
    ("head-turn", include_str!("../presets/head-turn.toml")),
    ("stray-sweep", include_str!("../presets/stray-sweep.toml")),
    ("straight-motion", include_str!("../presets/straight-motion.toml")),
    ("back-lit", include_str!("../presets/back-lit.toml")),
    ("rim-lit", include_str!("../presets/rim-lit.toml")),
    ("blond", include_str!("../presets/blond.toml")),
];

impl SceneSettings {
    /// Builds the scene: loads `file` when set, runs the generator otherwise.
    pub fn build(&self) -> Result<crate::scene::Scene> {
        self.build_with(&mut crate::progress::Quiet)
    }

    /// [`SceneSettings::build`] telling `progress` how far the load or the growth got; once it answers `false`
    /// the build stops early (an error, or the strands so far: the caller drops either).
    pub fn build_with(&self, progress: &mut dyn crate::progress::Progress) -> Result<crate::scene::Scene> {
        use crate::scene::{Mesh, generate, gltf_load};
        match (&self.file, &self.scalp) {
            (Some(f), _) => crate::scene::load::load_scene_with(f, progress),
            (None, Some(scalp)) => {
                let meshes = gltf_load::load_gltf(scalp)?.meshes;
                if meshes.is_empty() {
                    anyhow::bail!(
                        "{}: a scalp needs triangles, and this file has none",
                        scalp.display()
                    );
                }
                generate::generate_on_scalp_with(&self.generator, &Mesh::merged(&meshes), progress)
                    .map_err(|e| anyhow::anyhow!("scene generator on {}: {e}", scalp.display()))
            }
            (None, None) => generate::generate_with(&self.generator, progress)
                .map_err(|e| anyhow::anyhow!("scene generator: {e}")),
        }
    }
}

/// The widest strand `render.strand_width` may give, in world units (the longest generated strand).
pub const MAX_STRAND_WIDTH: f32 = crate::scene::generate::MAX_LENGTH;

/// The largest turning angle (light azimuth, camera yaw) a setting may hold, in degrees: 100 turns.
pub const MAX_TURN_DEG: f32 = 36000.0;

impl Settings {
    /// Range checks with messages naming the key.
    pub fn validate(&self) -> Result<()> {
        let r = &self.render;
        if !(1..=8192).contains(&r.width) || !(1..=8192).contains(&r.height) {
            bail!(
                "render.width/height must be in 1..=8192 (got {}x{})",
                r.width,
                r.height
            );
        }
        if !(1..=4096).contains(&r.map_resolution) {
            bail!(
                "render.map_resolution must be in 1..=4096 (got {})",
                r.map_resolution
            );
        }
        if !(1..=crate::render::render_settings::MAX_SPP).contains(&r.spp) {
            bail!(
                "render.spp must be in 1..={} (got {})",
                crate::render::render_settings::MAX_SPP,
                r.spp
            );
        }
        if !(r.hair_alpha > 0.0 && r.hair_alpha <= 1.0) {
            bail!("render.hair_alpha must be in (0, 1] (got {})", r.hair_alpha);
        }
        if !(r.strand_width > 0.0 && r.strand_width <= MAX_STRAND_WIDTH) {
            bail!(
                "render.strand_width must be in (0, {MAX_STRAND_WIDTH}] world units (got {})",
                r.strand_width
            );
        }
        if !(r.ambient.is_finite() && r.ambient >= 0.0) {
            anyhow::bail!("render.ambient must be finite and at least 0 (got {})", r.ambient);
        }
        if !(1.0..=8.0).contains(&r.light_min_width) {
            bail!(
                "render.light_min_width must be in 1..=8 light texels (got {})",
                r.light_min_width
            );
        }
        if !crate::render::render_settings::LIGHT_SUPERSAMPLES.contains(&r.light_supersample) {
            bail!(
                "render.light_supersample must be 1, 2 or 4 (got {})",
                r.light_supersample
            );
        }
        let tiles = crate::render::caster::compute::RASTER_TILES;
        if r.raster_tile != 0 && !tiles.contains(&r.raster_tile) {
            bail!(
                "render.raster_tile must be 0 (one invocation per segment) or a tile side in {}..={} texels (got {})",
                tiles.start(),
                tiles.end(),
                r.raster_tile
            );
        }
        if let Err(e) = r.raster.stage(r.light_strands) {
            bail!("{e}");
        }
        for (k, c) in [
            ("render.hair_color", r.hair_color),
            ("render.background", r.background),
        ] {
            if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
                bail!("{k} must hold three finite non-negative numbers (got {c:?})");
            }
        }
        let l = &self.light;
        let c = &self.camera;
        for (key, v) in [
            ("light.azimuth_deg", l.azimuth_deg),
            ("light.elevation_deg", l.elevation_deg),
            ("light.distance", l.distance),
            ("light.cone_deg", l.cone_deg),
            ("light.intensity", l.intensity),
            ("camera.yaw_deg", c.yaw_deg),
            ("camera.pitch_deg", c.pitch_deg),
            ("camera.distance", c.distance),
            ("camera.fov_y_deg", c.fov_y_deg),
        ]
        .into_iter()
        .chain(c.target.iter().map(|&v| ("camera.target", v)))
        {
            if !v.is_finite() {
                bail!("{key} must be a finite number (got {v:?})");
            }
        }
        // Turning angles wrap, but far from 0 an f32 angle loses its precision (at 1e30 every sine is noise).
        for (key, v) in [
            ("light.azimuth_deg", l.azimuth_deg),
            ("camera.yaw_deg", c.yaw_deg),
        ] {
            if v.abs() > MAX_TURN_DEG {
                bail!("{key} must be within ±{MAX_TURN_DEG} degrees (got {v:?})");
            }
        }
        if !(-90.0..=90.0).contains(&c.pitch_deg) {
            bail!("camera.pitch_deg must be in [-90, 90] (got {:?})", c.pitch_deg);
        }
        if !(-90.0..=90.0).contains(&l.elevation_deg) {
            bail!(
                "light.elevation_deg must be in [-90, 90] (got {})",
                l.elevation_deg
            );
        }
        if !(1.0..=170.0).contains(&l.cone_deg) || l.distance < 1.01 || l.intensity < 0.0 {
            bail!("light: cone_deg in [1, 170], distance >= 1.01 scene radii, intensity >= 0");
        }
        if !(5.0..=120.0).contains(&c.fov_y_deg) || !c.distance.is_finite() || c.distance < 0.0 {
            bail!("camera: fov_y_deg in [5, 120] and distance >= 0 (0 frames the scene)");
        }
        let m = registry::find(&self.method.name).map_err(anyhow::Error::msg)?;
        methods::validate(m, &self.method.params).map_err(anyhow::Error::msg)?;
        self.fur.validate().map_err(anyhow::Error::msg)?;
        self.motion.validate()?;
        let t = self.transparency.technique()?;
        for (k, v) in &self.transparency.params {
            techniques::spec(t, k)
                .and_then(|s| s.check(*v))
                .map_err(|e| anyhow::anyhow!("transparency.params.{k}: {e}"))?;
        }
        Ok(())
    }

    /// Parses TOML; `origin` names the source in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Settings> {
        Self::from_toml_with(text, origin, &[])
    }

    /// Parses TOML, applies `key=value` overrides (dotted keys, TOML values; bare words are taken as strings),
    /// then validates.
    pub fn from_toml_with(text: &str, origin: &str, overrides: &[String]) -> Result<Settings> {
        // The TOML crate's messages span lines (a snippet and a caret): one line each here.
        let one_line =
            |e: &dyn std::fmt::Display| e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        let mut tree: toml::Table =
            toml::from_str(text).map_err(|e| anyhow::anyhow!("{origin}: invalid TOML: {}", one_line(&e)))?;
        for o in overrides {
            apply_override(&mut tree, o)?;
        }
        let s: Settings = Settings::deserialize(toml::Value::Table(tree))
            .map_err(|e| anyhow::anyhow!("{origin}: invalid preset: {}", one_line(&e)))?;
        s.validate()
            .with_context(|| format!("{origin}: invalid preset"))?;
        Ok(s)
    }

    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("Settings always serialises to TOML")
    }

    /// Loads a preset by name (built-in, or `presets/<name>.toml` under the current directory) or by path.
    pub fn load_preset(name_or_path: &str, overrides: &[String]) -> Result<Settings> {
        let path = Path::new(name_or_path);
        let local = Path::new("presets").join(format!("{name_or_path}.toml"));
        let file = if path.extension().is_some_and(|e| e == "toml") || path.is_file() {
            Some(path.to_path_buf())
        } else if local.is_file() {
            Some(local)
        } else {
            None
        };
        match file {
            Some(f) => {
                let text = crate::io::read_regular_text(&f)
                    .with_context(|| format!("{}: cannot read", f.display()))?;
                let mut s = Settings::from_toml_with(&text, &f.display().to_string(), overrides)?;
                s.resolve_paths(f.parent().unwrap_or(Path::new(".")));
                Ok(s)
            }
            None => {
                let (_, text) = BUILTIN_PRESETS
                    .iter()
                    .find(|(n, _)| *n == name_or_path)
                    .with_context(|| {
                        let names: Vec<_> = BUILTIN_PRESETS.iter().map(|(n, _)| *n).collect();
                        format!(
                            "no preset '{name_or_path}': not a file, and built-in presets are {}",
                            names.join(", ")
                        )
                    })?;
                Settings::from_toml_with(text, &format!("preset '{name_or_path}'"), overrides)
            }
        }
    }

    /// Makes a relative scene file path relative to the preset's folder.
    fn resolve_paths(&mut self, base: &Path) {
        for f in [
            &mut self.scene.file,
            &mut self.scene.scalp,
            &mut self.motion.path,
            &mut self.fur.env_map,
        ]
        .into_iter()
        .flatten()
        {
            if f.is_relative() {
                *f = base.join(&*f);
            }
        }
    }

    /// Builds the scene and opens its motion (`[motion]`): a sequence replaces the strands with its first
    /// frame's; the simulation collides with the generator's head ellipsoid when the scene is that head, or
    /// with the meshes that ride on the root frame (`motion.colliders`): every mesh but the generator's floor.
    pub fn open_motion(&self) -> Result<(crate::scene::Scene, crate::motion::Motion)> {
        self.open_motion_with(&mut crate::progress::Quiet)
    }

    /// [`Settings::open_motion`] telling `progress` how far the scene's build got ([`SceneSettings::build_with`]).
    pub fn open_motion_with(
        &self,
        progress: &mut dyn crate::progress::Progress,
    ) -> Result<(crate::scene::Scene, crate::motion::Motion)> {
        let mut scene = self.scene.build_with(progress)?;
        let s = &self.scene;
        let generated = s.file.is_none();
        let head =
            (generated && s.scalp.is_none() && s.generator.kind == crate::scene::generate::GenKind::Head)
                .then_some(crate::motion::Ellipsoid {
                    center: glam::Vec3::ZERO,
                    radii: crate::scene::generate::HEAD_RADII,
                });
        // The generator puts its floor last.
        let floor = usize::from(generated && s.generator.floor);
        let root_meshes = (0..scene.meshes.len().saturating_sub(floor)).collect();
        let motion = crate::motion::Motion::open(&self.motion, &mut scene, head, root_meshes)?;
        Ok((scene, motion))
    }

    /// Writes the settings as a preset file (atomically).
    pub fn save_preset(&self, path: &Path) -> Result<()> {
        crate::io::write_atomic(path, self.to_toml().as_bytes())
    }
}

/// Sets `key=value` (dotted key) in a TOML tree. The value is parsed as TOML, or taken as a string.
pub fn apply_override(tree: &mut toml::Table, assignment: &str) -> Result<()> {
    let (key, raw) = assignment
        .split_once('=')
        .with_context(|| format!("--set '{assignment}': expected key=value"))?;
    let key = key.trim();
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) => t.remove("v").unwrap_or(toml::Value::String(raw.to_string())),
        Err(_) => toml::Value::String(raw.trim().to_string()),
    };
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts
        .pop()
        .filter(|l| !l.is_empty())
        .with_context(|| format!("--set '{assignment}': empty key"))?;
    let mut table = tree;
    for p in parts {
        let entry = table
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry
            .as_table_mut()
            .with_context(|| format!("--set '{assignment}': '{p}' is not a table"))?;
    }
    table.insert(last.to_string(), value);
    Ok(())
}

#[cfg(test)]
mod tests;
