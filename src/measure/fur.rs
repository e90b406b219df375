//! Fur figures (Andersen et al. 2016): the paper's Table 1 for the last frame a renderer drew with fur, and
//! `measure fur`: each blending against the reference (virtual fragments of one step, no early exit) —
//! image error over fur pixels (of `(H, 1 − T)`, and FLIP of the fur over black), Table 1 per blending,
//! fragments.

use std::time::Instant;

use anyhow::{Result, anyhow};

use super::median;
use crate::fur::settings::{Blending, FurMode, FurScene, FurSettings};
use crate::fur::table::{FurMemory, Table1};
use crate::gpu::timing::{PassTime, Phase};
use crate::gpu::{AdapterPreference, Gpu};
use crate::methods;
use crate::render::FrameInput;
use crate::render::Renderer;
use crate::render::eye::lists::NODE_BYTES;
use crate::settings::Settings;

/// Table 1 of `renderer`'s last frame (drawn with `fur`, its passes timed as `times`); `scene_ms` is the
/// scene's generation (row 3).
pub fn table1(renderer: &Renderer, fur: &FurScene, scene_ms: f64, times: &[PassTime]) -> Result<Table1> {
    let state = renderer
        .fur_state()
        .ok_or_else(|| anyhow!("fur.mode: the renderer holds no fur"))?;
    let lists = state
        .lists
        .ok_or_else(|| anyhow!("fur.mode: no fur frame has been drawn yet"))?;
    let stats = lists.stats();
    let (shell_mesh, volume) = state.shell.memory();
    let g = renderer.scene_gpu();
    let (width, height) = renderer.eye_size();
    let pixels = u64::from(width) * u64::from(height);
    let memory = FurMemory {
        mesh: g.mesh_vertices.size() + g.mesh_indices.size() + shell_mesh,
        volume,
        strands: g.hair_vertices.size() + g.hair_indices.size(),
        shell_fragments: stats.shell * NODE_BYTES,
        // The meshes' 32-bit depth image stands in for stored base-mesh fragments.
        base_fragments: pixels * 4,
        // Explicit nodes, and the per-pixel heads and counts the lists need whatever they hold.
        explicit_fragments: stats.explicit * NODE_BYTES + (2 * pixels + 1) * 4,
    };
    Ok(Table1::new(
        [fur.process_ms, state.volume_ms, scene_ms],
        times,
        memory,
    ))
}

/// One blending of `measure fur`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FurConfig {
    pub blending: Blending,
    /// Virtual fragments' `k` (the others ignore it).
    pub group_steps: u32,
}

impl FurConfig {
    pub fn label(&self) -> String {
        match self.blending {
            Blending::Virtual => format!("virtual k={}", self.group_steps),
            b => b.word().to_string(),
        }
    }

    /// `naive`, `simplified` or `virtual:k=K`.
    pub fn parse(text: &str) -> Result<FurConfig> {
        let (name, pairs) = crate::selection::split_config(text).map_err(|e| anyhow!("--fur-config {e}"))?;
        let blending = Blending::ALL
            .into_iter()
            .find(|b| b.word() == name)
            .ok_or_else(|| anyhow!("--fur-config '{text}': the blendings are naive, simplified, virtual"))?;
        let mut group_steps = FurSettings::default().group_steps;
        for pair in pairs {
            match pair {
                ("k", v) if blending == Blending::Virtual => {
                    group_steps = v
                        .parse()
                        .ok()
                        .filter(|k| *k >= 1)
                        .ok_or_else(|| anyhow!("--fur-config '{text}': k must be a whole number ≥ 1"))?;
                }
                _ => anyhow::bail!("--fur-config '{text}': only virtual takes a parameter, k=K"),
            }
        }
        Ok(FurConfig {
            blending,
            group_steps,
        })
    }
}

