//! `hairlab bench motion`: each configuration measured over a preset's motion (the rows of `measure motion`,
//! [`crate::measure::motion`]) and charted as its GPU time against a temporal metric — flicker, its p99, the
//! pop rate or the image flicker (docs/design.md, "Temporal metrics") — with the Pareto front of the
//! configurations no other beats on both. Writes `motion_summary.csv`, `motion_frames.csv` and
//! `motion_speed_vs_<metric>.png/.svg`.

use super::chart::{Axis, Chart, Front, Mark, Point, Scale, Series, method_color};
use super::report::{chart_files, write_files};
use super::stats::pareto_front;
use crate::gpu::{AdapterPreference, Gpu};
use crate::measure::motion::{MotionConfig, MotionMeasurement, MotionRow, measure_motion_on, usual_configs};
use crate::progress::Outcome;
use crate::settings::Settings;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// The temporal metric a motion bench charts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TemporalMetric {
    /// Mean `|ΔV_method − ΔV_reference|` between consecutive frames at the tracked points.
    Flicker,
    /// Its 99th percentile.
    FlickerP99,
    /// Share of tracked points per frame pair whose change is off by more than 0.1.
    PopRate,
    /// RMSE of the image's frame-to-frame change against the reference's.
    ImageFlicker,
}

impl TemporalMetric {
    /// The metric's column in `motion_summary.csv`.
    pub fn column(self) -> &'static str {
        match self {
            TemporalMetric::Flicker => "flicker",
            TemporalMetric::FlickerP99 => "flicker_p99",
            TemporalMetric::PopRate => "pop_rate",
            TemporalMetric::ImageFlicker => "image_flicker",
        }
    }

    pub fn value(self, r: &MotionRow) -> f64 {
        match self {
            TemporalMetric::Flicker => r.flicker.mean,
            TemporalMetric::FlickerP99 => r.flicker.p99,
            TemporalMetric::PopRate => r.flicker.pop_rate,
            TemporalMetric::ImageFlicker => r.image_flicker,
        }
    }

    fn axis(self) -> &'static str {
        match self {
            TemporalMetric::Flicker => "flicker: mean |ΔV − ΔV_ref| between frames (lower is better)",
            TemporalMetric::FlickerP99 => "flicker p99: |ΔV − ΔV_ref| between frames (lower is better)",
            TemporalMetric::PopRate => {
                "pop rate: share of points per frame pair with a pop > 0.1 (lower is better)"
            }
            TemporalMetric::ImageFlicker => {
                "image flicker: RMSE of ΔI against the reference's (lower is better)"
            }
        }
    }
}

/// The motion, its overrides, the configurations and the frames: what `measure motion` and `bench motion` run.
#[derive(clap::Args, Debug, Clone)]
pub struct MotionRun {
    /// Preset with a `[motion]`: built-in name (`wind`, `head-turn`, `stray-sweep`, `straight-motion`),
    /// `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "wind")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Method configurations `name` or `name:key=value,...` (repeatable); the key a method's analysis chooses
    /// may be `auto` (chosen on frame 0 and kept) or `auto-per-frame` (chosen again every frame), e.g.
    /// `bom:layers=4,split_ratio=auto-per-frame`. Default: the usual settings of every registered method.
    #[arg(long = "config", value_name = "METHOD[:K=V,...]")]
    pub configs: Vec<String>,
    /// Frames of the motion played, 0..N (at least 2).
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
}

impl MotionRun {
    /// The preset's settings with the overrides, and the configurations (the usual ones when none is given).
    pub fn resolve(&self) -> Result<(Settings, Vec<MotionConfig>)> {
        let settings = Settings::load_preset(&self.preset, &self.set)?;
        let configs = if self.configs.is_empty() {
            usual_configs()
        } else {
            self.configs
                .iter()
                .map(|c| MotionConfig::parse(c))
                .collect::<Result<_>>()?
        };
        Ok((settings, configs))
    }
}

