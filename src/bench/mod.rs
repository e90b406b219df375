//! The bench: speed charted against accuracy. It sweeps each method's parameters on one scene, as each method
//! gives them ([`crate::methods::ShadowMethod::sweep`]), measures every configuration with
//! [`crate::measure::measure`], and writes `results.csv`, `results.json` and the chart
//! `speed_vs_accuracy.png`/`.svg` (GPU time against map error, the Pareto front marked).
//!
//! The scaling mode measures a few configurations over the generator's strand density × 0.25..4 and fits GPU
//! time against segment count by least squares: the cost per segment and the fixed cost.
//!
//! GPU time is that of the method's own light passes per frame (the shared light-depth pass every method uses
//! is left out, so the opaque shadow map, which reads only that pass, costs 0 ms).
//!
//! [`sweep`] says what to measure, [`run`](mod@run) measures it, [`result`] holds what came out, [`stats`] the
//! medians, the Pareto front and the fits, [`report`] the files, [`chart`] the charts, [`cli`] `hairlab bench`.

pub mod chart;
pub mod cli;
pub mod report;
pub mod result;
pub mod run;
pub mod stats;
pub mod sweep;

pub use chart::{CHART_SIZE, method_color, scaling_chart, speed_accuracy_chart};
pub use cli::{BenchArgs, run_cli};
pub use report::{
    prepare_out_dir, scaling_csv, scaling_points_csv, to_csv, to_json, write_results, write_scaling,
};
pub use result::{
    ACCURACY_METRIC, BenchResult, BenchRow, ScalingFit, ScalingPoint, ScalingResult, error_metrics,
};
pub use run::{Progress, TerminalProgress, measure_configs, run, run_scaling};
pub use stats::{Spread, fit_line, pareto_front};
pub use sweep::{
    BenchConfig, SCALING_DENSITIES, Tuned, all_scaling_configs, parse_methods, scaling_configs,
    sweep_configs, sweep_methods, tune, tune_analysed,
};
