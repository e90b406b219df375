//! A preset's still scene as the path tracer sees it, one place for `render`, the window, `measure` and
//! `export --format mitsuba`: the fibres (per-point widths from the file's thickness times
//! `render.strand_width`), the meshes as Lambertian triangles, the framed camera, the directional light and the
//! fibre BSDF's parameters from the hair colour through the real-time Marschner model's constants.

use anyhow::Result;
use glam::Vec3;

use super::bsdf::FibreParams;
use super::bvh::Bvh;
use super::integrator::{self, DirectionalLight};
use super::{fibre, triangle};
use crate::scene::{Camera, LightKind, Scene};
use crate::settings::Settings;
use crate::shading::marschner;

/// Bounces at most: hair's long chains of scattering (light hair is mostly multiple scattering).
pub const MAX_DEPTH: u32 = 32;

/// The fibres' material for a linear hair colour: Chiang et al. 2016's colour inversion at the real-time
/// Marschner model's roughness, cuticle tilt and index of refraction.
pub fn fibre_params(hair_color: [f32; 3]) -> FibreParams {
    FibreParams::from_colour(
        Vec3::from(hair_color),
        marschner::BETA_R,
        marschner::BETA_N,
        marschner::ALPHA_R,
    )
}

/// The directional light of `settings`; an error for a spot light, which the path tracer does not model. Its
/// irradiance is π × colour × intensity: the raster shades a mesh `colour × light × N·L`, so a white Lambertian
/// surface facing a light of intensity 1 shows 1, which is what irradiance π gives it.
pub fn light(settings: &Settings) -> Result<DirectionalLight> {
    if settings.light.kind != LightKind::Directional {
        anyhow::bail!(
            "light.kind: the path tracer lights the scene with a directional light only (light.kind = directional)"
        );
    }
    Ok(DirectionalLight {
        to_light: settings.light.to_light(),
        irradiance: Vec3::from(settings.light.color) * settings.light.intensity * std::f32::consts::PI,
    })
}

/// The camera of `settings`, framed on `scene` where the preset leaves the distance at 0.
pub fn camera(settings: &Settings, scene: &Scene) -> Camera {
    let mut camera = settings.camera;
    if camera.distance <= 0.0 {
        camera.frame(&scene.framing_bounds());
    }
    camera
}

/// Everything one path-traced image of a still scene needs.
pub struct PathScene {
    pub bvh: Bvh,
    pub camera: Camera,
    pub light: DirectionalLight,
    pub settings: integrator::Settings,
}

impl PathScene {
    /// `scene` under `settings` at `render.width × render.height` and `render.spp` samples per pixel.
    pub fn new(settings: &Settings, scene: &Scene) -> Result<PathScene> {
        let r = &settings.render;
        let light = light(settings)?;
        let bvh = Bvh::with_triangles(
            fibre::segments(&scene.strands, r.strand_width),
            triangle::triangles(&scene.meshes),
        );
        Ok(PathScene {
            bvh,
            camera: camera(settings, scene),
            light,
            settings: integrator::Settings {
                width: r.width as usize,
                height: r.height as usize,
                samples: r.spp,
                seed: r.seed,
                max_depth: MAX_DEPTH,
                fibre: fibre_params(r.hair_color),
            },
        })
    }

    /// The image in passes of `pass` samples per pixel ([`integrator::render_in_passes`]).
    pub fn render(&self, pass: u32, after_pass: &mut dyn FnMut(u32) -> bool) -> (Vec<Vec3>, u32) {
        integrator::render_in_passes(
            &self.bvh,
            &self.camera,
            &self.light,
            &self.settings,
            pass,
            after_pass,
        )
    }
}

/// `image` (`width × height` linear RGB, row after row) as an OpenEXR file of 32-bit floats.
pub fn encode_exr(image: &[Vec3], width: u32, height: u32) -> Result<Vec<u8>> {
    let data: Vec<f32> = image.iter().flat_map(|v| v.to_array()).collect();
    let buffer = image::Rgb32FImage::from_raw(width, height, data)
        .ok_or_else(|| anyhow::anyhow!("{width}×{height} does not match {} pixels", image.len()))?;
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb32F(buffer).write_to(&mut out, image::ImageFormat::OpenExr)?;
    Ok(out.into_inner())
}
