//! What the bench measures: the methods it sweeps, each method's parameter values, the configurations of a
//! sweep (with Bounding Opacity Maps' automatic split ratios), and the configurations of the scaling mode.

use super::Progress;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::MethodConfig;
use crate::methods::{ParamValues, registry};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use crate::visibility::SplitCriterion;
use anyhow::{Result, bail};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Methods the bench sweeps, in chart and table order.
pub const SWEEP_METHODS: &[&str] = &[
    "opaque-shadow-map",
    "osm",
    "dom",
    "bom",
    "dc",
    "occupancy",
    "reference",
];
pub const OSM_SLICES: &[u32] = &[4, 8, 16, 32, 64, 128, 256];
pub const DOM_LAYERS: &[u32] = &[1, 2, 3, 4, 5, 7, 10, 15];
/// Deep Opacity Maps' `spacing` values: 0 linearly increasing layer sizes, 1 uniform.
pub const DOM_SPACINGS: &[u32] = &[0, 1];
pub const BOM_LAYERS: &[u32] = &[1, 2, 3, 4, 6, 8, 12, 15];
/// Fixed split ratios; the automatic ratio is swept beside them.
pub const BOM_RATIOS: &[f32] = &[0.0, 0.5, 1.0];
pub const DC_CLUSTERS: &[u32] = &[2, 4, 8];
/// Strand density factors of the scaling mode.
pub const SCALING_DENSITIES: &[f32] = &[0.25, 0.5, 1.0, 2.0, 4.0];
/// Configurations of the scaling mode.
pub const SCALING_CONFIGS: &[&str] = &["osm:slices=16", "osm:slices=64", "dom:layers=3", "occupancy"];
/// The note of a configuration whose split ratio is the automatic one.
pub const AUTO_NOTE: &str = "automatic split ratio";

/// Checks a `--methods` list against [`SWEEP_METHODS`]; empty means all of them.
pub fn parse_methods(names: &[String]) -> Result<Vec<&'static str>> {
    if names.is_empty() {
        return Ok(SWEEP_METHODS.to_vec());
    }
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()) {
        let Some(m) = SWEEP_METHODS.iter().find(|m| **m == n) else {
            let why = match registry::find(n) {
                Ok(_) => format!("method '{n}' has no bench sweep"),
                Err(e) => e,
            };
            bail!("--methods: {why}; the bench sweeps {}", SWEEP_METHODS.join(", "));
        };
        if !out.contains(m) {
            out.push(*m);
        }
    }
    Ok(out)
}

/// A configuration to measure, with a note for the tables (e.g. [`AUTO_NOTE`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchConfig {
    pub config: MethodConfig,
    pub note: String,
}

fn config(name: &str, params: &[(&str, f32)]) -> BenchConfig {
    BenchConfig {
        config: MethodConfig {
            name: name.to_string(),
            params: params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        },
        note: String::new(),
    }
}

/// The sweep of `methods`, in [`SWEEP_METHODS`] order. `auto_ratios` holds Bounding Opacity Maps' automatic
/// split ratio per layer count; a ratio equal to a fixed one is measured once, with the note.
pub fn sweep_configs(methods: &[&str], auto_ratios: &[(u32, f32)]) -> Vec<BenchConfig> {
    let mut out = Vec::new();
    for &m in SWEEP_METHODS.iter().filter(|m| methods.contains(m)) {
        match m {
            "osm" => out.extend(OSM_SLICES.iter().map(|&n| config(m, &[("slices", n as f32)]))),
            "dom" => {
                for &k in DOM_LAYERS {
                    for &s in DOM_SPACINGS {
                        out.push(config(m, &[("layers", k as f32), ("spacing", s as f32)]));
                    }
                }
            }
            "bom" => {
                for &k in BOM_LAYERS {
                    let start = out.len();
                    for &r in BOM_RATIOS {
                        out.push(config(m, &[("layers", k as f32), ("split_ratio", r)]));
                    }
                    if let Some(&(_, auto)) = auto_ratios.iter().find(|(l, _)| *l == k) {
                        let same = out[start..]
                            .iter_mut()
                            .find(|c| c.config.params.get("split_ratio") == Some(&auto));
                        match same {
                            Some(c) => c.note = AUTO_NOTE.to_string(),
                            None => {
                                let mut c = config(m, &[("layers", k as f32), ("split_ratio", auto)]);
                                c.note = AUTO_NOTE.to_string();
                                out.push(c);
                            }
                        }
                    }
                }
            }
            "dc" => out.extend(DC_CLUSTERS.iter().map(|&n| config(m, &[("clusters", n as f32)]))),
            "occupancy" => out.extend([0.0, 1.0].map(|v| config(m, &[("variant", v)]))),
            _ => out.push(config(m, &[])),
        }
    }
    out
}

