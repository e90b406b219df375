//! The opacity model against geometry over a whole map (`measure visibility`): in every occupied texel of the
//! hair map, the depth-peeled reference's `V` after each of its fragments (the product of `1 − α`) against the
//! ray-traced `V` of the fibres (`pathtrace::visibility`: stratified rays through the texel's footprint, the share
//! not yet blocked) halfway to the next fragment, and the single `α` whose `(1 − α)^k` fits the ray-traced values
//! best (least squares over every texel and fragment). Directional light only: a spot's texels are frusta.

use anyhow::Result;
use serde::Serialize;

use crate::gpu::Gpu;
use crate::path_scene;
use crate::pathtrace::bvh::Bvh;
use crate::pathtrace::fibre;
use crate::pathtrace::visibility::{light_map_texel, texel_visibility};
use crate::progress::Outcome;
use crate::render::Renderer;
use crate::scene::LightKind;
use crate::settings::Settings;

/// One occupied texel's comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TexelRow {
    pub x: u32,
    pub y: u32,
    pub fragments: usize,
    /// The ray-traced `V` past the last fragment (the share of the footprint no fibre covers) and the
    /// reference's there.
    pub ray_visibility: f32,
    pub reference_visibility: f32,
    /// Mean and largest `|V_ray − V_ref|` over the texel's fragments.
    pub mean_abs_dv: f32,
    pub max_abs_dv: f32,
}

/// The whole map's comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct MapComparison {
    pub side: u32,
    pub rays_per_texel: usize,
    pub texels: Vec<TexelRow>,
    /// Over every (texel, fragment): mean, 95th percentile and largest `|V_ray − V_ref|`.
    pub mean_abs_dv: f64,
    pub p95_abs_dv: f64,
    pub max_abs_dv: f64,
    /// The `α` whose `(1 − α)^k` best fits the ray-traced `V` after `k` fragments, and the mean `|ΔV|` it leaves.
    pub best_alpha: f64,
    pub mean_abs_dv_at_best: f64,
}

/// `(1 − α)^k` fitted to `(k, v)` samples by least squares: sums per `k`, then a search over `α` in steps of
/// 0.001 refined by steps of 1e-5.
pub fn best_alpha(samples: &[(usize, f32)]) -> f64 {
    let kmax = samples.iter().map(|s| s.0).max().unwrap_or(0);
    let mut sums = vec![(0.0f64, 0.0f64); kmax + 1];
    for &(k, v) in samples {
        sums[k].0 += 1.0;
        sums[k].1 += f64::from(v);
    }
    // Σ (v − c)² = Σ v² − 2 c Σ v + n c²; Σ v² does not depend on α.
    let cost = |a: f64| {
        sums.iter()
            .enumerate()
            .map(|(k, &(n, sv))| {
                let c = (1.0 - a).powi(k as i32);
                n * c * c - 2.0 * c * sv
            })
            .sum::<f64>()
    };
    let search = |lo: f64, step: f64, count: usize| {
        (0..=count)
            .map(|i| (lo + i as f64 * step).clamp(0.0, 1.0))
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap_or(lo)
    };
    let coarse = search(0.0, 1e-3, 1000);
    search(coarse - 1e-3, 1e-5, 200)
}

