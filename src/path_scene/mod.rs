//! A preset's still scene as the path tracer sees it, one place for `render`, the window, `measure` and
//! `export --format mitsuba`: the fibres (per-point widths from the file's thickness times
//! `render.strand_width`), the meshes as Lambertian triangles, the framed camera, the light and the fibres'
//! BSDF from the hair colour ([`fibre_params`]); the same scene for Mitsuba 3 ([`mitsuba`]). The path tracer
//! itself (`crate::pathtrace`) knows no settings.

use anyhow::Result;
use glam::Vec3;

pub mod mitsuba;

use crate::pathtrace::bsdf::fibre_params;
use crate::pathtrace::bvh::Bvh;
use crate::pathtrace::effects::{self, Effects, Events, FirstHit, HairShadows, RasterLight, RasterShading};
use crate::pathtrace::integrator::{self, MAX_DEPTH};
use crate::pathtrace::light::{DirectionalLight, Light, SpotLight};
use crate::pathtrace::{fibre, triangle};
use crate::render::render_settings::{PathEvents, PathFirstHit, PathHairShadows};
use crate::scene::{Aabb, Camera, LightKind, Scene};
use crate::settings::Settings;
use crate::shading::HairModel;

/// The light of `settings` over `scene`. Both kinds give a white Lambertian surface facing the light at the
/// scene's centre what the raster shows it (`colour × light × N·L`: the light's colour × intensity): the
/// directional light irradiance π × colour × intensity; the spot, placed as the raster places it
/// ([`crate::scene::Light::spot_position`] around `around`, the box the renderer's light fit places it around), a
/// radiant intensity that gives that irradiance at `around`'s centre, full within the half-angle where the raster's cone edge ramp reaches 1 and none beyond half of
/// `light.cone_deg`, linear in angle between (Mitsuba's `spot`).
pub fn light(settings: &Settings, around: &Aabb) -> Light {
    let l = &settings.light;
    let irradiance = Vec3::from(l.color) * l.intensity * std::f32::consts::PI;
    match l.kind {
        LightKind::Directional => Light::Directional(DirectionalLight {
            to_light: l.to_light(),
            irradiance,
        }),
        LightKind::Spot => {
            let centre = if around.is_empty() {
                Vec3::ZERO
            } else {
                around.center()
            };
            let position = l.spot_position(around);
            let cutoff = (l.cone_deg * 0.5).to_radians();
            let edge = cutoff.cos();
            let beam = (edge + effects::SPOT_RAMP * (1.0 - edge)).acos();
            Light::Spot(SpotLight {
                position,
                axis: (centre - position).normalize(),
                intensity: irradiance * centre.distance_squared(position),
                beam,
                cutoff,
            })
        }
    }
}

/// The effects `render.path` asks for ([`Effects::TRUTH`] by default).
pub fn effects(settings: &Settings, scene: &Scene, around: &Aabb) -> Effects {
    let p = &settings.render.path;
    Effects {
        events: match p.events {
            PathEvents::All => Events::All,
            PathEvents::Fibres => Events::Fibres,
            PathEvents::One => Events::One,
        },
        hair_shadows: match p.hair_shadows {
            PathHairShadows::Traced => HairShadows::Traced,
            PathHairShadows::Off => HairShadows::Off,
        },
        first_hit: match p.first_hit {
            PathFirstHit::Fibre => FirstHit::Physical,
            PathFirstHit::Raster => FirstHit::Raster(raster_shading(settings, scene, around)),
            PathFirstHit::Isotropic => FirstHit::Isotropic(crate::shading::mesh_bounce::hair_response(
                Vec3::from(settings.render.hair_color),
            )),
        },
    }
}

/// The raster's shading of `settings` at a first hit ([`FirstHit::Raster`]): its shading model,
/// hair colour and alpha, and its light (colour × intensity; a spot with its smooth edge and no falloff, placed
/// as [`light`] places the path tracer's).
pub fn raster_shading(settings: &Settings, scene: &Scene, around: &Aabb) -> RasterShading {
    let l = &settings.light;
    let spot = match light(settings, around) {
        Light::Spot(s) => Some((s.position, s.axis, (l.cone_deg * 0.5).to_radians().cos())),
        Light::Directional(_) => None,
    };
    let light = RasterLight {
        radiance: Vec3::from(l.color) * l.intensity,
        to_light: l.to_light(),
        spot,
    };
    let bounce = (settings.render.hair_model == HairModel::Fibres).then(|| {
        let strands = &scene.strands;
        let ranges: Vec<(usize, usize)> = strands.ranges().collect();
        std::sync::Arc::new(crate::pathtrace::probe::bake(
            settings.render.probe,
            &light,
            Vec3::from(settings.render.hair_color),
            &strands.points,
            &ranges,
            |k| strands.thickness.as_ref().map_or(1.0, |t| t[k]) * settings.render.strand_width,
            triangle::triangles(&scene.meshes),
        ))
    });
    RasterShading {
        model: settings.render.shading,
        colour: Vec3::from(settings.render.hair_color),
        hair: settings.render.hair_model,
        probe: settings.render.probe,
        hair_alpha: settings.render.opacity(),
        ambient: settings.render.ambient_scale(),
        bounce,
        light,
        scattered: true,
    }
}

