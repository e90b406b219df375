//! The path-traced truth of `measure shadows --truth path-traced` (and a report's truth section), measured and
//! written in this one place: the scene's fibres under Chiang et al. 2016's BSDF (`crate::pathtrace`) with every
//! scattering event, and the chain of path-traced images that turn the real-time model's effects on one at a
//! time (`decompose.rs`, `docs/truth.md`): no light bounced off meshes; one scattering event; the fibres' shadow
//! read from the depth-peeled
//! reference's light map; the raster's lobes and light at the first hit, one event; its whole shading there,
//! an image of each per shading model. Each is the mean
//! of two renders (seeds `render.seed` and `render.seed + 1`, `render.spp / 2` samples each) so that their
//! difference measures its noise. The regions (hair, receivers) come from the first hits of 4 × 4 rays a pixel.

use std::sync::Arc;

use anyhow::Result;
use glam::{Vec2, Vec3};

use super::IMAGE_SIZE;
use super::decompose::{Masks, SharedSteps, Stage, step};
use crate::gpu::Gpu;
use crate::path_scene::{PathScene, raster_shading};
use crate::pathtrace::effects::{Effects, Events, FirstHit, HairShadows, VisibilityMap};
use crate::pathtrace::{integrator, masks};
use crate::progress::{Part, Progress};
use crate::render::Renderer;
use crate::settings::Settings;
use crate::shading::ShadingModel;
use crate::visibility::lookup::Lookup;
use crate::visibility::reference::Reference;
use crate::visibility::{Fragment, Model};

/// The files `measure shadows --truth path-traced --out` (and a report) write beside `results.csv`.
pub const DECOMPOSITION_CSV: &str = "decomposition.csv";
pub const TRUTH_PNG: &str = "truth_path_traced.png";
/// The stem of the speed chart against the truth, and its two files.
pub const TRUTH_CHART: &str = "speed_vs_truth";
pub const TRUTH_CHART_FILES: [&str; 2] = ["speed_vs_truth.png", "speed_vs_truth.svg"];

/// Rays a side per pixel for the regions' first hits.
const MASK_RAYS: usize = 4;

/// The path-traced chain of a still scene at [`IMAGE_SIZE`].
pub struct Truth {
    /// The truth (every effect).
    pub truth: Stage,
    /// Every scattering event among the fibres, no light bounced off a mesh after the first hit.
    pub fibre_events: Stage,
    /// One scattering event, the fibres' shadow traced.
    pub one_event: Stage,
    /// One event, the fibres' shadow from the depth-peeled reference's light map.
    pub map_shadows: Stage,
    /// One event, the map's shadow, the raster's lobes and light at the first hit, none of its light beyond
    /// one event (`RasterShading::scattered` false): one per shading model asked for.
    pub raster_direct: Vec<(ShadingModel, Stage)>,
    /// The same with the raster's light beyond one event: its whole shading at the first hit.
    pub raster_shading: Vec<(ShadingModel, Stage)>,
    /// The depth-peeled reference's raster image under each model, the chain's last image before the method's
    /// (`shading::against_truth` adds them once drawn; empty until then).
    pub reference: Vec<(ShadingModel, Stage)>,
    pub masks: Masks,
    /// The truth's samples per pixel (both seeds together).
    pub spp: u32,
    /// Samples left out of the chain's images for a NaN or infinite radiance (the caller says so when any were).
    pub dropped: u64,
    pub seconds: f64,
}

impl Truth {
    /// The chain's path-traced images with the file names they are written as: [`TRUTH_PNG`], then
    /// `truth_fibre_events.png`, `truth_one_event.png`, `truth_map_shadows.png`, `truth_raster_one_<model>.png`,
    /// `truth_raster_<model>.png` and the raster's own `truth_reference_<model>.png`.
    pub fn chain_images(&self) -> Vec<(String, &Stage)> {
        let mut out = vec![
            (TRUTH_PNG.to_owned(), &self.truth),
            ("truth_fibre_events.png".to_owned(), &self.fibre_events),
            ("truth_one_event.png".to_owned(), &self.one_event),
            ("truth_map_shadows.png".to_owned(), &self.map_shadows),
        ];
        out.extend(
            self.raster_direct
                .iter()
                .map(|(m, s)| (format!("truth_raster_one_{}.png", m.word()), s)),
        );
        out.extend(
            self.raster_shading
                .iter()
                .map(|(m, s)| (format!("truth_raster_{}.png", m.word()), s)),
        );
        out.extend(
            self.reference
                .iter()
                .map(|(m, s)| (format!("truth_reference_{}.png", m.word()), s)),
        );
        out
    }

