//! `hairlab report`: the arguments, the study (fresh, or `--from` earlier folders) and the page
//! ([`crate::report`]). Ctrl-C during a fresh study stops after the configuration in progress and writes the
//! page of what finished (exit code 130); any failure writes nothing.

use crate::report::data::Study;
use crate::report::run::Plan;
use crate::report::{Draft, Meta};
use crate::settings::Settings;
use anyhow::{Result, bail};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:
  hairlab report --preset stray-strand --out r/
  hairlab report --preset stray-sweep --config dom:layers=3 --config occupancy --motion --out r/
  hairlab report --from bench-out/ --from motion-out/ --out r/")]
pub struct ReportArgs {
    /// Preset of a fresh study: built-in name, `presets/<name>.toml`, or a path.
    #[arg(long, default_value = "default", conflicts_with = "from")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.map_resolution=256` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", conflicts_with = "from")]
    pub set: Vec<String>,
    /// Shadow method configuration `name` or `name:key=value,...` (repeatable); default: every method's sweep
    /// (and the usual motion configurations).
    #[arg(long = "config", value_name = "METHOD[:K=V,...]", conflicts_with = "from")]
    pub configs: Vec<String>,
    /// Eye transparency technique configuration (repeatable); default: every technique's sweep.
    #[arg(
        long = "technique",
        value_name = "TECHNIQUE[:K=V,...]",
        conflicts_with = "from"
    )]
    pub techniques: Vec<String>,
    /// Measure the preset's motion too (a preset with a `[motion]`).
    #[arg(long, conflicts_with = "from")]
    pub motion: bool,
    /// Timed frames per configuration.
    #[arg(long, default_value_t = 5, conflicts_with = "from")]
    pub frames: u32,
    /// `path-traced` adds the path-traced truth and each configuration's error decomposition under each shading
    /// model (as `measure shadows --truth path-traced`, `render.spp` samples per pixel).
    #[arg(long, value_enum, default_value = "depth-peeled", conflicts_with = "from")]
    pub truth: super::measure::TruthKind,
    /// Read a folder an earlier `hairlab bench shadows`, `bench transparency` or `measure motion` wrote
    /// (repeatable), measuring nothing again.
    #[arg(long, value_name = "DIR")]
    pub from: Vec<PathBuf>,
    /// The report's folder: index.html and its files (replaced whole when it holds an earlier report).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// `words` as one POSIX shell command line: each word as it is where it holds only characters a shell leaves
/// alone, else in single quotes (a `'` inside written `'\''`), so `sh -c` gives back the same words.
pub fn shell_command<S: AsRef<str>>(words: impl IntoIterator<Item = S>) -> String {
    let quote = |a: &str| {
        if !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_=.,:/@+".contains(c))
        {
            a.to_string()
        } else {
            format!("'{}'", a.replace('\'', "'\\''"))
        }
    };
    words
        .into_iter()
        .map(|w| quote(w.as_ref()))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The command line as typed (the program by its file name), quoted by [`shell_command`].
fn command_line() -> String {
    let mut args = std::env::args();
    let first = args.next().map_or("hairlab".to_string(), |p| {
        std::path::Path::new(&p)
            .file_name()
            .map_or(p.clone(), |n| n.to_string_lossy().into_owned())
    });
    shell_command(std::iter::once(first).chain(args))
}

/// `hairlab report`.
pub fn report(a: &ReportArgs) -> Result<()> {
    if !(1..=1000).contains(&a.frames) {
        bail!("--frames must be in 1..=1000 (got {})", a.frames);
    }
    if a.from.is_empty() {
        let settings = Settings::load_preset(&a.preset, &a.set)?;
        let plan = Plan {
            preset: a.preset.clone(),
            configs: a.configs.clone(),
            techniques: a.techniques.clone(),
            motion: a.motion,
            frames: a.frames,
            truth: a.truth == super::measure::TruthKind::PathTraced,
        };
        // Ctrl-C answers the bar's next step with a stop.
        let mut bar = super::progress::TerminalProgress::new();
        let written = crate::report::fresh(&a.out, &plan, &settings, command_line(), &[], &mut bar)?;
        drop(bar);
        let (page, configurations) = &*written;
        println!("wrote {}", page.display());
        return super::interrupt::finish(&written, *configurations);
    }
    let draft = Draft::new(&a.out)?;
    let study = Study::read(&a.from)?;
    let meta = Meta {
        version: env!("CARGO_PKG_VERSION"),
        command: command_line(),
        ..Meta::default()
    };
    println!("wrote {}", draft.finish(&study, &meta)?.display());
    Ok(())
}
