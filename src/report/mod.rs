//! `hairlab report`: one self-contained HTML page of a study. The page is written from the folders `hairlab
//! bench shadows`, `bench transparency` and `measure motion` write ([`data`]): a fresh report runs those into
//! its own folder first ([`run`]), `--from` reads folders an earlier run wrote, and both go through the same
//! reader, so the two give the same tables. Each section ([`sections`], [`claims`]) appears only where its data
//! exists; the table cells are the CSV text; the charts are the bench's chart writer's SVG. A fresh study also
//! renders what only it can, into the same folders: each configuration's image, difference and FLIP maps
//! ([`images`], the transparency Fig. 2 grid too), the worst texels' `V(z)` and the depth-complexity histogram
//! ([`curves`]), and the motion as looping GIFs ([`animations`]); [`page`] is the frame every section shares.
//! The window's **Export report…** runs [`fresh`] as a job (`crate::app`).
//!
//! The page is built in a temporary folder beside the output ([`Draft`]) and renamed into place whole, so a
//! failure leaves nothing half-written; every image and file the page names is inside the folder, and the page
//! fetches nothing (no `http`, no `https`), so it opens from `file://`.

pub mod animations;
pub mod claims;
pub mod curves;
pub mod data;
pub mod images;
pub mod page;
pub mod run;
pub mod sections;

use crate::progress::Outcome;
use anyhow::{Context, Result, bail};
use data::Study;
use std::path::{Path, PathBuf};

/// The adapter a fresh study measured on.
#[derive(Clone, Debug, PartialEq)]
pub struct AdapterFacts {
    pub name: String,
    pub driver: String,
    pub backend: String,
}

impl AdapterFacts {
    pub fn of(info: &wgpu::AdapterInfo) -> AdapterFacts {
        let driver = [info.driver.as_str(), info.driver_info.as_str()]
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join(" ");
        AdapterFacts {
            name: crate::gpu::describe(info),
            driver: if driver.is_empty() {
                "not reported".to_string()
            } else {
                driver
            },
            backend: format!("{:?}", info.backend),
        }
    }
}

/// What the page says beside the tables: how it was made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Meta {
    /// The exact command line that reproduces the page.
    pub command: String,
    pub version: &'static str,
    pub preset: Option<String>,
    pub light: Option<String>,
    pub adapter: Option<AdapterFacts>,
    /// The scene's thumbnail, relative to the page.
    pub thumbnail: Option<String>,
}

/// The files of each part that are copied into the report, where present.
const SHADOWS_FILES: &[&str] = &[
    "results.csv",
    "results.json",
    "speed_vs_accuracy.svg",
    "speed_vs_accuracy.png",
    data::HISTOGRAM_CSV,
    data::DECOMPOSITION_CSV,
    data::TRUTH_PNG,
    data::TRUTH_CHART_FILES[0],
    data::TRUTH_CHART_FILES[1],
];
const TRANSPARENCY_FILES: &[&str] = &[
    "transparency.csv",
    "transparency.json",
    "transparency_speed_vs_accuracy.svg",
    "transparency_speed_vs_accuracy.png",
];
const MOTION_FILES: &[&str] = &["motion_summary.csv", "motion_frames.csv", "motion_point.csv"];

/// A report being built: a temporary folder beside the output, renamed to it by [`Draft::finish`] and deleted
/// if dropped before.
pub struct Draft {
    tmp: tempfile::TempDir,
    out: PathBuf,
}

impl Draft {
    /// Checks that `out` can take a report (absent, an empty folder, or an earlier report) and makes the
    /// temporary folder beside it.
    pub fn new(out: &Path) -> Result<Draft> {
        if out.exists() {
            let is_report = out.join("index.html").is_file();
            let empty = out.is_dir()
                && std::fs::read_dir(out)
                    .with_context(|| format!("{}: cannot read", out.display()))?
                    .next()
                    .is_none();
            if !is_report && !empty {
                bail!(
                    "{}: exists and is not an earlier report (no index.html); choose a new folder",
                    out.display()
                );
            }
        }
        let parent = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent)
            .with_context(|| format!("{}: cannot create the folder", parent.display()))?;
        let tmp = tempfile::Builder::new()
            .prefix(".hairlab-report-")
            .tempdir_in(&parent)
            .with_context(|| format!("{}: cannot create a folder in it", parent.display()))?;
        Ok(Draft {
            tmp,
            out: out.to_path_buf(),
        })
    }

    /// The temporary folder (a fresh run writes its data under it).
    pub fn path(&self) -> &Path {
        self.tmp.path()
    }

    /// Copies each part's files into the draft (unless they are there already), writes the page and the
    /// motion chart, and renames the draft to the output folder (an earlier report there is replaced).
    pub fn finish(self, study: &Study, meta: &Meta) -> Result<PathBuf> {
        let root = self.tmp.path();
        if let Some(s) = &study.shadows {
            let dir = root.join(sections::SHADOWS_DIR);
            copy_part(&s.dir, &dir, SHADOWS_FILES)?;
            let pictures = images::files(s);
            let names: Vec<&str> = pictures.iter().map(String::as_str).collect();
            copy_part(&s.dir.join(data::IMAGES), &dir.join(data::IMAGES), &names)?;
            if let Some(t) = &s.depth_complexity {
                crate::io::write_atomic(
                    &dir.join(curves::HISTOGRAM_SVG),
                    curves::histogram_svg(t)?.as_bytes(),
                )?;
            }
        }
        if let Some(t) = &study.transparency {
            let dir = root.join(sections::TRANSPARENCY_DIR);
            copy_part(&t.dir, &dir, TRANSPARENCY_FILES)?;
            let pictures = images::technique_files(t);
            let names: Vec<&str> = pictures.iter().map(String::as_str).collect();
            copy_part(&t.dir.join(data::IMAGES), &dir.join(data::IMAGES), &names)?;
        }
        if let Some(m) = &study.motion {
            let dir = root.join(sections::MOTION_DIR);
            copy_part(&m.dir, &dir, MOTION_FILES)?;
            let gifs = animations::files(m);
            let names: Vec<&str> = gifs.iter().map(String::as_str).collect();
            copy_part(&m.dir.join(data::ANIMATIONS), &dir.join(data::ANIMATIONS), &names)?;
            crate::io::write_atomic(
                &dir.join(sections::MOTION_CHART),
                sections::motion_chart_svg(m)?.as_bytes(),
            )?;
        }
        crate::io::write_atomic(&root.join("index.html"), html(study, meta).as_bytes())?;
        let tmp = self.tmp.keep();
        let old = if self.out.exists() {
            let aside = tmp.with_extension("old");
            std::fs::rename(&self.out, &aside)
                .with_context(|| format!("{}: cannot move the earlier report aside", self.out.display()))?;
            Some(aside)
        } else {
            None
        };
        if let Err(e) = std::fs::rename(&tmp, &self.out) {
            if let Some(aside) = &old {
                let _ = std::fs::rename(aside, &self.out);
            }
            let _ = std::fs::remove_dir_all(&tmp);
            return Err(e).with_context(|| format!("{}: cannot write the report", self.out.display()));
        }
        if let Some(aside) = old {
            std::fs::remove_dir_all(&aside)
                .with_context(|| format!("{}: cannot remove the earlier report", aside.display()))?;
        }
        Ok(self.out.join("index.html"))
    }
}