    /// The steps that do not depend on the method under `model` (one of those the chain was traced for).
    pub fn shared_steps(&self, model: ShadingModel, reference: &Stage) -> Option<SharedSteps> {
        let (_, raster) = self.raster_shading.iter().find(|(m, _)| *m == model)?;
        let (_, direct) = self.raster_direct.iter().find(|(m, _)| *m == model)?;
        Some(SharedSteps {
            mesh_bounce: step(&self.truth, &self.fibre_events, &self.masks),
            multiple_scattering: step(&self.fibre_events, &self.one_event, &self.masks),
            shadowing: step(&self.one_event, &self.map_shadows, &self.masks),
            shading: step(&self.map_shadows, direct, &self.masks),
            scattered_light: step(direct, raster, &self.masks),
            eye_coverage: step(raster, reference, &self.masks),
        })
    }
}

/// The depth-peeled reference's visibility at a world point, read as the eye pass reads it (`Lookup`: the
/// base texel, supersampling and 3×3 PCF of `render`; half-texel jitter is not modelled; under the fibres model
/// a fibre's point moved towards the light by `fibre_transport::own_strand_offset`, as `shaders/hair.wgsl`
/// moves a strand fragment's).
fn reference_map(gpu: &Gpu, settings: &Settings, scene: &crate::scene::Scene) -> Result<VisibilityMap> {
    let camera = crate::path_scene::camera(settings, scene);
    let mut r = Renderer::new(gpu, scene, settings.render.map_resolution)?;
    let lists = r.reference_lists(&camera, &settings.light, &settings.render)?;
    let frame = r.hair_light_frame(&settings.light);
    let texels: Vec<_> = lists
        .iter()
        .map(|l| Reference.build(&l.iter().map(|f| f.fragment()).collect::<Vec<Fragment>>()))
        .collect();
    let lookup = Lookup {
        base: settings.render.map_resolution,
        supersample: settings.render.light_supersample.max(1),
        pcf: settings.render.pcf,
    };
    let side = lookup.side() as usize;
    let to_clip = frame.world_to_clip();
    let footprint = crate::render::footprint_per_w(&frame.view_to_clip, side as u32, side as u32);
    let fibres = settings.render.hair_model == crate::shading::HairModel::Fibres;
    let spot = settings.light.kind == crate::scene::LightKind::Spot;
    Ok(Arc::new(move |at: Vec3, tangent: Option<Vec3>| {
        let c = to_clip * at.extend(1.0);
        if c.w <= 0.0 {
            return 1.0;
        }
        let p = match tangent.filter(|_| fibres) {
            Some(t) => {
                let l = if spot {
                    (frame.position - at).normalize_or_zero()
                } else {
                    frame.to_light
                };
                at + l * crate::shading::fibre_transport::own_strand_offset(footprint * c.w, t, l)
            }
            None => at,
        };
        let c = to_clip * p.extend(1.0);
        let uv = Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5);
        lookup.visibility(uv, frame.depth(p), |[x, y], z| {
            texels
                .get(y as usize * side + x as usize)
                .map_or(1.0, |t| Reference.visibility(t, z))
        })
    }))
}

