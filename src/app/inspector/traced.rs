//! The light the methods approximate, in the inspector: the ray-traced `V(z)` of a texel's fibres beside the
//! depth-peeled reference. For each inspected scene texel (and each scene pin) [`TRACED_RAYS`]² stratified rays
//! through the texel's footprint along a directional light (`pathtrace::visibility::light_map_texel`, the
//! footprint `measure visibility` traces) cross the scene's fibres, round cylinders `render.strand_width` wide in a
//! BVH built once per scene generation and width; `V(z)` is the share of rays no fibre has blocked before depth
//! `z`, on the plot's own axis (normalised light depth times `far − near`, the distance from the near plane). Where
//! it leaves the product of `(1 − α)`, the opacity model departs from geometry: strands correlated in clumps, `α`
//! against the width and the texel size.
//!
//! Also here: the `α` that fits the ray-traced curves of the whole map best ([`AlphaFit`],
//! `measure::fibre_visibility::compare_map` as a job), offered for the scene's `hair_alpha`.

use super::lists::ListsKey;
use crate::app::jobs::{Job, JobGate, JobStatus, PATIENCE, Poll};
use crate::gpu::Gpu;
use crate::measure::fibre_visibility::{MapComparison, compare_map};
use crate::pathtrace::bvh::Bvh;
use crate::pathtrace::fibre;
use crate::pathtrace::visibility::{Texel, crossings, light_map_texel};
use crate::progress::{Progress, share};
use crate::render::AlphaMode;
use crate::scene::light_frame::LightFrame;
use crate::scene::{LightKind, Strands};
use crate::settings::{SceneSettings, Settings};
use egui::Color32;
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

/// Rays a side through an inspected texel's footprint: `TRACED_RAYS²` stratified rays, each one's first fibre
/// crossing kept (a `V` step of 1/256 per ray).
pub const TRACED_RAYS: usize = 16;

/// Rays a side per texel of the whole-map `α` fit (`measure visibility`'s default).
pub const FIT_RAYS: usize = 8;

/// The ray-traced curve's colour (its line is dashed; a pin's is dotted in the pin's colour).
pub const TRACED_COLOR: Color32 = Color32::from_rgb(235, 175, 0);

/// The ray-traced curve's name on the plot's legend.
pub fn traced_label() -> String {
    format!("ray-traced (fibres, {TRACED_RAYS}×{TRACED_RAYS} rays)")
}

/// Why there is no ray-traced curve under a spot light.
pub const SPOT_NOTE: &str = "ray-traced V(z): directional light only (a spot light's texels are frusta, not the parallel footprints traced)";

/// The scene's fibres as the window has them now.
#[derive(Clone, Copy)]
pub struct FibreScene<'a> {
    pub strands: &'a Strands,
    /// The renderer's scene generation (`Renderer::scene_generation`): it changes whenever the geometry does.
    pub generation: u64,
    /// The hair maps' light frame (`Renderer::hair_light_frame`), the one the fragment lists were drawn in.
    pub frame: LightFrame,
}

/// What the rays of a texel depend on besides the texel.
#[derive(Clone, Debug, PartialEq)]
struct Geometry {
    generation: u64,
    strand_width: u32,
    frame: LightFrame,
    side: u32,
}

impl Geometry {
    fn of(fibres: &FibreScene<'_>, settings: &Settings) -> Geometry {
        Geometry {
            generation: fibres.generation,
            strand_width: settings.render.strand_width.to_bits(),
            frame: fibres.frame,
            side: settings.render.light_map_side(),
        }
    }

    /// What the BVH depends on.
    fn bvh_key(&self) -> (u64, u32) {
        (self.generation, self.strand_width)
    }
}

/// One texel's rays: where each first crosses a fibre.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedRays {
    pub texel: [u32; 2],
    /// The footprint traced ([`light_map_texel`] of the hair maps' frame), with the seed of its rays' jitter.
    pub footprint: Texel,
    /// Rays a side.
    pub rays: usize,
    /// `far − near` of the light frame: normalised depth `z` lies `z · span` from the near plane.
    pub span: f32,
    /// Each ray's first fibre crossing, as distance from the near plane; ∞ where it crosses none.
    pub first: Vec<f32>,
}

impl TracedRays {
    /// `V` at each normalised depth of `depths`: the share of rays whose first crossing lies at or beyond it
    /// (`pathtrace::visibility::texel_visibility`'s count at the depths `z · span`).
    pub fn curve(&self, depths: &[f32]) -> Vec<f32> {
        let n = self.first.len().max(1) as f32;
        depths
            .iter()
            .map(|&z| {
                let d = z * self.span;
                self.first.iter().filter(|&&t| t >= d).count() as f32 / n
            })
            .collect()
    }
}

