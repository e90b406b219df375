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
    if let Some(adapter) = &cli.adapter {
        hairlab::gpu::set_adapter_choice(adapter);
    }
    if cli.command.is_some()
        && std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
        && let Some(code) = rerun_without_device_select()
    {
        return code;
    }
    if cli.command.is_some()
        && let Some(dir) = &cli.shaders
        && let Err(e) = hairlab::live_shaders::load(dir)
    {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Some(cmd) => run(cmd),
        None => open_window(cli.preset, &cli.set, cli.shaders),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if hairlab::cli::interrupt::is_interrupted(&e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(hairlab::cli::interrupt::EXIT_CODE)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn open_window(
    preset: Option<String>,
    overrides: &[String],
    shaders: Option<std::path::PathBuf>,
) -> anyhow::Result<()> {
    let settings = match preset {
        Some(p) => Some(Settings::load_preset(&p, overrides)?),
        None if !overrides.is_empty() => Some(Settings::load_preset("default", overrides)?),
        None => None,
    };
    eframe::run_native(
        "hairlab",
        hairlab::app::native_options(),
        Box::new(move |cc| {
            let mut app = hairlab::app::HairlabApp::new(cc, settings);
            if let Some(dir) = &shaders {
                app.watch_shaders(dir);
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the window: {e}"))
}

/// Headless, with no session: Mesa's Vulkan device-select layer would try a Wayland display only to have libwayland
/// print "XDG_RUNTIME_DIR is invalid or not set" (twice) on every GPU run. Choosing the GPU that drives a display
/// means nothing without one, so the command runs again with the layer switched off (`NODEVICE_SELECT=1`; the
/// environment cannot be changed safely inside a running process). Returns its exit code, or `None` when it could
/// not be started (the command then runs here, noise and all). A SIGINT sent to this process alone is passed on
/// to the command (Ctrl-C on a terminal reaches both), which stops cleanly (`hairlab::cli::interrupt`).
fn rerun_without_device_select() -> Option<ExitCode> {
    let exe = std::env::current_exe().ok()?;
    let mut child = std::process::Command::new(exe)
        .args(std::env::args_os().skip(1))
        .env("NODEVICE_SELECT", "1")
        .spawn()
        .ok()?;
    let pid = child.id().to_string();
    let forward = move || {
        let _ = std::process::Command::new("kill").args(["-INT", &pid]).status();
    };
    if let Err(e) = ctrlc::set_handler(forward) {
        log::warn!("Ctrl-C will not reach the command: {e}");
    }
    let status = child.wait().ok()?;
    Some(match status.code() {
        Some(0) => ExitCode::SUCCESS,
        Some(c) => ExitCode::from(u8::try_from(c).unwrap_or(1)),
        None => ExitCode::FAILURE,
    })
}