/// What `measure fur` compares with its reference by default: the three blendings, virtual at four `k`.
pub fn usual_configs() -> Vec<FurConfig> {
    let mut out = vec![
        FurConfig {
            blending: Blending::Naive,
            group_steps: 1,
        },
        FurConfig {
            blending: Blending::Simplified,
            group_steps: 1,
        },
    ];
    out.extend([32, 8, 4, 2].map(|k| FurConfig {
        blending: Blending::Virtual,
        group_steps: k,
    }));
    out
}

/// How tables name the reference's row.
pub const REFERENCE_LABEL: &str = "virtual k=1 eps_t=0";

/// The reference every fur blending is measured against: virtual fragments of one step each, no early exit
/// (B.7).
pub fn reference_settings(s: &FurSettings) -> FurSettings {
    FurSettings {
        blending: Blending::Virtual,
        group_steps: 1,
        epsilon_t: 0.0,
        ..s.clone()
    }
}

/// One row of `measure fur`.
#[derive(Clone, Debug)]
pub struct FurMeasurement {
    pub config: FurConfig,
    /// RMSE of (H, 1 − T) against the reference over fur pixels (either image covered), and its maximum.
    pub rmse: f64,
    pub max_error: f32,
    /// FLIP of the fur over black ([`crate::io::over_black`]) against the reference's: over all pixels, and over the fur
    /// pixels (either image covered) as the hair pixels.
    pub flip: crate::transparency::FlipMetrics,
    /// Table 1 with each GPU row the median over the timed frames.
    pub table: Table1,
    pub explicit_fragments: u64,
    pub shell_fragments: u64,
    pub deepest: u32,
}

/// The scene of a `measure fur` run.
#[derive(Clone, Debug)]
pub struct FurSceneStats {
    pub triangles: usize,
    pub sub_elements: u64,
    pub strands: usize,
    pub width: u32,
    pub height: u32,
    pub fur_pixels: usize,
    pub reference: Table1,
    /// The adapter, in words.
    pub device: String,
}

/// Per-pixel (H, 1 − T) error of `image` against `reference` over the pixels either covers.
fn image_error(image: &[[f32; 4]], reference: &[[f32; 4]]) -> (f64, f32, usize) {
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f32, 0usize);
    for (a, b) in image.iter().zip(reference) {
        if a[3] == 0.0 && b[3] == 0.0 {
            continue;
        }
        n += 1;
        for c in 0..4 {
            let d = a[c] - b[c];
            sum += f64::from(d * d) / 4.0;
            max = max.max(d.abs());
        }
    }
    let rmse = if n == 0 { 0.0 } else { (sum / n as f64).sqrt() };
    (rmse, max, n)
}

/// Measures `configs` on `settings`' fur at its own image size, `frames` timed frames each after a warm-up.
pub fn measure(
    settings: &Settings,
    configs: &[FurConfig],
    frames: u32,
) -> Result<(FurSceneStats, Vec<FurMeasurement>)> {
    measure_each(settings, configs, frames, &mut crate::progress::Quiet, |_, _| {
        Ok(())
    })
}