/// A fresh study run into a report's draft, its page not yet written: dropped, it leaves nothing behind (an
/// earlier report at the output stays).
pub struct FreshStudy {
    draft: Draft,
    study: Study,
    meta: Meta,
}

impl FreshStudy {
    /// The configurations the study holds.
    pub fn configurations(&self) -> usize {
        self.study.configurations()
    }

    /// Writes the page (with `command`, the command line that made it) and moves the report into place: the
    /// page's path.
    pub fn finish(self, command: String) -> Result<PathBuf> {
        let meta = Meta { command, ..self.meta };
        self.draft.finish(&self.study, &meta)
    }
}

/// A fresh study of `settings` (`plan`) run into a draft of the report at `out`, with `extra` files (name, bytes)
/// beside the page: [`Outcome::Stopped`] with what finished when `progress` stopped it. It fails (nothing
/// written) when it was stopped before any configuration finished.
pub fn study_fresh(
    out: &Path,
    plan: &run::Plan,
    settings: &crate::settings::Settings,
    extra: &[(&str, Vec<u8>)],
    progress: &mut dyn crate::progress::Progress,
) -> Result<Outcome<FreshStudy>> {
    let draft = Draft::new(out)?;
    for (name, bytes) in extra {
        crate::io::write_atomic(&draft.path().join(name), bytes)?;
    }
    let done = run::run(&draft, plan, settings, progress)?;
    if done.dirs.is_empty() {
        bail!("stopped before any configuration finished; no report written");
    }
    done.try_map(|done| {
        Ok(FreshStudy {
            study: Study::read(&done.dirs)?,
            meta: done.meta,
            draft,
        })
    })
}

/// [`study_fresh`] written with `command` on its page: the page's path and the configurations it holds (stopped,
/// those finished).
pub fn fresh(
    out: &Path,
    plan: &run::Plan,
    settings: &crate::settings::Settings,
    command: String,
    extra: &[(&str, Vec<u8>)],
    progress: &mut dyn crate::progress::Progress,
) -> Result<Outcome<(PathBuf, usize)>> {
    study_fresh(out, plan, settings, extra, progress)?.try_map(|study| {
        let configurations = study.configurations();
        Ok((study.finish(command)?, configurations))
    })
}

/// Copies `names` present in `from` into `to` (created), unless `from` is `to` or there are none.
fn copy_part(from: &Path, to: &Path, names: &[&str]) -> Result<()> {
    if names.is_empty() {
        return Ok(());
    }
    std::fs::create_dir_all(to).with_context(|| format!("{}: cannot create", to.display()))?;
    let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y);
    if same(from, to) {
        return Ok(());
    }
    for name in names {
        let src = from.join(name);
        if src.is_file() {
            std::fs::copy(&src, to.join(name))
                .with_context(|| format!("{}: cannot copy into the report", src.display()))?;
        }
    }
    Ok(())
}

/// The page of `study`: the sections that have data, in order.
pub fn html(study: &Study, meta: &Meta) -> String {
    let title = match &meta.preset {
        Some(p) => format!("hairlab study: {p}"),
        None => "hairlab study".to_string(),
    };
    let mut body = format!("<header><h1>{}</h1></header>\n<main>\n", page::escape(&title));
    body += &sections::scene(study, meta).unwrap_or_default();
    body += &sections::machine(study, meta);
    if let Some(s) = &study.shadows {
        body += &sections::shadows(s);
        let dir = format!("{}/{}", sections::SHADOWS_DIR, data::IMAGES);
        body += &images::configurations(s, &dir).unwrap_or_default();
    }
    if let Some(t) = &study.transparency {
        body += &sections::transparency(t);
    }
    if let Some(m) = &study.motion {
        body += &sections::motion(m);
    }
    if let Some(t) = &study.truth {
        body += &sections::truth(t);
    }
    body += &claims::claims(study).unwrap_or_default();
    body += "</main>\n";
    page::document(&title, &body)
}