/// `hairlab bench motion`'s arguments.
#[derive(clap::Args, Debug, Clone)]
pub struct MotionBenchArgs {
    #[command(flatten)]
    pub run: MotionRun,
    /// The temporal metric charted against GPU time (every metric is in the CSV files whichever is chosen).
    #[arg(long, value_enum, default_value_t = TemporalMetric::Flicker)]
    pub metric: TemporalMetric,
    /// Output folder (created).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// GPU time against `metric`, one colour per method, the Pareto front connected.
pub fn motion_chart(m: &MotionMeasurement, preset: &str, metric: TemporalMetric) -> Chart {
    let point = |i: usize| {
        let r = &m.rows[i];
        Point {
            x: r.gpu_ms,
            y: metric.value(r),
            label: r.config.label(),
            row: Some(i),
        }
    };
    let mut series: Vec<Series> = Vec::new();
    for (i, r) in m.rows.iter().enumerate() {
        let name = &r.config.config.name;
        match series.iter_mut().find(|s| &s.name == name) {
            Some(s) => s.points.push(point(i)),
            None => series.push(Series {
                name: name.clone(),
                color: method_color(name),
                mark: Mark::Points,
                points: vec![point(i)],
            }),
        }
    }
    let coords: Vec<[f64; 2]> = m.rows.iter().map(|r| [r.gpu_ms, metric.value(r)]).collect();
    let front = Front {
        name: "Pareto front".to_string(),
        points: pareto_front(&coords).into_iter().map(point).collect(),
    };
    Chart {
        title: format!("Speed vs {} over a motion", metric.column()),
        notes: vec![
            format!(
                "preset {preset}: {} strands, {} segments, frames 0..{}",
                m.strands, m.segments, m.frames
            ),
            m.device.clone(),
        ],
        x: Axis {
            label: "GPU ms per frame, method's own light passes (log scale, median over the frames)"
                .to_string(),
            scale: Scale::Log,
        },
        y: Axis {
            label: metric.axis().to_string(),
            scale: Scale::Linear,
        },
        series,
        front: (!front.points.is_empty()).then_some(front),
    }
}

/// Writes the motion's CSV files ([`MotionMeasurement::csv_files`]) and the chart into `dir` (created), each file
/// whole; returns their paths.
pub fn write_motion_bench(
    dir: &Path,
    m: &MotionMeasurement,
    preset: &str,
    metric: TemporalMetric,
) -> Result<Vec<PathBuf>> {
    let mut files = m.csv_files()?;
    files.extend(chart_files(
        &format!("motion_speed_vs_{}", metric.column()),
        &motion_chart(m, preset, metric),
    )?);
    write_files(dir, files)
}

/// `hairlab bench motion`: measures, prints the table and the front, writes the files; `progress` hears what is
/// measured. Stopped, the files hold the configurations kept: the outcome holds how many.
pub fn run(a: &MotionBenchArgs, progress: &mut dyn crate::progress::Progress) -> Result<Outcome<usize>> {
    let (settings, configs) = a.run.resolve()?;
    let gpu = Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Hardware))?;
    let m = measure_motion_on(&gpu, &settings, &configs, a.run.frames, progress)?;
    print!("{}", m.table(&a.run.preset));
    let coords: Vec<[f64; 2]> = m.rows.iter().map(|r| [r.gpu_ms, a.metric.value(r)]).collect();
    let front: Vec<String> = pareto_front(&coords)
        .into_iter()
        .map(|i| m.rows[i].config.label())
        .collect();
    println!(
        "Pareto front of GPU ms against {} (fastest first): {}",
        a.metric.column(),
        front.join(" -> ")
    );
    for path in write_motion_bench(&a.out, &m, &a.run.preset, a.metric)? {
        println!("wrote {}", path.display());
    }
    Ok(m.map(|m| m.rows.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::MethodConfig;
    use crate::measure::temporal::{Flicker, OverFrames};
    use crate::methods::LightMethod;
    use crate::methods::{dom::Dom, occupancy::Occupancy, osm::Osm};

    fn row(name: &str, gpu_ms: f64, flicker: f64, pop_rate: f64) -> MotionRow {
        MotionRow {
            config: MotionConfig::fixed(MethodConfig::new(name, Default::default())),
            map_error: OverFrames::default(),
            shading_error: OverFrames::default(),
            flicker: Flicker {
                points: 10,
                mean: flicker,
                p99: flicker * 2.0,
                pop_rate,
                max_pop: 0.5,
            },
            image_flicker: 0.01,
            gpu_ms,
            image_flip: 0.0,
            frames: Vec::new(),
            followed: Vec::new(),
        }
    }

    #[test]
    fn the_chart_puts_gpu_time_against_the_metric_and_fronts_the_undominated() {
        let m = MotionMeasurement {
            device: "test device".to_string(),
            strands: 10,
            segments: 90,
            frames: 3,
            // (1 ms, 0.3), (2 ms, 0.1), (3 ms, 0.2): the third is beaten by the second on both.
            rows: vec![
                row(Osm.name(), 1.0, 0.3, 0.02),
                row(Dom.name(), 2.0, 0.1, 0.05),
                row(Occupancy.name(), 3.0, 0.2, 0.01),
            ],
            sim: None,
            followed: None,
        };
        let c = motion_chart(&m, "wind", TemporalMetric::Flicker);
        let front: Vec<(f64, f64)> = c
            .front
            .as_ref()
            .unwrap()
            .points
            .iter()
            .map(|p| (p.x, p.y))
            .collect();
        assert_eq!(front, [(1.0, 0.3), (2.0, 0.1)]);
        assert_eq!(c.series.len(), 3);
        assert!(c.y.label.starts_with("flicker"));
        // Against the pop rate (0.02, 0.05, 0.01) nothing beats the first or the third.
        let c = motion_chart(&m, "wind", TemporalMetric::PopRate);
        let front: Vec<f64> = c.front.as_ref().unwrap().points.iter().map(|p| p.x).collect();
        assert_eq!(front, [1.0, 3.0]);
        assert_eq!(TemporalMetric::FlickerP99.value(&m.rows[1]), 0.2);
    }
}
