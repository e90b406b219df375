//! Measuring methods against the exact reference on one scene: depth complexity, map error (design.md: the
//! mean over occupied texels of the mean |V_m - V_ref| over the texel's samples — every fragment depth and a
//! uniform grid between its nearest and furthest fragment, `visibility::metrics::sample_depths`), GPU time per
//! pass (median over frames) and memory. The method side is read through its GPU lookup (the evaluation
//! pass), so what is measured is what the GPU computes.

use crate::gpu::{AdapterPreference, Gpu};
use crate::methods::{self, ParamValues, registry};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use crate::visibility::{Fragment, MethodParams, metrics};
use anyhow::{Context, Result};

/// A method with parameter values, written `name` or `name:key=value,key=value`.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodConfig {
    pub name: String,
    pub params: ParamValues,
}

impl MethodConfig {
    pub fn parse(text: &str) -> Result<MethodConfig> {
        let (name, rest) = text.split_once(':').unwrap_or((text, ""));
        let method = registry::find(name.trim()).map_err(anyhow::Error::msg)?;
        let mut params = ParamValues::new();
        for kv in rest.split(',').filter(|s| !s.trim().is_empty()) {
            let (k, v) = kv
                .split_once('=')
                .with_context(|| format!("'{text}': expected key=value in '{kv}'"))?;
            let v: f32 = v
                .trim()
                .parse()
                .with_context(|| format!("'{text}': '{v}' is not a number"))?;
            params.insert(k.trim().to_string(), v);
        }
        methods::validate(method, &params).map_err(anyhow::Error::msg)?;
        Ok(MethodConfig {
            name: method.name().to_string(),
            params,
        })
    }

    /// `name` or `name:key=value,...`, parseable by [`MethodConfig::parse`].
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            return self.name.clone();
        }
        let kv: Vec<String> = self.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{}:{}", self.name, kv.join(","))
    }
}

/// The configurations the methods issue reports: OSM 16/64/256, DOM 3/7, BOM 4/8, DC 4, occupancy, plus the
/// baselines present in the registry.
pub fn usual_configs() -> Vec<MethodConfig> {
    [
        "osm:slices=16",
        "osm:slices=64",
        "osm:slices=256",
        "dom:layers=3",
        "dom:layers=7",
        "bom:layers=4",
        "bom:layers=8",
        "dc:clusters=4",
        "occupancy",
    ]
    .iter()
    .filter_map(|c| MethodConfig::parse(c).ok())
    .collect()
}

/// What the reference says about the scene's light view.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneStats {
    pub strands: usize,
    pub segments: usize,
    pub map_resolution: u32,
    pub fragments: usize,
    pub occupied_texels: usize,
    pub max_depth_complexity: usize,
    pub mean_depth_complexity: f64,
}

/// One configuration measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    pub config: MethodConfig,
    /// Mean texel error over occupied texels, and the largest texel mean error.
    pub map_error: f64,
    pub worst_texel_error: f64,
    /// Median GPU milliseconds per pass of the method's own light passes, by pass name.
    pub pass_ms: Vec<(String, f64)>,
    pub memory_bytes: u64,
    pub geometry_passes: u32,
}

impl Measurement {
    pub fn total_ms(&self) -> f64 {
        self.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>() + 0.0
    }
}

/// Samples per texel: every fragment depth and this many grid points across the texel's range.
pub const GRID_POINTS: usize = 16;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Measures `configs` on the scene of `settings` (`frames` timed frames each, after one warm-up).
pub fn measure(
    settings: &Settings,
    configs: &[MethodConfig],
    frames: u32,
    mut progress: impl FnMut(&str),
) -> Result<(SceneStats, Vec<Measurement>)> {
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let res = s.render.map_resolution;
    let mut r = Renderer::new(&gpu, &scene, res)?;
    let input = |method: &'static dyn methods::ShadowMethod, params| FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: params,
        width: 8,
        height: 8,
    };
    progress("reference");
    let empty = ParamValues::new();
    r.render_light(&input(
        registry::find("reference").map_err(anyhow::Error::msg)?,
        &empty,
    ))?;
    let lists = r.reference_lists()?;
    let occupied: Vec<usize> = (0..lists.len()).filter(|&t| !lists[t].is_empty()).collect();
    let fragments: usize = lists.iter().map(Vec::len).sum();
    let stats = SceneStats {
        strands: scene.strands.strand_count(),
        segments: scene.strands.segment_count(),
        map_resolution: res,
        fragments,
        occupied_texels: occupied.len(),
        max_depth_complexity: lists.iter().map(Vec::len).max().unwrap_or(0),
        mean_depth_complexity: if occupied.is_empty() {
            0.0
        } else {
            fragments as f64 / occupied.len() as f64
        },
    };
    // Samples and reference visibility, texel by texel.
    let mut samples = Vec::new();
    let mut reference = Vec::new();
    let mut spans = Vec::with_capacity(occupied.len());
    for &t in &occupied {
        let frags: Vec<Fragment> = lists[t].iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
        let zs = metrics::sample_depths(&frags, GRID_POINTS);
        let start = samples.len();
        let (x, y) = ((t as u32 % res) as f32, (t as u32 / res) as f32);
        samples.extend(zs.iter().map(|&z| [x, y, z]));
        reference.extend(MethodParams::Reference.visibility_curve(&frags, &zs));
        spans.push(start..samples.len());
    }
    let mut out = Vec::new();
    for c in configs {
        progress(&c.label());
        let method = registry::find(&c.name).map_err(anyhow::Error::msg)?;
        let mut per_pass: Vec<(String, Vec<f64>)> = Vec::new();
        for frame in 0..=frames {
            r.render_light(&input(method, &c.params))?;
            let times = r.wait_timings();
            if frame == 0 {
                continue;
            }
            for t in times
                .into_iter()
                .filter(|t| t.name != "light depth" && t.name != "mesh shadow map")
            {
                match per_pass.iter_mut().find(|(n, _)| *n == t.name) {
                    Some((_, v)) => v.push(t.ms),
                    None => per_pass.push((t.name, vec![t.ms])),
                }
            }
        }
        let mut v = Vec::with_capacity(samples.len());
        for chunk in samples.chunks(1 << 20) {
            v.extend(r.evaluate(method, chunk)?);
        }
        let mut sum = 0.0;
        let mut worst = 0.0f64;
        for span in &spans {
            let n = span.len() as f64;
            let e: f64 = span
                .clone()
                .map(|i| (v[i] - reference[i]).abs() as f64)
                .sum::<f64>()
                / n;
            sum += e;
            worst = worst.max(e);
        }
        let gpu_state = r.method_gpu(method);
        out.push(Measurement {
            config: c.clone(),
            map_error: if spans.is_empty() {
                0.0
            } else {
                sum / spans.len() as f64
            },
            worst_texel_error: worst,
            pass_ms: per_pass.into_iter().map(|(n, v)| (n, median(v))).collect(),
            memory_bytes: gpu_state.map_or(0, |g| g.memory_bytes()),
            geometry_passes: gpu_state.map_or(0, |g| g.geometry_passes()),
        });
    }
    Ok((stats, out))
}