/// Path-traces the chain of `settings`' still scene at [`IMAGE_SIZE`] for `models`, telling `progress` as it
/// goes; `None` when it asked to stop.
pub fn path_traced(
    gpu: &Gpu,
    settings: &Settings,
    models: &[ShadingModel],
    progress: &mut dyn Progress,
) -> Result<Option<Truth>> {
    let mut s = settings.clone();
    (s.render.width, s.render.height) = IMAGE_SIZE;
    let scene = s.scene.build()?;
    let start = std::time::Instant::now();
    let path = PathScene::new(&s, &scene)?;
    let (w, h) = (path.settings.width, path.settings.height);
    let masks = Masks::from_first_hits(&masks::first_hits(&path.bvh, &path.camera, w, h, MASK_RAYS));
    let map = reference_map(gpu, &s, &scene)?;
    let raster = raster_shading(&s, &scene, &scene.bounds());
    let one = |hair_shadows, first_hit| Effects {
        events: Events::One,
        hair_shadows,
        first_hit,
    };
    let mut chain = vec![
        Effects::TRUTH,
        Effects {
            events: Events::Fibres,
            ..Effects::TRUTH
        },
        one(HairShadows::Traced, FirstHit::Physical),
        one(HairShadows::Map(map.clone()), FirstHit::Physical),
    ];
    for scattered in [false, true] {
        chain.extend(models.iter().map(|&model| {
            one(
                HairShadows::Map(map.clone()),
                FirstHit::Raster(crate::pathtrace::effects::RasterShading {
                    model,
                    scattered,
                    ..raster.clone()
                }),
            )
        }));
    }
    let spp = path.settings.samples.max(2);
    let (mut stages, mut dropped) = (Vec::with_capacity(chain.len()), 0);
    let parts = chain.len() as f32;
    for (k, effects) in chain.into_iter().enumerate() {
        // The truth takes most of the time: the one-event images stop after one bounce.
        let (from, to) = (k as f32 / parts, (k + 1) as f32 / parts);
        let mut part = Part::of(&mut *progress, from, to);
        let Some(stage) = traced_pair(&path, effects, spp, &mut dropped, &mut part) else {
            return Ok(None);
        };
        stages.push(stage);
    }
    let mut stages = stages.into_iter();
    let mut next = || stages.next().expect("one stage per effect set");
    Ok(Some(Truth {
        truth: next(),
        fibre_events: next(),
        one_event: next(),
        map_shadows: next(),
        raster_direct: models.iter().map(|&m| (m, next())).collect(),
        raster_shading: models.iter().map(|&m| (m, next())).collect(),
        reference: Vec::new(),
        masks,
        spp: spp / 2 * 2,
        dropped,
        seconds: start.elapsed().as_secs_f64(),
    }))
}

/// The mean of two renders of `path` under `effects` (seeds `seed` and `seed + 1`, `spp / 2` samples each),
/// adding the samples they left out (NaN or infinite) to `dropped`; `None` when `progress` asked to stop.
fn traced_pair(
    path: &PathScene,
    effects: Effects,
    spp: u32,
    dropped: &mut u64,
    progress: &mut dyn Progress,
) -> Option<Stage> {
    let mut renders = Vec::with_capacity(2);
    for k in 0..2u64 {
        let s = integrator::TraceSettings {
            samples: spp / 2,
            seed: path.settings.seed.wrapping_add(k),
            effects: effects.clone(),
            ..path.settings.clone()
        };
        let mut part = Part::of(&mut *progress, k as f32 * 0.5, (k + 1) as f32 * 0.5);
        let pass = s.samples.div_ceil(8).max(1);
        let acc = integrator::render_in_passes(&path.bvh, &path.camera, &path.light, &s, pass, &mut part);
        if acc.samples() < s.samples {
            return None;
        }
        *dropped += acc.dropped();
        renders.push(acc.mean());
    }
    let (w, h) = (path.settings.width as u32, path.settings.height as u32);
    let srgb = |v: &[Vec3]| {
        let rgba: Vec<[f32; 4]> = v.iter().map(|p| [p.x, p.y, p.z, 1.0]).collect();
        crate::io::over_black(&rgba, w, h)
    };
    let mean: Vec<Vec3> = renders[0]
        .iter()
        .zip(&renders[1])
        .map(|(a, b)| 0.5 * (*a + *b))
        .collect();
    Some(Stage::of_two(srgb(&mean), srgb(&renders[0]), srgb(&renders[1])))
}

/// The shading model the truth chart is drawn under: the settings' when measured, else the first measured.
pub fn chart_shading(settings: &Settings, models: &[ShadingModel]) -> ShadingModel {
    models
        .iter()
        .copied()
        .find(|m| *m == settings.render.shading)
        .unwrap_or(models[0])
}
