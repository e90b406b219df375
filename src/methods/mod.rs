//! Shadow methods behind one trait. Each method is one file; [`registry`] lists them and is the only place that
//! knows them all. The UI's method panel is generated from [`ShadowMethod::params`].

pub mod none;
pub mod opaque_shadow_map;
pub mod registry;

use std::collections::BTreeMap;

/// The kind and range of one method parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// A real value in `[min, max]`; `log` asks the UI for a logarithmic slider.
    Float { min: f32, max: f32, log: bool },
    /// An integer in `[min, max]`.
    Int { min: i32, max: i32 },
}

/// One tunable parameter of a method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    pub key: &'static str,
    pub label: &'static str,
    pub help: &'static str,
    pub kind: ParamKind,
    pub default: f32,
}

impl ParamSpec {
    /// Checks `v` against the parameter's range (and integrality).
    pub fn check(&self, v: f32) -> Result<(), String> {
        let ok = match self.kind {
            ParamKind::Float { min, max, .. } => v.is_finite() && (min..=max).contains(&v),
            ParamKind::Int { min, max } => v.fract() == 0.0 && (min as f32..=max as f32).contains(&v),
        };
        if ok {
            Ok(())
        } else {
            let range = match self.kind {
                ParamKind::Float { min, max, .. } => format!("a number in [{min}, {max}]"),
                ParamKind::Int { min, max } => format!("an integer in [{min}, {max}]"),
            };
            Err(format!(
                "parameter '{}' = {v} is out of range: expected {range}",
                self.key
            ))
        }
    }
}

/// Parameter values by key; missing keys take the spec's default.
pub type ParamValues = BTreeMap<String, f32>;

/// A hair self-shadowing method: how it turns the light-space view of the strands into visibility `V(z)`.
pub trait ShadowMethod: Sync {
    /// Stable identifier used in presets and on the command line (kebab-case).
    fn name(&self) -> &'static str;
    /// Human-readable name for the UI.
    fn label(&self) -> &'static str;
    /// The paper the method follows (or a one-line description of the baseline).
    fn source(&self) -> &'static str;
    /// The WGSL file under `shaders/` defining `fn hair_visibility(world: vec3<f32>) -> f32`.
    fn lookup_wgsl(&self) -> &'static str;
    /// Tunable parameters, shown as the method's panel.
    fn params(&self) -> &'static [ParamSpec] {
        &[]
    }
    /// Values for `FrameUniforms::method_params` from the parameter values.
    fn uniform_params(&self, _values: &ParamValues) -> [f32; 4] {
        [0.0; 4]
    }
    /// GPU memory in bytes of the maps this method reads at `map_resolution`², beyond the scene geometry.
    fn memory_bytes(&self, map_resolution: u32) -> u64;
    /// CPU model of the method for one texel: visibility at normalised light depth `z` given the texel's
    /// fragments as `(depth, alpha)` (the specification the GPU lookup must match).
    fn visibility(&self, values: &ParamValues, fragments: &[(f32, f32)], z: f32) -> f32;
}

/// The value of `spec` in `values`, or its default.
pub fn value(values: &ParamValues, spec: &ParamSpec) -> f32 {
    values.get(spec.key).copied().unwrap_or(spec.default)
}

/// Checks that every key in `values` belongs to `method` and lies in range.
pub fn validate(method: &dyn ShadowMethod, values: &ParamValues) -> Result<(), String> {
    for (k, v) in values {
        let spec = method.params().iter().find(|p| p.key == k).ok_or_else(|| {
            let known: Vec<_> = method.params().iter().map(|p| p.key).collect();
            format!(
                "method '{}' has no parameter '{k}' (it has: {})",
                method.name(),
                known.join(", ")
            )
        })?;
        spec.check(*v)?;
    }
    Ok(())
}
