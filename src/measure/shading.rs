//! The image error of each shadow method under each strand shading model (`measure shadows --shading a,b`):
//! how much a method's error grows when the shading it is judged under changes, e.g. when Marschner's
//! transmitted lobe (TT) lights the hair from behind. For every model the reference image is shaded with that
//! model, so each figure is the shadows' error alone under that shading. The visibility error at the visible
//! hair points (`Measurement::shading_error`) does not depend on the shading model and is not repeated here.
//! Given a path-traced truth (`truth.rs`), every image is drawn over black, as the path tracer's, and each
//! configuration's error is decomposed against it.

use super::truth::{Decomposition, ImageError, Truth};
use super::{IMAGE_SIZE, MethodConfig, image_error};
use crate::gpu::Gpu;
use crate::methods::{ParamValues, ShadowMethod, registry};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use crate::shading::ShadingModel;
use anyhow::Result;

/// One method's image error under one shading model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingError {
    pub model: ShadingModel,
    /// RMSE (RGB in [0,1]) of the image against the reference image under the same model.
    pub image_rmse: f64,
    /// Mean FLIP over all pixels against the same reference image.
    pub image_flip: f64,
    /// The image against the path-traced truth, where one was given.
    pub against_truth: Option<ImageError>,
}

/// One configuration's errors, one per shading model asked for, in the order asked.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingRow {
    pub config: MethodConfig,
    pub errors: Vec<ShadingError>,
}

/// Every configuration's errors, and, with a truth, the reference image's own error against it per model.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingTable {
    pub rows: Vec<ShadingRow>,
    /// The depth-peeled reference against the truth, one per model in the order asked (empty without a truth).
    pub reference_vs_truth: Vec<ImageError>,
}

impl ShadingTable {
    /// The decomposition of every configuration's error under every model (empty without a truth).
    pub fn decomposition(&self) -> Vec<Decomposition> {
        let mut out = Vec::new();
        for row in &self.rows {
            for (e, model) in row.errors.iter().zip(&self.reference_vs_truth) {
                if let Some(total) = e.against_truth {
                    let own = ImageError {
                        rmse: e.image_rmse,
                        flip: e.image_flip,
                    };
                    out.push(Decomposition::new(
                        row.config.label(),
                        e.model.word(),
                        own,
                        *model,
                        total,
                    ));
                }
            }
        }
        out
    }
}

/// Renders the scene of `settings` at [`IMAGE_SIZE`] under each of `models`, with the reference and with each
/// of `configs`, and compares each method's image with the reference image of the same model, and, given a
/// `truth`, every image with it (all drawn over black).
pub fn shading_errors_on(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    models: &[ShadingModel],
    truth: Option<&Truth>,
    mut progress: impl FnMut(&str),
) -> Result<ShadingTable> {
    let mut s = settings.clone();
    if truth.is_some() {
        s.render.background = [0.0; 3];
    }
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution)?;
    let technique = crate::render::transparency::registry::reference();
    let empty = ParamValues::new();
    let mut rows: Vec<ShadingRow> = configs
        .iter()
        .map(|c| ShadingRow {
            config: c.clone(),
            errors: Vec::new(),
        })
        .collect();
    let mut reference_vs_truth = Vec::new();
    for &model in models {
        progress(model.word());
        let mut render = s.render.clone();
        render.shading = model;
        let (w, h) = IMAGE_SIZE;
        let mut image =
            |method: &'static dyn ShadowMethod, params: &ParamValues| -> Result<image::RgbaImage> {
                r.render(&FrameInput {
                    camera: &s.camera,
                    light: &s.light,
                    render: &render,
                    method,
                    method_params: params,
                    technique,
                    technique_params: &s.transparency.params,
                    width: w,
                    height: h,
                })?;
                Ok(r.read_output()?)
            };
        let reference = image(registry::reference(), &empty)?;
        let against_truth = |image: &image::RgbaImage| truth.map(|t| ImageError::of(image, &t.image));
        reference_vs_truth.extend(against_truth(&reference));
        for row in &mut rows {
            let method = registry::find(&row.config.name).map_err(anyhow::Error::msg)?;
            let shaded = image(method, &row.config.params)?;
            let (image_rmse, _) = image_error(&shaded, &reference);
            let image_flip = crate::transparency::FlipMap::new(&shaded, &reference)
                .metrics(|_, _| false)
                .mean;
            row.errors.push(ShadingError {
                model,
                image_rmse,
                image_flip,
                against_truth: against_truth(&shaded),
            });
        }
    }
    Ok(ShadingTable {
        rows,
        reference_vs_truth,
    })
}

