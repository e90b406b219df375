//! Shadow methods behind one trait. Each method is one file here (its [`MethodInfo`], GPU state and sweep),
//! its CPU model in `visibility/`, its WGSL in `shaders/`; [`registry`] lists them and is the only place that
//! knows them all. The UI's method panel is generated from [`MethodInfo::params`].

pub mod adsm;
pub mod avsm;
pub mod bom;
pub mod dc;
pub mod dom;
pub mod dsm;
pub mod fom;
pub mod msm;
pub mod none;
pub mod occupancy;
pub mod opacity_layers;
pub mod opaque_shadow_map;
pub mod osm;
pub mod reference;
pub mod registry;

pub use crate::render::method::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, NoMaps, ParamError, ParamKind, ParamSpec, ParamValues,
    Role, UniformMirror, UnknownName, choice, value,
};
use crate::visibility::TexelModel;

/// One configuration of a method's bench sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    pub values: ParamValues,
    /// Run the method's [`Analysis`] on the scene with these values first and measure what it applies (e.g.
    /// Bounding Opacity Maps' automatic split ratio).
    pub analysed: bool,
}

impl SweepPoint {
    /// A fixed configuration from `(key, value)` pairs.
    pub fn fixed(pairs: &[(&str, f32)]) -> SweepPoint {
        SweepPoint {
            values: pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            analysed: false,
        }
    }
}

/// A hair self-shadowing method: how it turns the light-space view of the strands into visibility `V(z)`.
/// Its GPU face is the renderer's [`LightMethod`]; this trait adds the CPU model (the specification), the bench
/// sweep and the on-demand analysis. A method is its own files (both implementations, its CPU model, its WGSL)
/// plus one line in [`registry`].
pub trait ShadowMethod: LightMethod {
    /// The CPU model with these parameter values: the specification the GPU lookup must match.
    fn model(&self, values: &ParamValues, hair_alpha: f32) -> Box<dyn TexelModel>;
    /// The configurations the bench sweeps (default: once, at the defaults; empty: not benched).
    fn sweep(&self) -> Vec<SweepPoint> {
        vec![SweepPoint::fixed(&[])]
    }
    /// The configurations `measure` reports when none is given.
    fn usual_configs(&self) -> Vec<ParamValues> {
        Vec::new()
    }
    /// The configurations the bench's scaling mode measures over strand density (empty: none).
    fn scaling_configs(&self) -> Vec<ParamValues> {
        Vec::new()
    }
    /// An on-demand analysis of the exact fragment lists that tunes the method's parameters (e.g. Bounding
    /// Opacity Maps' automatic split ratio); run from the method panel and by analysed sweep points, never
    /// per frame.
    fn analysis(&self) -> Option<Analysis> {
        None
    }
}

/// An on-demand computation over the reference's per-texel fragment lists.
#[derive(Clone, Copy)]
pub struct Analysis {
    /// Button label.
    pub label: &'static str,
    /// How the bench and `measure` tables mark a configuration it tuned (e.g. "automatic split ratio").
    pub note: &'static str,
    /// The parameter a `measure --config` value of `auto` asks it to choose (e.g. `split_ratio=auto`).
    pub tunes: &'static str,
    pub help: &'static str,
    pub run: fn(&[Vec<crate::render::passes::abuffer::RefFragment>], &ParamValues) -> AnalysisResult,
}

/// What an analysis found: parameter values to apply, a table of scores (first row: header) and a summary.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisResult {
    pub apply: ParamValues,
    pub table: Vec<Vec<String>>,
    pub summary: String,
}

/// The parameter `key` of `method`, or an error listing the parameters it has.
pub fn spec(method: &dyn ShadowMethod, key: &str) -> Result<&'static ParamSpec, ParamError> {
    method.params().iter().find(|p| p.key == key).ok_or_else(|| {
        let known: Vec<_> = method.params().iter().map(|p| p.key).collect();
        ParamError::UnknownKey {
            family: "method",
            name: method.name(),
            key: key.to_string(),
            known: if known.is_empty() {
                "no parameters".to_string()
            } else {
                known.join(", ")
            },
        }
    })
}

/// Parses `key` = `text` for `method` (a number, or a choice's word).
pub fn parse_value(method: &dyn ShadowMethod, key: &str, text: &str) -> Result<f32, ParamError> {
    spec(method, key)?.parse(text)
}

/// `key=value` pairs as presets and the command line write them (choices as words), comma-separated.
pub fn format_values(method: &dyn ShadowMethod, values: &ParamValues) -> String {
    let kv: Vec<String> = values
        .iter()
        .map(|(k, v)| match spec(method, k) {
            Ok(s) => format!("{k}={}", s.format(*v)),
            Err(_) => format!("{k}={v}"),
        })
        .collect();
    kv.join(",")
}

/// Checks that every key in `values` belongs to `method` and lies in range.
pub fn validate(method: &dyn ShadowMethod, values: &ParamValues) -> Result<(), ParamError> {
    for (k, v) in values {
        spec(method, k)?.check(*v)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const CHOICE: ParamSpec = ParamSpec {
        key: "spacing",
        label: "spacing",
        help: "",
        kind: ParamKind::Choice {
            options: &["linear", "uniform"],
        },
        default: 0.0,
    };

    #[test]
    fn choices_parse_words_and_indices() {
        assert_eq!(CHOICE.parse("uniform"), Ok(1.0));
        assert_eq!(CHOICE.parse(" linear "), Ok(0.0));
        assert_eq!(CHOICE.parse("1"), Ok(1.0), "old numeric presets still load");
        let e = CHOICE.parse("2").unwrap_err().to_string();
        assert!(e.contains("expected one of linear, uniform"), "{e}");
        let e = CHOICE.parse("wide").unwrap_err().to_string();
        assert_eq!(e, "parameter 'spacing': 'wide' is not one of linear, uniform");
        assert_eq!(CHOICE.format(1.0), "uniform");
        assert_eq!(CHOICE.option(0.0), Some("linear"));
        assert_eq!(CHOICE.option(2.0), None);
        let chosen = ParamValues::from([("spacing".to_string(), 1.0)]);
        assert_eq!(
            (choice(&chosen, &CHOICE), choice(&ParamValues::new(), &CHOICE)),
            ("uniform", "linear")
        );
    }
}