/// [`measure`] telling `progress` each configuration as it starts and calling `after` with the rows so far after
/// each (to write them; its error ends the run with it); a stop `progress` asks for ends the run with those rows.
pub fn measure_each(
    settings: &Settings,
    configs: &[FurConfig],
    frames: u32,
    progress: &mut dyn crate::progress::Progress,
    mut after: impl FnMut(&FurSceneStats, &[FurMeasurement]) -> Result<()>,
) -> Result<(FurSceneStats, Vec<FurMeasurement>)> {
    let mut s = settings.clone();
    if s.fur.mode == FurMode::Off {
        anyhow::bail!("fur.mode is off in this preset: measure --fur needs fur (e.g. --preset fur-cylinder)");
    }
    let start = Instant::now();
    let scene = s.scene.build()?;
    let scene_ms = start.elapsed().as_secs_f64() * 1e3;
    let fur = FurScene::build(&scene, &s.fur)
        .map_err(anyhow::Error::msg)?
        .ok_or_else(|| anyhow!("fur.mode is off"))?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution)?;
    let reference = reference_settings(&s.fur);
    r.set_fur(Some((&fur, &reference)))?;
    let method = methods::registry::find(&s.method.name).map_err(anyhow::Error::msg)?;
    // `measure fur` measures the fur's typed lists, whichever technique the preset names.
    let technique = crate::render::transparency::registry::fur();
    let technique_params = if s.transparency.name == technique.name() {
        s.transparency.params.clone()
    } else {
        Default::default()
    };
    let input = FrameInput {
        camera: &s.camera,
        light: &s.light,
        render: &s.render,
        method,
        method_params: &s.method.params,
        technique,
        technique_params: &technique_params,
        width: s.render.width,
        height: s.render.height,
    };
    // Each configuration: a warm-up, `frames` timed frames (per-pass medians), then a capture.
    let run = |r: &mut Renderer| -> Result<(Table1, Vec<[f32; 4]>)> {
        let mut per_pass: Vec<(Phase, String, Vec<f64>)> = Vec::new();
        for f in 0..=frames {
            r.render(&input)?;
            let times = r.wait_timings();
            if f == 0 {
                continue;
            }
            for t in times {
                match per_pass
                    .iter_mut()
                    .find(|(p, n, _)| (*p, n) == (t.phase, &t.name))
                {
                    Some((_, _, v)) => v.push(t.ms),
                    None => per_pass.push((t.phase, t.name, vec![t.ms])),
                }
            }
        }
        let medians: Vec<PassTime> = per_pass
            .into_iter()
            .map(|(phase, name, v)| PassTime {
                phase,
                name,
                ms: median(v),
            })
            .collect();
        let table = table1(r, &fur, scene_ms, &medians)?;
        Ok((table, r.render_capture(&input)?))
    };
    let (reference_table, reference_image) = run(&mut r)?;
    let reference_over_black = crate::io::over_black(&reference_image, s.render.width, s.render.height);
    let (_, _, fur_pixels) = image_error(&reference_image, &reference_image);
    let scene_stats = FurSceneStats {
        triangles: fur.shell.mesh.faces.len(),
        sub_elements: fur.shell.sub_elements,
        strands: scene.strands.strand_count(),
        width: s.render.width,
        height: s.render.height,
        fur_pixels,
        reference: reference_table,
        device: crate::gpu::describe(&gpu.info),
    };
    let mut out = Vec::with_capacity(configs.len());
    for (i, c) in configs.iter().enumerate() {
        if !progress.step(&c.label(), crate::progress::share(i, configs.len())) {
            break;
        }
        let fs = FurSettings {
            blending: c.blending,
            group_steps: c.group_steps,
            ..s.fur.clone()
        };
        r.set_fur_rendering(&fs);
        let (table, image) = run(&mut r)?;
        let stats = r
            .fur_state()
            .and_then(|f| f.lists)
            .map(|l| l.stats())
            .unwrap_or_default();
        let (rmse, max_error, _) = image_error(&image, &reference_image);
        let width = s.render.width as usize;
        let covered = |x: u32, y: u32| {
            let i = y as usize * width + x as usize;
            let alpha = |v: &[[f32; 4]]| v.get(i).is_some_and(|p| p[3] != 0.0);
            alpha(&image) || alpha(&reference_image)
        };
        let flip = crate::transparency::FlipMap::new(
            &crate::io::over_black(&image, s.render.width, s.render.height),
            &reference_over_black,
        )
        .metrics(covered);
        out.push(FurMeasurement {
            config: *c,
            rmse,
            max_error,
            flip,
            table,
            explicit_fragments: stats.explicit,
            shell_fragments: stats.shell,
            deepest: stats.deepest,
        });
        after(&scene_stats, &out)?;
    }
    Ok((scene_stats, out))
}