/// CSV `method,<model> img RMSE,<model> FLIP,...`: one row per configuration.
pub fn csv(models: &[ShadingModel], rows: &[ShadingRow]) -> Result<String> {
    let mut header = vec!["method".to_string()];
    for m in models {
        header.extend([format!("{} img RMSE", m.word()), format!("{} FLIP", m.word())]);
    }
    let rows = rows.iter().map(|row| {
        let mut r = vec![row.config.label()];
        for e in &row.errors {
            r.extend([e.image_rmse.to_string(), e.image_flip.to_string()]);
        }
        r
    });
    crate::io::csv_table("shading.csv", &header, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSV holds one column pair per model, in the order asked, and one row per configuration.
    #[test]
    fn csv_has_a_column_pair_per_model() {
        let models = [ShadingModel::KajiyaKay, ShadingModel::Marschner];
        let config = MethodConfig::new(registry::reference().name(), ParamValues::new());
        let rows = [ShadingRow {
            config: config.clone(),
            errors: models
                .iter()
                .zip([(0.5, 0.25), (0.125, 0.75)])
                .map(|(&model, (image_rmse, image_flip))| ShadingError {
                    model,
                    image_rmse,
                    image_flip,
                    against_truth: None,
                })
                .collect(),
        }];
        let text = csv(&models, &rows).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "method,kajiya-kay img RMSE,kajiya-kay FLIP,marschner img RMSE,marschner FLIP"
        );
        assert_eq!(lines[1], format!("{},0.5,0.25,0.125,0.75", config.label()));
        assert_eq!(lines.len(), 2);
    }

    /// The decomposition pairs each configuration's errors under a model with that model's reference-vs-truth
    /// error: method = against the reference, opacity model = the reference against the truth, total = against
    /// the truth.
    #[test]
    fn decomposition_pairs_each_model_with_the_reference_against_the_truth() {
        let models = [ShadingModel::KajiyaKay, ShadingModel::Marschner];
        let config = MethodConfig::new(registry::reference().name(), ParamValues::new());
        let e = |rmse, flip| ImageError { rmse, flip };
        let table = ShadingTable {
            rows: vec![ShadingRow {
                config: config.clone(),
                errors: vec![
                    ShadingError {
                        model: models[0],
                        image_rmse: 0.01,
                        image_flip: 0.02,
                        against_truth: Some(e(0.3, 0.4)),
                    },
                    ShadingError {
                        model: models[1],
                        image_rmse: 0.05,
                        image_flip: 0.06,
                        against_truth: Some(e(0.7, 0.8)),
                    },
                ],
            }],
            reference_vs_truth: vec![e(0.25, 0.375), e(0.625, 0.75)],
        };
        let d = table.decomposition();
        assert_eq!(d.len(), 2);
        assert_eq!(
            (
                d[1].method.as_str(),
                d[1].shading,
                d[1].method_rmse,
                d[1].opacity_model_rmse,
                d[1].total_rmse
            ),
            (config.label().as_str(), "marschner", 0.05, 0.625, 0.7)
        );
        assert_eq!(
            (d[0].method_flip, d[0].opacity_model_flip, d[0].total_flip),
            (0.02, 0.375, 0.4)
        );
        let csv = crate::io::csv_text("decomposition.csv", &d).unwrap();
        assert_eq!(
            csv.lines().next().unwrap(),
            "method,shading,method_rmse,opacity_model_rmse,total_rmse,method_flip,opacity_model_flip,total_flip"
        );
    }

    /// A configuration whose label lists several parameters (commas) stays one field: a CSV reader gets the
    /// label back whole and the row keeps its column count.
    #[test]
    fn a_label_with_commas_stays_one_field() {
        let models = [ShadingModel::KajiyaKay];
        let method = registry::all()
            .iter()
            .find(|m| m.params().len() >= 2)
            .expect("a method with two parameters");
        let params: ParamValues = method
            .params()
            .iter()
            .map(|p| (p.key.to_string(), p.default))
            .collect();
        let config = MethodConfig::new(method.name(), params);
        assert!(config.label().contains(','), "{}", config.label());
        let rows = [ShadingRow {
            config: config.clone(),
            errors: vec![ShadingError {
                model: models[0],
                image_rmse: 0.5,
                image_flip: 0.25,
                against_truth: None,
            }],
        }];
        let text = csv(&models, &rows).unwrap();
        let mut reader = ::csv::Reader::from_reader(text.as_bytes());
        let record = reader.records().next().expect("one row").expect("a valid row");
        assert_eq!(record.len(), 3);
        assert_eq!(&record[0], config.label());
        assert_eq!(&record[1], "0.5");
    }
}