/// The rays of `texels` (inside the map) through `bvh`, as `measure fibres` traces them, telling `progress` before
/// each texel; `None` once it answers `false`.
fn trace(
    bvh: &Bvh,
    geometry: &Geometry,
    texels: &[[u32; 2]],
    progress: &mut dyn Progress,
) -> Option<Vec<TracedRays>> {
    let frame = &geometry.frame;
    let span = frame.far - frame.near;
    // Far past the far plane: every plotted depth lies well inside.
    let max_depth = 2.0 * span;
    let mut out = Vec::with_capacity(texels.len());
    for (i, &[x, y]) in texels.iter().enumerate() {
        if !progress.step(&format!("tracing texel ({x}, {y})"), share(i, texels.len())) {
            return None;
        }
        let footprint = light_map_texel(frame, geometry.side, x, y);
        let first = crossings(bvh, &footprint, TRACED_RAYS, max_depth)
            .iter()
            .map(|h| h.first().map_or(f32::INFINITY, |h| h.t))
            .collect();
        out.push(TracedRays {
            texel: [x, y],
            footprint,
            rays: TRACED_RAYS,
            span,
            first,
        });
    }
    Some(out)
}

/// A traced batch: its geometry, the BVH it used, the texels' rays.
struct Batch {
    geometry: Geometry,
    bvh: Arc<Bvh>,
    rays: Vec<TracedRays>,
}

/// The inspected texels' rays, their BVH and the job tracing more.
#[derive(Default)]
pub(super) struct Traced {
    /// The geometry of the scene now (`None` under a spot light or without fibres).
    current: Option<Geometry>,
    /// The geometry of [`Traced::texels`].
    geometry: Option<Geometry>,
    texels: HashMap<[u32; 2], Arc<TracedRays>>,
    /// The BVH over the fibres and its (scene generation, strand width bits).
    bvh: Option<((u64, u32), Arc<Bvh>)>,
    /// The job tracing more, and what it traces.
    job: Option<(Attempt, Job<Batch>)>,
    /// What a job stopped without a result for (not retried until it changes).
    failed: Option<Attempt>,
}

/// A job's geometry and texels.
type Attempt = (Geometry, Vec<[u32; 2]>);

impl Traced {
    /// Takes a finished batch (waiting up to `patience`).
    pub fn poll(&mut self, patience: Duration) {
        let Some((attempt, job)) = &self.job else { return };
        match job.wait(patience) {
            Poll::Running => {}
            Poll::Done(batch) => {
                self.job = None;
                if self.geometry.as_ref() != Some(&batch.geometry) {
                    self.texels.clear();
                    self.geometry = Some(batch.geometry.clone());
                }
                self.bvh = Some((batch.geometry.bvh_key(), batch.bvh));
                for r in batch.rays {
                    self.texels.insert(r.texel, Arc::new(r));
                }
            }
            Poll::Gone => {
                if !job.cancelled() {
                    self.failed = Some(attempt.clone());
                }
                self.job = None;
            }
        }
    }

    /// Starts tracing the texels of `wanted` missing for the current geometry (one job at a time: a job for older
    /// geometry finishes first, so that a moving scene does not pile up workers), when `allow` (the input has
    /// settled). Under a spot light, or without fibres, nothing.
    pub fn update(
        &mut self,
        fibres: Option<FibreScene<'_>>,
        settings: &Settings,
        wanted: &[[u32; 2]],
        allow: bool,
        ctx: &egui::Context,
        gate: Option<JobGate>,
    ) {
        self.poll(Duration::ZERO);
        let fibres = fibres.filter(|_| settings.light.kind == LightKind::Directional);
        self.current = fibres.as_ref().map(|f| Geometry::of(f, settings));
        let Some(fibres) = fibres else { return };
        let geometry = Geometry::of(&fibres, settings);
        let have = self.geometry.as_ref() == Some(&geometry);
        let mut missing: Vec<[u32; 2]> = wanted
            .iter()
            .copied()
            .filter(|&[x, y]| x < geometry.side && y < geometry.side)
            .filter(|t| !(have && self.texels.contains_key(t)))
            .collect();
        missing.sort_unstable();
        missing.dedup();
        if missing.is_empty() || self.job.is_some() || !allow {
            return;
        }
        let attempt = (geometry.clone(), missing.clone());
        if self.failed.as_ref() == Some(&attempt) {
            return;
        }
        // The BVH of this scene generation and width when built, else the fibres to build it from.
        let bvh = self
            .bvh
            .as_ref()
            .filter(|(k, _)| *k == geometry.bvh_key())
            .map(|(_, b)| b.clone());
        let source = match bvh {
            Some(b) => Ok(b),
            None => Err(fibres.strands.clone()),
        };
        let width = settings.render.strand_width;
        let job = Job::spawn("ray-traced V(z)", ctx, gate, move |ctl| {
            let bvh = match source {
                Ok(b) => b,
                Err(strands) => {
                    ctl.step("building the fibres' BVH", 0.0).then_some(())?;
                    Arc::new(Bvh::new(fibre::segments(&strands, width)))
                }
            };
            let rays = trace(&bvh, &geometry, &missing, &mut ctl.clone().part(0.5, 1.0))?;
            Some(Batch { geometry, bvh, rays })
        });
        self.job = Some((attempt, job));
        // A small scene's curve shows in the frame that asked for it.
        self.poll(PATIENCE);
    }