/// The camera of `settings`, framed on `scene` where the preset leaves the distance at 0.
pub fn camera(settings: &Settings, scene: &Scene) -> Camera {
    let mut camera = settings.camera;
    if camera.distance <= 0.0 {
        camera.frame(&scene.framing_bounds());
    }
    camera
}

/// Checks that `scene`'s fibres under `render.strand_width` are thinner than the strands' bounds are across: a
/// fibre wider than the whole hair is a unit mistake (millimetres for metres), and a BVH of such fibres would
/// swallow the scene. The widest fibre is `render.strand_width` times the largest point thickness.
pub fn check_width(settings: &Settings, scene: &Scene) -> Result<()> {
    let width = settings.render.strand_width;
    let thickest = scene
        .strands
        .thickness
        .as_ref()
        .map_or(1.0, |t| t.iter().copied().fold(0.0f32, f32::max));
    let bounds = scene.strand_bounds();
    let across = if bounds.is_empty() {
        0.0
    } else {
        (bounds.max - bounds.min).length()
    };
    let widest = width * thickest;
    if scene.strands.segment_count() > 0 && (widest >= across || widest.is_nan()) {
        anyhow::bail!(
            "render.strand_width = {width} makes fibres {widest} wide (× the largest point thickness {thickest}): \
             wider than the hair, whose bounds are {across} across; the width is in the scene's world units"
        );
    }
    Ok(())
}

/// Everything one path-traced image of a still scene needs.
pub struct PathScene {
    pub bvh: Bvh,
    pub camera: Camera,
    pub light: Light,
    pub settings: integrator::TraceSettings,
}

impl PathScene {
    /// The still `scene` under `settings` at `render.width × render.height` and `render.spp` samples per pixel,
    /// its light placed around the whole scene, as the renderer places a still scene's under every light fit.
    pub fn new(settings: &Settings, scene: &Scene) -> Result<PathScene> {
        PathScene::placed(settings, scene, &scene.bounds())
    }

    /// [`PathScene::new`] with the light placed around `around`: a posed frame's, the box the renderer's light
    /// fit places the light around (`Renderer::light_around`), so both draw one light.
    pub fn placed(settings: &Settings, scene: &Scene, around: &Aabb) -> Result<PathScene> {
        check_width(settings, scene)?;
        let r = &settings.render;
        let light = light(settings, around);
        let bvh = Bvh::with_triangles(
            fibre::segments(&scene.strands, r.strand_width),
            triangle::triangles(&scene.meshes),
        );
        Ok(PathScene {
            bvh,
            camera: camera(settings, scene),
            light,
            settings: integrator::TraceSettings {
                width: r.width as usize,
                height: r.height as usize,
                samples: r.spp,
                seed: r.seed,
                max_depth: MAX_DEPTH,
                fibre: fibre_params(r.hair_color),
                effects: effects(settings, scene, around),
            },
        })
    }

    /// The image in passes of `pass` samples per pixel ([`integrator::render_in_passes`]).
    pub fn render(
        &self,
        pass: u32,
        progress: &mut dyn crate::progress::Progress,
    ) -> integrator::Accumulation {
        integrator::render_in_passes(
            &self.bvh,
            &self.camera,
            &self.light,
            &self.settings,
            pass,
            progress,
        )
    }

    /// Adds `n` samples per pixel to `acc` (made by [`PathScene::accumulation`]).
    pub fn add_samples(&self, acc: &mut integrator::Accumulation, n: u32) {
        acc.add(&self.bvh, &self.camera, &self.light, &self.settings, n);
    }

    /// An empty progressive image of this scene's size.
    pub fn accumulation(&self) -> integrator::Accumulation {
        integrator::Accumulation::new(&self.settings)
    }
}
