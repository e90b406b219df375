//! The bench: speed charted against accuracy. It sweeps each method's parameters on one scene, as each method
//! gives them ([`crate::methods::ShadowMethod::sweep`]), measures every configuration with
//! [`crate::measure::measure`], and writes `results.csv`, `results.json` and the chart
//! `speed_vs_accuracy.png`/`.svg` (GPU time against an accuracy metric, map error unless `--metric` says
//! otherwise, the Pareto front marked).
//!
//! The scaling mode times a few configurations (light passes only) at strand densities evenly spaced in segment
//! count up to a million segments (`--max-segments`, `--points`), each point the median of at least three timed
//! frames after discarded warm-up frames, and fits GPU time against segment count by least squares
//! (`t = a + b·n`): the cost per segment, the fixed cost, R², and the log-log exponent that says how a cost that
//! is not linear grows.
//!
//! GPU time is that of the method's own light passes per frame (the shared light-depth pass every method uses
//! is left out, so the opaque shadow map, which reads only that pass, costs 0 ms).
//!
//! [`sweep`] says what to measure, [`run`](mod@run) measures it, [`result`] holds what came out, [`stats`] the
//! medians, the Pareto front and the fits, [`report`] the files, [`chart`] the charts, [`cli`] `hairlab bench`.

pub mod chart;
pub mod fur;
pub mod motion;
pub mod report;
pub mod result;
pub mod run;
pub mod stats;
pub mod sweep;
pub mod transparency;
pub mod truth_chart;

pub use chart::{CHART_SIZE, method_color, scaling_chart, speed_accuracy_chart};
pub use report::{
    prepare_out_dir, scaling_csv, scaling_passes_csv, scaling_points_csv, to_csv, to_json, write_results,
    write_scaling, write_scaling_tables, write_tables,
};
pub use result::{
    BenchResult, BenchRow, DEFAULT_ACCURACY_METRIC, METRICS, Metric, ScalingFit, ScalingPoint,
    ScalingRefusal, ScalingResult, accuracy_metrics, error_metrics, frame_totals, metric_axis, parse_metric,
};
pub use run::{
    BenchOutcome, Finished, ScalingPlan, measure_configs, measure_configs_each, run, run_each, run_scaling,
    scaling_densities,
};
pub use stats::{Spread, fit_line, growth_exponent, pareto_front};
pub use sweep::{
    BenchConfig, DEFAULT_SCALING_POINTS, DEFAULT_SCALING_SEGMENTS, DEFAULT_SCALING_WARMUP,
    MIN_SCALING_FRAMES, Tuned, all_scaling_configs, parse_methods, scaling_configs, sweep_configs,
    sweep_methods, tune, tune_analysed,
};