    /// The rays of `texel` for the geometry of the last [`Traced::update`], when traced.
    pub fn get(&self, texel: [u32; 2]) -> Option<Arc<TracedRays>> {
        let current = self.current.as_ref()?;
        (self.geometry.as_ref() == Some(current))
            .then(|| self.texels.get(&texel).cloned())
            .flatten()
    }

    /// Whether a job is tracing.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    pub fn status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(|(_, j)| j.status())
    }
}

/// What the whole-map fit is of: the scene, and the light view's key with the hair alpha left out (it moves the
/// reference's `V`, not the fibres' nor the fit).
#[derive(Clone, Debug, PartialEq)]
struct FitKey {
    scene: SceneSettings,
    lists: ListsKey,
}

impl FitKey {
    fn of(settings: &Settings) -> FitKey {
        let mut s = settings.clone();
        s.render.hair_alpha = 0.0;
        FitKey {
            scene: s.scene.clone(),
            lists: ListsKey::new(&s, None),
        }
    }
}

/// The `α` whose `(1 − α)^k` fits the ray-traced `V` of the whole map best, with the comparison it came from.
#[derive(Clone, Debug)]
pub struct AlphaFit {
    key: FitKey,
    /// `compare_map` at [`FIT_RAYS`] a side on the scene as built from the settings.
    pub comparison: MapComparison,
    /// The scene's `hair_alpha` and alpha mode when fitted (the comparison's mean `|ΔV|` is at them).
    pub scene_alpha: f32,
    pub alpha_mode: AlphaMode,
}

impl AlphaFit {
    /// Whether the fit is of the scene, light and map of `settings`.
    pub fn is_of(&self, settings: &Settings) -> bool {
        self.key == FitKey::of(settings)
    }

    /// The fitted `α` as a `hair_alpha` (`None` when no fibre was crossed: `α` 0 is not a setting).
    pub fn alpha(&self) -> Option<f32> {
        let a = self.comparison.best_alpha as f32;
        (a > 0.0 && a <= 1.0).then_some(a)
    }

    /// The result line: the fitted `α`, the mean `|ΔV|` it leaves against the scene's, and the scene's `α`.
    pub fn summary(&self, settings: &Settings) -> String {
        let c = &self.comparison;
        format!(
            "best-fit α = {:.3} (mean |ΔV| {:.4} -> {:.4}), scene α = {}",
            c.best_alpha, c.mean_abs_dv, c.mean_abs_dv_at_best, settings.render.hair_alpha
        )
    }
}

/// The fit, and the job computing it.
#[derive(Default)]
pub(super) struct Fit {
    pub fit: Option<AlphaFit>,
    job: Option<Job<Result<AlphaFit, String>>>,
}

impl Fit {
    /// Starts fitting `α` to the ray-traced fibres of `settings`' scene on `gpu` (a job), replacing a fit under way.
    pub fn start(&mut self, gpu: Gpu, settings: &Settings, ctx: &egui::Context, gate: Option<JobGate>) {
        let settings = settings.clone();
        self.job = Some(Job::spawn("α fit to the fibres", ctx, gate, move |ctl| {
            ctl.step("reading the fragment lists", 0.0).then_some(())?;
            let comparison = compare_map(&gpu, &settings, FIT_RAYS, &mut ctl.clone());
            if ctl.cancelled() {
                return None;
            }
            Some(
                comparison
                    // Only Cancel ends this job early, and a cancelled job's result is dropped: what comes
                    // back is complete.
                    .map(|outcome| AlphaFit {
                        key: FitKey::of(&settings),
                        comparison: outcome.kept(),
                        scene_alpha: settings.render.hair_alpha,
                        alpha_mode: settings.render.alpha,
                    })
                    .map_err(|e| format!("α fit: {e:#}")),
            )
        }));
    }

