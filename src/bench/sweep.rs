//! What the bench measures, asked of the methods: which ones it sweeps, each one's sweep points
//! ([`crate::methods::ShadowMethod::sweep`]; analysed points are tuned first by the method's analysis on the
//! scene's exact fragment lists, e.g. Bounding Opacity Maps' automatic split ratio), and the scaling mode's
//! configurations. No method is named here.

use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::MethodConfig;
use crate::methods::{ParamValues, Role, ShadowMethod, registry};
use crate::progress::{Outcome, Progress};
use crate::render::Renderer;
use crate::render::passes::abuffer::RefFragment;
use crate::settings::Settings;
use anyhow::{Result, bail};

/// The scaling mode's points: strand densities evenly spaced in segment count, the last at `--max-segments`.
/// Evenly spaced points weigh the fit alike (a doubling ladder put half its points below an eighth of the range,
/// where the fixed cost dominates, and let the last point alone decide the slope).
pub const DEFAULT_SCALING_POINTS: usize = 6;
/// Fewest timed frames per point (the median of fewer is one noisy frame).
pub const MIN_SCALING_FRAMES: u32 = 3;
/// Frames rendered and discarded before timing each configuration at each point (pipelines, first-use
/// allocations and caches).
pub const DEFAULT_SCALING_WARMUP: u32 = 2;
/// The segment count the scaling mode reaches by default.
pub const DEFAULT_SCALING_SEGMENTS: usize = 1_000_000;

/// The methods the bench sweeps (every registered method with a sweep), in chart and table order: the
/// baselines, then the approximations, then the reference.
pub fn sweep_methods() -> Vec<&'static str> {
    let rank = |r: Role| match r {
        Role::Baseline => 0,
        Role::Approximation => 1,
        Role::Reference => 2,
    };
    let mut out: Vec<&'static dyn ShadowMethod> = registry::all()
        .iter()
        .copied()
        .filter(|m| !m.sweep().is_empty())
        .collect();
    out.sort_by_key(|m| rank(m.info().role));
    out.into_iter().map(|m| m.name()).collect()
}

/// Checks a `--methods` list against [`sweep_methods`]; empty means all of them.
pub fn parse_methods(names: &[String]) -> Result<Vec<&'static str>> {
    let swept = sweep_methods();
    if names.is_empty() {
        return Ok(swept);
    }
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()) {
        let Some(m) = swept.iter().find(|m| **m == n) else {
            let why = match registry::find(n) {
                Ok(_) => format!("method '{n}' has no bench sweep"),
                Err(e) => e.to_string(),
            };
            bail!("--methods: {why}; the bench sweeps {}", swept.join(", "));
        };
        if !out.contains(m) {
            out.push(*m);
        }
    }
    Ok(out)
}

/// A configuration to measure, with a note for the tables (the analysis that tuned it, e.g. "automatic split
/// ratio").
#[derive(Clone, Debug, PartialEq)]
pub struct BenchConfig {
    pub config: MethodConfig,
    pub note: String,
}

/// An analysed sweep point and the values its method's analysis chose for it.
#[derive(Clone, Debug, PartialEq)]
pub struct Tuned {
    pub method: &'static str,
    /// The sweep point as the method gives it.
    pub point: ParamValues,
    /// The point with what the analysis applies.
    pub values: ParamValues,
    pub note: &'static str,
}

/// The sweep of `methods`, in [`sweep_methods`] order: every fixed point of each method's sweep, and each
/// analysed point as `tuned` resolved it (a tuned configuration equal to a fixed one is measured once, with the
/// note). Analysed points missing from `tuned` are left out.
pub fn sweep_configs(methods: &[&str], tuned: &[Tuned]) -> Vec<BenchConfig> {
    let mut out: Vec<BenchConfig> = Vec::new();
    for name in sweep_methods().into_iter().filter(|m| methods.contains(m)) {
        let Ok(m) = registry::find(name) else { continue };
        let start = out.len();
        for p in m.sweep() {
            if !p.analysed {
                out.push(BenchConfig {
                    config: MethodConfig::new(name.to_string(), p.values),
                    note: String::new(),
                });
                continue;
            }
            let Some(t) = tuned.iter().find(|t| t.method == name && t.point == p.values) else {
                continue;
            };
            match out[start..].iter_mut().find(|c| c.config.params == t.values) {
                Some(c) => c.note = t.note.to_string(),
                None => out.push(BenchConfig {
                    config: MethodConfig::new(name.to_string(), t.values.clone()),
                    note: t.note.to_string(),
                }),
            }
        }
    }
    out
}

/// The exact fragment lists of `settings`' light view, on a renderer of its own.
fn reference_lists(settings: &Settings) -> Result<Vec<Vec<RefFragment>>> {
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    Ok(r.reference_lists(&s.camera, &s.light, &s.render)?)
}