/// Compares the reference with the ray-traced fibres in every occupied texel of the hair map of `settings`
/// (`render.map_resolution × render.light_supersample` a side), `rays × rays` rays per texel, telling `progress`
/// after each texel; it stops early when that answers `false`, [`Outcome::Stopped`] with the texels done.
pub fn compare_map(
    gpu: &Gpu,
    settings: &Settings,
    rays: usize,
    progress: &mut dyn crate::progress::Progress,
) -> Result<Outcome<MapComparison>> {
    if settings.light.kind != LightKind::Directional {
        anyhow::bail!(
            "light.kind: measure visibility traces a directional light's map (light.kind = directional)"
        );
    }
    let scene = settings.scene.build()?;
    let camera = path_scene::camera(settings, &scene);
    let mut r = Renderer::new(gpu, &scene, settings.render.map_resolution)?;
    let lists = r.reference_lists(&camera, &settings.light, &settings.render)?;
    let frame = r.hair_light_frame(&settings.light);
    let side = settings.render.light_map_side();
    let bvh = Bvh::new(fibre::segments(&scene.strands, settings.render.strand_width));
    let span = frame.far - frame.near;
    let occupied: Vec<usize> = (0..lists.len()).filter(|&i| !lists[i].is_empty()).collect();
    let mut texels = Vec::with_capacity(occupied.len());
    let mut samples: Vec<(usize, f32, f32)> = Vec::new();
    for (n, &i) in occupied.iter().enumerate() {
        let list = &lists[i];
        let (x, y) = ((i % side as usize) as u32, (i / side as usize) as u32);
        let texel = light_map_texel(&frame, side, x, y);
        // Halfway from each fragment to the next (the last: to the far plane), in distance from the near plane.
        let depths: Vec<f32> = (0..list.len())
            .map(|k| {
                let next = list.get(k + 1).map_or(1.0, |f| f.depth);
                0.5 * (list[k].depth + next) * span
            })
            .collect();
        let traced = texel_visibility(&bvh, &texel, rays, &depths);
        let mut v_ref = 1.0f32;
        let (mut sum, mut max) = (0.0f32, 0.0f32);
        for (k, (f, &v_ray)) in list.iter().zip(&traced).enumerate() {
            v_ref *= 1.0 - f.alpha;
            let d = (v_ray - v_ref).abs();
            sum += d;
            max = max.max(d);
            samples.push((k + 1, v_ray, d));
        }
        texels.push(TexelRow {
            x,
            y,
            fragments: list.len(),
            ray_visibility: traced.last().copied().unwrap_or(1.0),
            reference_visibility: v_ref,
            mean_abs_dv: sum / list.len() as f32,
            max_abs_dv: max,
        });
        let label = format!("ray-tracing {} texels", occupied.len());
        if !progress.step(&label, crate::progress::share(n + 1, occupied.len())) {
            break;
        }
    }
    let mut errors: Vec<f32> = samples.iter().map(|s| s.2).collect();
    errors.sort_by(f32::total_cmp);
    let mean = |v: &[f32]| v.iter().map(|&d| f64::from(d)).sum::<f64>() / v.len().max(1) as f64;
    let fit: Vec<(usize, f32)> = samples.iter().map(|s| (s.0, s.1)).collect();
    let alpha = best_alpha(&fit);
    let at_best: Vec<f32> = fit
        .iter()
        .map(|&(k, v)| (v - (1.0 - alpha as f32).powi(k as i32)).abs())
        .collect();
    let stopped = texels.len() < occupied.len();
    let comparison = MapComparison {
        side,
        rays_per_texel: rays * rays,
        texels,
        mean_abs_dv: mean(&errors),
        p95_abs_dv: errors.get(errors.len() * 95 / 100).map_or(0.0, |&d| f64::from(d)),
        max_abs_dv: errors.last().map_or(0.0, |&d| f64::from(d)),
        best_alpha: alpha,
        mean_abs_dv_at_best: mean(&at_best),
    };
    Ok(Outcome::new(comparison, stopped))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples that are exactly `(1 − 0.3)^k` give back α = 0.3; a mixture of two opacities gives one between.
    #[test]
    fn best_alpha_recovers_a_geometric_decay() {
        let exact: Vec<(usize, f32)> = (1..8).map(|k| (k, 0.7f32.powi(k as i32))).collect();
        assert!((best_alpha(&exact) - 0.3).abs() < 1e-4, "{}", best_alpha(&exact));
        let mixed: Vec<(usize, f32)> = (1..8)
            .flat_map(|k| [(k, 0.8f32.powi(k as i32)), (k, 0.6f32.powi(k as i32))])
            .collect();
        let a = best_alpha(&mixed);
        assert!(a > 0.2 && a < 0.4, "{a}");
    }
}
