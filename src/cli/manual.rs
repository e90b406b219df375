//! `hairlab completions SHELL` and `hairlab man`: shell completions (clap_complete) and man pages
//! (clap_mangen), generated from the same command definition as `--help`.

use anyhow::Result;
use clap::{Args, CommandFactory};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell to complete for; e.g. `hairlab completions bash > /etc/bash_completion.d/hairlab`.
    pub shell: clap_complete::Shell,
}

#[derive(Args, Debug)]
pub struct ManArgs {
    /// Folder (existing) to write `hairlab.1` and one `hairlab-<subcommand>.1` per subcommand into; default: print
    /// `hairlab.1` on stdout (`hairlab man | man -l -`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub(super) fn completions(a: &CompletionsArgs) -> Result<()> {
    let mut cmd = super::Cli::command();
    clap_complete::generate(a.shell, &mut cmd, "hairlab", &mut std::io::stdout());
    Ok(())
}

/// The roff text of one page, titled `title`.
fn page(cmd: clap::Command, title: &str) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    clap_mangen::Man::new(cmd).title(title).render(&mut out)?;
    Ok(out)
}

pub(super) fn man(a: &ManArgs) -> Result<()> {
    let mut cmd = super::Cli::command();
    cmd.build();
    let Some(dir) = &a.out else {
        use std::io::Write;
        std::io::stdout().write_all(&page(cmd, "hairlab")?)?;
        return Ok(());
    };
    if !dir.is_dir() {
        anyhow::bail!("{}: not an existing folder", dir.display());
    }
    let mut pages = vec![("hairlab.1".to_string(), page(cmd.clone(), "hairlab")?)];
    for sub in cmd.get_subcommands() {
        let name = format!("hairlab-{}", sub.get_name());
        pages.push((format!("{name}.1"), page(sub.clone(), &name)?));
    }
    for (file, bytes) in pages {
        let path = dir.join(file);
        crate::io::write_atomic(&path, &bytes)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
