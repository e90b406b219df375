//! `hairlab`: the workbench window, or a headless subcommand (`render`, `info`, `gen`).

use clap::Parser;
use hairlab::cli::{Cli, run};
use hairlab::settings::Settings;
use std::process::ExitCode;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .filter_module("wgpu_core", log::LevelFilter::Warn)
        .filter_module("wgpu_hal", log::LevelFilter::Warn)
        .filter_module("naga", log::LevelFilter::Warn)
        .filter_module("egui_wgpu", log::LevelFilter::Warn)
        .filter_module("eframe", log::LevelFilter::Warn)
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(cmd) => run(cmd),
        None => open_window(cli.preset, &cli.set),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn open_window(preset: Option<String>, overrides: &[String]) -> anyhow::Result<()> {
    let settings = match preset {
        Some(p) => Some(Settings::load_preset(&p, overrides)?),
        None if !overrides.is_empty() => Some(Settings::load_preset("default", overrides)?),
        None => None,
    };
    eframe::run_native(
        "hairlab",
        hairlab::app::native_options(),
        Box::new(move |cc| Ok(Box::new(hairlab::app::HairlabApp::new(cc, settings)))),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the window: {e}"))
}
