//! The image error of each shadow method under each strand shading model (`measure shadows --shading a,b`):
//! how much a method's error grows when the shading it is judged under changes, e.g. when Marschner's
//! transmitted lobe (TT) lights the hair from behind. For every model the reference image is shaded with that
//! model, so each figure is the shadows' error alone under that shading. The visibility error at the visible
//! hair points (`Measurement::shading_error`) does not depend on the shading model and is not repeated here.
//! Given a path-traced truth (`truth.rs`), every image is drawn over black, as the path tracer's, and each
//! configuration's error is decomposed against it by effect (`decompose.rs`).

use super::decompose::{Decomposition, Stage, rows as decomposition_rows, step};
use super::truth::Truth;
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
}

/// One configuration's errors, one per shading model asked for, in the order asked.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingRow {
    pub config: MethodConfig,
    pub errors: Vec<ShadingError>,
}

/// Every configuration's errors, and, with a truth, every configuration's error decomposed by effect under
/// every model (`decompose.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingTable {
    pub rows: Vec<ShadingRow>,
    /// Model after model, configuration after configuration, the chain's steps and the total (empty without a
    /// truth).
    pub decomposition: Vec<Decomposition>,
    /// With a truth, the reference's image under each model (empty without one).
    pub reference: Vec<(ShadingModel, image::RgbaImage)>,
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
    let mut decomposition = Vec::new();
    let mut references = Vec::new();
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
        let reference = Stage::exact(image(registry::reference(), &empty)?);
        let chain = truth.and_then(|t| Some((t, t.shared_steps(model, &reference)?)));
        for row in &mut rows {
            let method = registry::find(&row.config.name).map_err(anyhow::Error::msg)?;
            let shaded = image(method, &row.config.params)?;
            let (image_rmse, _) = image_error(&shaded, &reference.image);
            let image_flip = crate::transparency::FlipMap::new(&shaded, &reference.image)
                .metrics(|_, _| false)
                .mean;
            row.errors.push(ShadingError {
                model,
                image_rmse,
                image_flip,
            });
            if let Some((t, shared)) = &chain {
                let shaded = Stage::exact(shaded);
                decomposition.extend(decomposition_rows(
                    &row.config.label(),
                    model.word(),
                    shared,
                    &step(&reference, &shaded, &t.masks),
                    &step(&t.truth, &shaded, &t.masks),
                ));
            }
        }
        if truth.is_some() {
            references.push((model, reference.image));
        }
    }
    Ok(ShadingTable {
        rows,
        decomposition,
        reference: references,
    })
}

/// The truth of `settings` for `models` and every configuration's error under each model, decomposed by
/// effect: what `measure shadows --truth path-traced` and a report's truth section both run. `None` when
/// `progress` asked to stop.
pub fn against_truth(
    gpu: &Gpu,
    settings: &Settings,
    configs: &[MethodConfig],
    models: &[ShadingModel],
    progress: &mut dyn crate::progress::Progress,
) -> Result<Option<(Truth, ShadingTable)>> {
    let Some(mut truth) = super::truth::path_traced(
        gpu,
        settings,
        models,
        &mut crate::progress::Part::of(&mut *progress, 0.0, 0.9),
    )?
    else {
        return Ok(None);
    };
    let mut table = shading_errors_on(gpu, settings, configs, models, Some(&truth), |m| {
        // Raster images only, and the table is whole or nothing: a stop takes effect at the caller's next step.
        let _ = progress.step(&format!("decomposing under {m}"), 0.95);
    })?;
    truth.reference = std::mem::take(&mut table.reference)
        .into_iter()
        .map(|(m, image)| (m, Stage::exact(image)))
        .collect();
    Ok(Some((truth, table)))
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