    /// Takes the fit when its job finished (waiting up to `patience`): the status line's message when it ended.
    pub fn poll(&mut self, patience: Duration) -> Option<Result<String, String>> {
        let job = self.job.as_ref()?;
        match job.wait(patience) {
            Poll::Running => None,
            Poll::Done(result) => {
                self.job = None;
                Some(result.map(|fit| {
                    let c = &fit.comparison;
                    let m = format!(
                        "α fit: best-fit α {:.3} over {} texels ({} rays each)",
                        c.best_alpha,
                        c.texels.len(),
                        c.rays_per_texel
                    );
                    self.fit = Some(fit);
                    m
                }))
            }
            Poll::Gone => {
                let cancelled = job.cancelled();
                self.job = None;
                Some(if cancelled {
                    Ok("α fit cancelled".to_string())
                } else {
                    Err("α fit: the worker stopped without a result".to_string())
                })
            }
        }
    }

    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    pub fn status(&self) -> Option<JobStatus> {
        self.job.as_ref().map(Job::status)
    }
}

/// What the fit's row asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FitClick {
    Start,
    Apply,
}

/// The fit's row: the button, the result for these settings and the offer to apply it.
pub(super) fn fit_row(ui: &mut egui::Ui, fit: &Fit, settings: &Settings) -> Option<FitClick> {
    let mut click = None;
    let directional = settings.light.kind == LightKind::Directional;
    ui.horizontal_wrapped(|ui| {
        let button = ui
            .add_enabled(directional && !fit.running(), egui::Button::new("Fit α to fibres"))
            .on_hover_text(format!(
                "the single α whose (1 − α)^k best fits the ray-traced V of every occupied texel of the map \
                 ({FIT_RAYS}×{FIT_RAYS} rays a texel, halfway between its fragments; least squares, as `hairlab \
                 measure visibility`), on the scene as built from the settings (rest pose)"
            ))
            .on_disabled_hover_text(if directional {
                "fitting…"
            } else {
                SPOT_NOTE
            });
        if button.clicked() {
            click = Some(FitClick::Start);
        }
        match fit.fit.as_ref().filter(|f| f.is_of(settings)) {
            Some(f) => {
                ui.label(f.summary(settings));
                let constant = settings.render.alpha == AlphaMode::Constant;
                match f.alpha() {
                    Some(_) if !constant => {
                        ui.weak("(a constant α: render.alpha is coverage)");
                    }
                    Some(a)
                        if a != settings.render.hair_alpha
                            && ui
                                .button(format!("Set hair α {a:.3}"))
                                .on_hover_text(
                                    "make the fitted α the scene's render.hair_alpha (undo with Ctrl+Z)",
                                )
                                .clicked() =>
                    {
                        click = Some(FitClick::Apply);
                    }
                    _ => {}
                }
            }
            None if fit.running() => {
                ui.weak("fitting (see the job bar)");
            }
            None => {}
        }
    });
    click
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::visibility::texel_visibility;
    use glam::Vec3;

    /// The curve from the rays' first crossings is `texel_visibility` at the same depths.
    #[test]
    fn curve_counts_first_crossings_as_texel_visibility_does() {
        // Three strands along x at depths 2, 4 and 6, each 0.14 wide, across a texel 2 wide looking along +z (the
        // identity frame's one texel): V ends near 1 − 3 · 0.14 / 2 = 0.79.
        let segments = [(0.2f32, 2.0f32), (0.5, 4.0), (0.8, 6.0)]
            .iter()
            .map(|&(y, z)| fibre::Segment::new(Vec3::new(-2.0, y, z), Vec3::new(2.0, y, z), 0.07, 0.07))
            .collect();
        let bvh = Bvh::new(segments);
        let frame = LightFrame {
            world_to_view: glam::Mat4::IDENTITY,
            view_to_clip: glam::Mat4::IDENTITY,
            near: 0.0,
            far: 10.0,
            position: Vec3::ZERO,
            to_light: -Vec3::Z,
        };
        let geometry = Geometry {
            generation: 1,
            strand_width: 0,
            frame,
            side: 1,
        };
        let rays = trace(&bvh, &geometry, &[[0, 0]], &mut crate::progress::Quiet).unwrap();
        let r = &rays[0];
        assert_eq!(
            (r.rays, r.footprint.seed, r.first.len()),
            (TRACED_RAYS, 0, TRACED_RAYS * TRACED_RAYS)
        );
        let zs: Vec<f32> = (0..=100).map(|i| i as f32 / 100.0).collect();
        let at: Vec<f32> = zs.iter().map(|z| z * r.span).collect();
        let want = texel_visibility(&bvh, &r.footprint, TRACED_RAYS, &at);
        assert_eq!(r.curve(&zs), want);
        assert_eq!(want[0], 1.0);
        assert!((want[100] - 0.79).abs() < 0.03, "{}", want[100]);
        assert!(
            want[10] == 1.0 && want[10] > want[30] && want[30] > want[50] && want[50] > want[70],
            "{want:?}"
        );
    }
}
