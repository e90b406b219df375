//! The path-traced truth of `measure shadows --truth path-traced` and the error decomposition it gives: under
//! each shading model, a method's image error against the depth-peeled reference (the method's own error), the
//! reference's error against the path-traced image (the opacity model's and the shading model's: every strand
//! fragment attenuating by `α`, light scattering once, against fibres and multiple scattering), and the method's
//! error against the path-traced image (the total). The truth does not depend on the shading model: it is the
//! scene's fibres under Chiang et al. 2016's BSDF (`crate::pathtrace`), rendered once at [`super::IMAGE_SIZE`].

use anyhow::Result;
use serde::Serialize;

use super::IMAGE_SIZE;
use crate::pathtrace::setup::PathScene;
use crate::progress::Progress;
use crate::settings::Settings;

/// The files `measure shadows --truth path-traced --out` (and a report) write beside `results.csv`.
pub const DECOMPOSITION_CSV: &str = "decomposition.csv";
pub const TRUTH_PNG: &str = "truth_path_traced.png";
/// The stem of the speed chart against the truth, and its two files.
pub const TRUTH_CHART: &str = "speed_vs_truth";
pub const TRUTH_CHART_FILES: [&str; 2] = ["speed_vs_truth.png", "speed_vs_truth.svg"];

/// The path-traced image of a still scene.
pub struct Truth {
    /// sRGB over black, as the raster images it is compared with.
    pub image: image::RgbaImage,
    pub spp: u32,
    pub seconds: f64,
}

/// Path-traces the still scene of `settings` at [`IMAGE_SIZE`] and `render.spp` samples per pixel, telling
/// `progress` after each pass; `None` when it asked to stop before the last.
pub fn path_traced(settings: &Settings, progress: &mut dyn Progress) -> Result<Option<Truth>> {
    let mut s = settings.clone();
    (s.render.width, s.render.height) = IMAGE_SIZE;
    let scene = s.scene.build()?;
    let start = std::time::Instant::now();
    let path = PathScene::new(&s, &scene)?;
    let of = path.settings.samples;
    let (linear, spp) = path.render(of.div_ceil(16), progress);
    if spp < of {
        return Ok(None);
    }
    let rgba: Vec<[f32; 4]> = linear.iter().map(|v| [v.x, v.y, v.z, 1.0]).collect();
    Ok(Some(Truth {
        image: super::fur::over_black(&rgba, IMAGE_SIZE.0, IMAGE_SIZE.1),
        spp,
        seconds: start.elapsed().as_secs_f64(),
    }))
}

/// One image against another: RMSE of sRGB in [0, 1] and mean FLIP.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ImageError {
    pub rmse: f64,
    pub flip: f64,
}

impl ImageError {
    pub fn of(image: &image::RgbaImage, against: &image::RgbaImage) -> ImageError {
        ImageError {
            rmse: super::image_error(image, against).0,
            flip: crate::transparency::FlipMap::new(image, against)
                .metrics(|_, _| false)
                .mean,
        }
    }
}

/// One row of `decomposition.csv`: a configuration under a shading model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Decomposition {
    pub method: String,
    pub shading: &'static str,
    /// The method against the depth-peeled reference.
    pub method_rmse: f64,
    /// The depth-peeled reference against the path-traced truth.
    pub opacity_model_rmse: f64,
    /// The method against the path-traced truth.
    pub total_rmse: f64,
    pub method_flip: f64,
    pub opacity_model_flip: f64,
    pub total_flip: f64,
}

impl Decomposition {
    pub fn new(
        method: String,
        shading: &'static str,
        own: ImageError,
        model: ImageError,
        total: ImageError,
    ) -> Self {
        Decomposition {
            method,
            shading,
            method_rmse: own.rmse,
            opacity_model_rmse: model.rmse,
            total_rmse: total.rmse,
            method_flip: own.flip,
            opacity_model_flip: model.flip,
            total_flip: total.flip,
        }
    }
}