/// Runs each method's analysis on the analysed points of its sweep, on the reference's fragment lists of
/// `settings`' scene (read once); [`Outcome::Stopped`] with the points tuned when `progress` asked to stop.
pub fn tune_analysed(
    settings: &Settings,
    methods: &[&str],
    progress: &mut dyn Progress,
) -> Result<Outcome<Vec<Tuned>>> {
    let mut points = Vec::new();
    for name in methods {
        let m = registry::find(name).map_err(anyhow::Error::msg)?;
        if let Some(a) = m.analysis() {
            points.extend(
                m.sweep()
                    .into_iter()
                    .filter(|p| p.analysed)
                    .map(|p| (m, a, p.values)),
            );
        }
    }
    if points.is_empty() {
        return Ok(Outcome::Complete(Vec::new()));
    }
    if !progress.step("reference fragment lists", 0.0) {
        return Ok(Outcome::Stopped(Vec::new()));
    }
    let lists = reference_lists(settings)?;
    let total = points.len();
    let mut out = Vec::with_capacity(total);
    for (i, (m, a, point)) in points.into_iter().enumerate() {
        let label = format!(
            "{}: {} for {}",
            m.name(),
            a.note,
            crate::methods::format_values(m, &point)
        );
        if !progress.step(&label, crate::progress::share(i, total)) {
            return Ok(Outcome::Stopped(out));
        }
        let mut values = point.clone();
        values.extend((a.run)(&lists, &point).apply);
        out.push(Tuned {
            method: m.name(),
            point,
            values,
            note: a.note,
        });
    }
    Ok(Outcome::Complete(out))
}

/// `method` with `values`, the parameter its analysis tunes chosen by that analysis on `settings`' scene (for
/// `measure --config name:key=auto`).
pub fn tune(
    settings: &Settings,
    method: &'static dyn ShadowMethod,
    values: &ParamValues,
) -> Result<ParamValues> {
    let Some(a) = method.analysis() else {
        bail!(
            "method '{}' has no analysis to choose a value marked 'auto'",
            method.name()
        );
    };
    let lists = reference_lists(settings)?;
    let mut out = values.clone();
    out.extend((a.run)(&lists, values).apply);
    Ok(out)
}

/// The scaling configurations of `methods` (each method's [`ShadowMethod::scaling_configs`]).
pub fn scaling_configs(methods: &[&str]) -> Vec<MethodConfig> {
    registry::all()
        .iter()
        .filter(|m| methods.contains(&m.name()))
        .flat_map(|m| {
            m.scaling_configs()
                .into_iter()
                .map(|params| MethodConfig::new(m.name().to_string(), params))
        })
        .collect()
}

/// Every scaling configuration, as `measure --config` writes them (for messages).
pub fn all_scaling_configs() -> Vec<String> {
    let names: Vec<&str> = registry::all().iter().map(|m| m.name()).collect();
    scaling_configs(&names).iter().map(MethodConfig::label).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sweep comes from the methods: every fixed point once, each analysed point resolved by `tuned` (or
    /// merged into an equal fixed point), in role order.
    #[test]
    fn sweep_has_every_configuration_once() {
        let methods = sweep_methods();
        let fixed: usize = methods
            .iter()
            .map(|n| {
                registry::find(n)
                    .unwrap()
                    .sweep()
                    .iter()
                    .filter(|p| !p.analysed)
                    .count()
            })
            .sum();
        let m = registry::all()
            .iter()
            .copied()
            .find(|m| m.sweep().iter().any(|p| p.analysed))
            .expect("a method with analysed sweep points");
        let a = m.analysis().unwrap();
        let sweep = m.sweep();
        let analysed: Vec<&ParamValues> = sweep.iter().filter(|p| p.analysed).map(|p| &p.values).collect();
        assert!(analysed.len() >= 2);
        // The first analysed point tunes to a fixed point of the sweep (merged), the second to a new value.
        let contains =
            |big: &ParamValues, small: &ParamValues| small.iter().all(|(k, v)| big.get(k) == Some(v));
        let equal_fixed = sweep
            .iter()
            .find(|p| !p.analysed && contains(&p.values, analysed[0]))
            .expect("a fixed point extending the first analysed one")
            .values
            .clone();
        let mut new_values = analysed[1].clone();
        new_values.insert(a.tunes.to_string(), 0.3);
        let tuned = [
            Tuned {
                method: m.name(),
                point: analysed[0].clone(),
                values: equal_fixed.clone(),
                note: a.note,
            },
            Tuned {
                method: m.name(),
                point: analysed[1].clone(),
                values: new_values.clone(),
                note: a.note,
            },
        ];
        let c = sweep_configs(&methods, &tuned);
        assert_eq!(c.len(), fixed + 1);
        let labels: Vec<String> = c.iter().map(|c| c.config.label()).collect();
        for (i, l) in labels.iter().enumerate() {
            assert!(!labels[..i].contains(l), "{l} twice");
            assert!(MethodConfig::parse(l).is_ok(), "{l} does not parse");
        }
        let noted: Vec<&ParamValues> = c
            .iter()
            .filter(|c| !c.note.is_empty())
            .map(|c| &c.config.params)
            .collect();
        assert_eq!(noted, [&equal_fixed, &new_values]);
        let role = |n: &&str| registry::find(n).unwrap().info().role;
        assert_eq!(methods.first().map(role), Some(Role::Baseline));
        assert_eq!(methods.last().map(role), Some(Role::Reference));
        assert!(
            registry::all()
                .iter()
                .all(|m| methods.contains(&m.name()) != m.sweep().is_empty())
        );
    }

    #[test]
    fn methods_list_is_checked() {
        let methods = sweep_methods();
        let two = [methods[1].to_string(), methods[2].to_string()];
        assert_eq!(parse_methods(&two).unwrap(), [methods[1], methods[2]]);
        let e = parse_methods(&["nonesuch".into()]).unwrap_err().to_string();
        assert!(e.contains("unknown shadow method 'nonesuch'"), "{e}");
        let unswept = registry::all()
            .iter()
            .find(|m| m.sweep().is_empty())
            .unwrap()
            .name();
        let e = parse_methods(&[unswept.into()]).unwrap_err().to_string();
        assert!(e.contains(&format!("'{unswept}' has no bench sweep")), "{e}");
    }
}