/// Bounding Opacity Maps' automatic split ratio (`methods::bom::automatic_split_ratio`, least correlated
/// successive layers) for each layer count, on the reference's fragment lists of `settings`' scene. `None` when
/// cancelled.
pub fn automatic_split_ratios(
    settings: &Settings,
    layers: &[u32],
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(Progress),
) -> Result<Option<Vec<(u32, f32)>>> {
    let start = Instant::now();
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    progress(Progress {
        done: 0,
        total: layers.len(),
        label: "reference fragment lists".to_string(),
        elapsed: start.elapsed(),
    });
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    let empty = ParamValues::new();
    r.render_light(&FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method: registry::find("reference").map_err(anyhow::Error::msg)?,
        method_params: &empty,
        width: 8,
        height: 8,
    })?;
    let lists = r.reference_lists()?;
    let mut out = Vec::with_capacity(layers.len());
    for (i, &k) in layers.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Ok(None);
        }
        progress(Progress {
            done: i,
            total: layers.len(),
            label: format!("automatic split ratio, {k} layers"),
            elapsed: start.elapsed(),
        });
        let best =
            crate::methods::bom::automatic_split_ratio(&lists, k).best(SplitCriterion::CrossCorrelation);
        // The search steps by 0.1: keep the ratio on that grid so it prints and compares exactly.
        out.push((k, (best * 10.0).round() / 10.0));
    }
    Ok(Some(out))
}

/// The scaling configurations of `methods` (those [`SCALING_CONFIGS`] names).
pub fn scaling_configs(methods: &[&str]) -> Vec<MethodConfig> {
    SCALING_CONFIGS
        .iter()
        .filter_map(|c| MethodConfig::parse(c).ok())
        .filter(|c| methods.contains(&c.name.as_str()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweep_has_every_configuration_once() {
        let c = sweep_configs(SWEEP_METHODS, &[(4, 0.5), (8, 0.3)]);
        // 7 OSM + 16 DOM + 8×3 BOM + 1 extra automatic ratio + 3 DC + 2 occupancy + reference + opaque.
        assert_eq!(c.len(), 7 + 16 + 24 + 1 + 3 + 2 + 1 + 1);
        let labels: Vec<String> = c.iter().map(|c| c.config.label()).collect();
        for (i, l) in labels.iter().enumerate() {
            assert!(!labels[..i].contains(l), "{l} twice");
            assert!(MethodConfig::parse(l).is_ok(), "{l} does not parse");
        }
        let auto: Vec<&str> = c
            .iter()
            .filter(|c| c.note == AUTO_NOTE)
            .map(|c| c.config.label())
            .map(|l| if l.contains("layers=4,") { "4" } else { "8" })
            .collect();
        assert_eq!(auto, ["4", "8"]);
        assert!(labels.contains(&"bom:layers=8,split_ratio=0.3".to_string()));
    }

    #[test]
    fn methods_list_is_checked() {
        assert_eq!(
            parse_methods(&["osm".into(), "occupancy".into()]).unwrap(),
            ["osm", "occupancy"]
        );
        let e = parse_methods(&["osm".into(), "osn".into()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown shadow method 'osn'"), "{e}");
        let e = parse_methods(&["none".into()]).unwrap_err().to_string();
        assert!(e.contains("'none' has no bench sweep"), "{e}");
    }
}
