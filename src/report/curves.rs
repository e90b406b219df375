//! The light map seen from the exact reference: the depth-complexity histogram of the occupied texels
//! (`depth_complexity.csv` in the bench's folder, charted by the bench's chart writer when the page is written)
//! and, per configuration, `V(z)` of its [`WORST_TEXELS`] worst texels against the reference's (`images/k_vz_r.svg`):
//! the samples and the texel error of the bench's map error (`crate::measure`'s texel samples, the method's GPU
//! lookup).

use super::data::{HISTOGRAM_CSV, IMAGES, Table, WORST_TEXELS, vz_file};
use crate::bench::chart::{self, Axis, Chart, Mark, Point, Scale, Series};
use crate::gpu::Gpu;
use crate::measure::{MethodConfig, TexelSamples, evaluate_all};
use crate::render::{FrameInput, Renderer};
use crate::settings::Settings;
use anyhow::Result;
use serde::Serialize;
use std::path::Path;

/// The size of each `V(z)` chart.
const VZ_SIZE: (u32, u32) = (600, 450);
/// Markers on a named line (the chart writer's legend lists named point series).
const MARKERS: usize = 12;

/// A line through `points` and, under `name` in the legend, a dozen of its points as markers (the texel
/// inspector's plots do the same).
pub fn named_line(name: String, color: chart::Color, points: Vec<Point>) -> [Series; 2] {
    Series::named_line(name, color, points, MARKERS)
}
/// The histogram's chart in the report.
pub const HISTOGRAM_SVG: &str = "depth_complexity.svg";

#[derive(Serialize)]
struct HistogramRow {
    depth_complexity: usize,
    texels: usize,
}

/// Writes the histogram and each configuration's worst-texel curves of `settings`' scene (frame 0) into
/// `bench_dir`.
pub fn write(gpu: &Gpu, settings: &Settings, configs: &[MethodConfig], bench_dir: &Path) -> Result<()> {
    let mut s = settings.clone();
    let scene = s.scene.build()?;
    if s.camera.distance <= 0.0 {
        s.camera.frame(&scene.framing_bounds());
    }
    let res = s.render.light_map_side();
    let mut r = Renderer::new(gpu, &scene, res)?;
    let lists = r.reference_lists(&s.camera, &s.light, &s.render)?;
    let max = lists.iter().map(Vec::len).max().unwrap_or(0);
    let mut counts = vec![0usize; max + 1];
    for l in &lists {
        counts[l.len()] += 1;
    }
    let rows = (1..=max).map(|d| HistogramRow {
        depth_complexity: d,
        texels: counts[d],
    });
    crate::io::write_atomic(
        &bench_dir.join(HISTOGRAM_CSV),
        crate::io::csv_text(HISTOGRAM_CSV, rows)?.as_bytes(),
    )?;
    let texels = TexelSamples::of(&lists, res);
    let occupied: Vec<usize> = (0..lists.len()).filter(|&t| !lists[t].is_empty()).collect();
    let technique = crate::render::transparency::registry::reference();
    let dir = bench_dir.join(IMAGES);
    std::fs::create_dir_all(&dir)?;
    for (k, c) in configs.iter().enumerate() {
        let method = crate::methods::registry::find(&c.name).map_err(anyhow::Error::msg)?;
        r.render_light(&FrameInput {
            camera: &s.camera,
            light: &s.light,
            render: &s.render,
            method,
            method_params: &c.params,
            technique,
            technique_params: &s.transparency.params,
            width: 8,
            height: 8,
        })?;
        let v = evaluate_all(&mut r, method, &texels.samples)?;
        let errors = texels.errors(&v);
        let mut worst: Vec<usize> = (0..errors.len()).collect();
        worst.sort_by(|&a, &b| errors[b].total_cmp(&errors[a]));
        for (rank, &i) in worst.iter().take(WORST_TEXELS).enumerate() {
            let t = occupied[i] as u32;
            let span = texels.spans[i].clone();
            let curve = |values: &[f32]| -> Vec<Point> {
                let mut points: Vec<Point> = span
                    .clone()
                    .map(|j| Point {
                        x: f64::from(texels.samples[j][2]),
                        y: f64::from(values[j]),
                        label: String::new(),
                        row: None,
                    })
                    .collect();
                points.sort_by(|a, b| a.x.total_cmp(&b.x));
                points
            };
            let mut series = named_line(c.label(), chart::method_color(&c.name), curve(&v)).to_vec();
            series.extend(named_line(
                crate::methods::registry::reference().name().to_string(),
                [40, 40, 40],
                curve(&texels.reference),
            ));
            let vz = Chart {
                title: format!("{}: texel ({}, {})", c.label(), t % res, t / res),
                notes: vec![format!(
                    "worst texel {} of {WORST_TEXELS}: mean |ΔV| {:.4}",
                    rank + 1,
                    errors[i]
                )],
                x: Axis {
                    label: "light depth z".to_string(),
                    scale: Scale::Linear,
                },
                y: Axis {
                    label: "visibility V(z)".to_string(),
                    scale: Scale::Linear,
                },
                series,
                front: None,
            };
            crate::io::write_atomic(
                &dir.join(vz_file(k, rank)),
                chart::svg(&vz, VZ_SIZE.0, VZ_SIZE.1)?.as_bytes(),
            )?;
        }
    }
    Ok(())
}

/// The histogram of `table` (`depth_complexity.csv`) as the bench's chart model.
pub fn histogram_chart(table: &Table) -> Chart {
    let points = (0..table.rows.len())
        .filter_map(|i| {
            Some(Point {
                x: table.number(i, "depth_complexity")?,
                y: table.number(i, "texels")?,
                label: String::new(),
                row: Some(i),
            })
        })
        .collect();
    Chart {
        title: "Light depth complexity".to_string(),
        notes: vec!["occupied texels of the light map by the number of fragments in them".to_string()],
        x: Axis {
            label: "fragments in the texel (depth complexity)".to_string(),
            scale: Scale::Linear,
        },
        y: Axis {
            label: "texels".to_string(),
            scale: Scale::Linear,
        },
        series: vec![Series {
            name: String::new(),
            color: [60, 90, 160],
            mark: Mark::Line,
            points,
        }],
        front: None,
    }
}

/// The histogram chart's SVG.
pub fn histogram_svg(table: &Table) -> Result<String> {
    let (w, h) = chart::CHART_SIZE;
    chart::svg(&histogram_chart(table), w, h)
}
