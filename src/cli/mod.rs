//! The headless command line, one file per subcommand. With no subcommand, `hairlab` opens the workbench window. Every failure is one line naming the file and the problem,
//! and a non-zero exit; outputs are written whole.

pub mod adapters;
pub mod bench;
pub mod compare;
pub mod composite;
pub mod convert;
pub mod curve;
pub mod export;
pub mod generate;
pub mod info;
pub mod interrupt;
pub mod manual;
pub mod measure;
pub mod measure_fibres;
pub mod measure_motion;
pub mod measure_probe;
mod measure_shading;
pub mod measure_visibility;
pub mod progress;
pub mod render;
pub mod report;
pub mod simulate;
pub mod soak;

use anyhow::Result;
use clap::{Parser, Subcommand};
use compare::CompareArgs;
use composite::CompositeArgs;
pub use composite::parse_pixel_csv;
use convert::ConvertArgs;
use curve::CurveArgs;
pub use curve::{parse_fragments_csv, read_fragments_csv};
use export::ExportArgs;
use generate::GenArgs;
use info::InfoArgs;
use manual::{CompletionsArgs, ManArgs};
use measure::MeasureArgs;
use render::RenderArgs;
pub use render::render_image;
use simulate::SimulateArgs;
pub use simulate::frame_file_name;
use soak::SoakArgs;

#[derive(Parser, Debug)]
#[command(
    name = "hairlab",
    version,
    about = "A workbench for real-time hair self-shadowing methods."
)]
// Help wraps at the terminal's width and at most 79 columns, so every page stays under 80 columns in a terminal
// and when piped to a file.
#[command(max_term_width = 79, after_help = ENVIRONMENT)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The GPU adapter: `software`, `hardware`, or a part of its name, any case (`hairlab adapters` lists them);
    /// wins over HAIRLAB_ADAPTER.
    #[arg(long, global = true, value_name = "NAME")]
    pub adapter: Option<String>,
    /// Preset for the window (built-in name, `presets/<name>.toml`, or a path); default: the last session's.
    #[arg(long, global = false)]
    pub preset: Option<String>,
    /// Read the WGSL shaders from DIR over the embedded ones (a file DIR lacks is the embedded one); every shader
    /// is validated first and an error names its file, line and column. The window reloads DIR on change.
    #[arg(long, global = true, value_name = "DIR", env = "HAIRLAB_SHADERS")]
    pub shaders: Option<std::path::PathBuf>,
    /// Override a preset value for the window, e.g. `--set render.hair_alpha=0.2` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// What `hairlab --help` says after the options: the window, and the environment variables hairlab reads.
pub const ENVIRONMENT: &str = "With no subcommand, hairlab opens the workbench window.

Environment:
  HAIRLAB_ADAPTER=NAME   the GPU adapter, as --adapter (which wins)
  HAIRLAB_SHADERS=DIR    the shaders folder, as --shaders (which wins)
  WGPU_BACKEND=LIST      the wgpu backends searched for adapters, e.g. vulkan
                         or vulkan,gl (default: Vulkan, Metal, DX12)
  RUST_LOG=FILTER        log verbosity (env_logger; default: info)
Tests only (cargo test):
  HAIRLAB_SKIP_GPU_TESTS=1     skip the GPU tests when no adapter exists
  HAIRLAB_UPDATE_SNAPSHOTS=1   rewrite the image snapshots
  HAIRLAB_FUZZ_CASES=N, HAIRLAB_FUZZ_SEED=N   the file-format fuzzing run";

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a preset headlessly to a PNG: the same image the window shows.
    Render(RenderArgs),
    /// Print what a `.hair` / glTF / `.tfx` / `.data` / USD (`.usda`, `.usdc`, `.usdz`) file holds: strands, points, segments, bounds, arrays, and
    /// what hairlab drops of it.
    Info(InfoArgs),
    /// Generate procedural hair and write it as a `.hair` file.
    Gen(GenArgs),
    /// Convert strands between formats: any file `info` reads in, `.hair`, TressFX `.tfx`, USC-HairSalon `.data`
    /// or `.usda` out (written whole or not at all; a time-sampled stage keeps its frames in `.usda`); prints
    /// what the output cannot hold.
    Convert(ConvertArgs),
    /// Write a preset's still scene for another renderer: `--format mitsuba` gives a Mitsuba 3 scene (XML, the
    /// strands as a linearcurve file, meshes as OBJ) of the path tracer's camera, light and fibre BSDF.
    Export(ExportArgs),
    /// Evaluate a method's CPU model on one texel's fragments (CSV rows `depth,alpha`, depth in [0,1]) and
    /// print CSV `depth,reference,<method>`: the papers' texel experiments, in a script.
    Curve(CurveArgs),
    /// Composite one pixel's eye fragments (CSV rows `depth,r,g,b,alpha`, linear colour) through a transparency
    /// technique's CPU model and print the linear RGB result `r,g,b`: the eye-space twin of `curve`.
    Composite(CompositeArgs),
    /// Print every image metric of B.png against the reference A.png: RMSE, PSNR, SSIM, the error distribution,
    /// contrast and FLIP, over all pixels and over a hair mask; `--flip-map` writes FLIP's heat map.
    Compare(CompareArgs),
    /// Measure methods against the exact reference on a preset's scene: depth complexity, map error, GPU time
    /// per pass (median), memory, geometry passes.
    Measure(MeasureArgs),
    /// Sweep every method's parameters on a preset's scene and chart GPU time against map error: results.csv,
    /// results.json and speed_vs_accuracy.png/.svg (Pareto front marked); `--scaling` fits GPU time per segment.
    Bench(bench::BenchArgs),
    /// One self-contained HTML page of a study (index.html and its files): the scene, the machine, speed
    /// against accuracy with the whole sortable table, transparency, motion and the papers' claims, each where
    /// its data exists; a fresh study, or `--from` folders earlier `bench` and `measure motion` runs wrote.
    Report(report::ReportArgs),
    /// Render many frames while the light turns and the method changes, and check that neither the process's
    /// resident memory nor the GPU memory grows (last cycle of methods against the first, at most 5 %).
    Soak(SoakArgs),
    /// Run a preset's motion (`[motion]`) and bake it to a folder of `.hair` files, `frame_0000.hair` …,
    /// that plays back with `--set motion.source=sequence --set motion.path=DIR`; prints the simulation's
    /// invariants and cost.
    Simulate(SimulateArgs),
    /// List the GPU adapters wgpu finds and mark the one hairlab uses (see --adapter).
    Adapters,
    /// Print shell completions for bash, zsh, fish, elvish or PowerShell.
    Completions(CompletionsArgs),
    /// Print the man page, or write every subcommand's page into a folder.
    Man(ManArgs),
}

/// Runs a subcommand.
pub fn run(cmd: Command) -> Result<()> {
    match cmd {
        Command::Render(a) => render::render(&a),
        Command::Info(a) => info::run(&a),
        Command::Gen(a) => generate::gen_hair(&a),
        Command::Convert(a) => convert::convert(&a),
        Command::Export(a) => export::export(&a),
        Command::Curve(a) => curve::curve(&a),
        Command::Composite(a) => composite::composite(&a),
        Command::Compare(a) => compare::compare_images(&a),
        Command::Measure(a) => measure::measure(&a),
        Command::Bench(a) => bench::run_cli(&a),
        Command::Report(a) => report::report(&a),
        Command::Soak(a) => soak::soak(&a),
        Command::Simulate(a) => simulate::simulate(&a),
        Command::Adapters => adapters::adapters(),
        Command::Completions(a) => manual::completions(&a),
        Command::Man(a) => manual::man(&a),
    }
}
