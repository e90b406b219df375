//! Shaders from a folder (`--shaders DIR`, `HAIRLAB_SHADERS`): its `.wgsl` files replace the embedded ones of the
//! same path relative to it (a file it lacks is the embedded one). Before a folder is used, every shader the
//! program composes is composed from it and validated with naga ([`check_all`]); the first error is reported at its
//! original `file:line:column`. The window polls the folder ([`Watch`]) and keeps the last folder that validated.

use super::{Composition, SOURCES, ShaderError};
use std::collections::HashSet;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

/// How often [`Watch::poll`] looks at the folder's modification times.
pub const POLL_INTERVAL: Duration = Duration::from_millis(500);

/// Why a shader folder cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    #[error("{path}: {source}")]
    Read {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{dir}: no .wgsl file in the shaders folder")]
    Empty { dir: String },
    #[error(transparent)]
    Shader(#[from] ShaderError),
}

/// Every `.wgsl` file under a folder with its modification time and length, sorted by path.
type Stamp = Vec<(PathBuf, Option<SystemTime>, u64)>;

/// The `.wgsl` files of a shaders folder, read once.
#[derive(Debug)]
pub struct Folder {
    dir: PathBuf,
    /// Path relative to `dir` (`/`-separated) and contents.
    files: Vec<(String, String)>,
    stamp: Stamp,
}

fn read_err(path: &Path) -> impl FnOnce(std::io::Error) -> LiveError + '_ {
    move |source| LiveError::Read {
        path: path.display().to_string(),
        source,
    }
}

fn stamp(dir: &Path) -> Result<Stamp, LiveError> {
    fn walk(dir: &Path, out: &mut Stamp) -> Result<(), LiveError> {
        for entry in std::fs::read_dir(dir).map_err(read_err(dir))? {
            let path = entry.map_err(read_err(dir))?.path();
            if path.is_dir() {
                walk(&path, out)?;
            } else if path.extension().is_some_and(|x| x == "wgsl") {
                let meta = std::fs::metadata(&path).map_err(read_err(&path))?;
                out.push((path, meta.modified().ok(), meta.len()));
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, &mut out)?;
    out.sort();
    Ok(out)
}

impl Folder {
    /// Reads every `.wgsl` file under `dir`.
    pub fn read(dir: &Path) -> Result<Folder, LiveError> {
        let stamp = stamp(dir)?;
        if stamp.is_empty() {
            return Err(LiveError::Empty {
                dir: dir.display().to_string(),
            });
        }
        let mut files = Vec::with_capacity(stamp.len());
        for (path, _, _) in &stamp {
            let text = std::fs::read_to_string(path).map_err(read_err(path))?;
            let rel = path
                .strip_prefix(dir)
                .expect("walked under the folder")
                .to_string_lossy()
                .replace('\\', "/");
            files.push((rel, text));
        }
        Ok(Folder {
            dir: dir.to_path_buf(),
            files,
            stamp,
        })
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The folder's files by path relative to it.
    pub fn paths(&self) -> impl Iterator<Item = &str> {
        self.files.iter().map(|(p, _)| p.as_str())
    }

    /// The file `path` (relative to the folder): its path, contents and how errors name it (`<dir>/<path>`).
    pub fn file(&self, path: &str) -> Option<(&str, &str, String)> {
        self.files
            .iter()
            .find(|(p, _)| p == path)
            .map(|(p, text)| (p.as_str(), text.as_str(), self.dir.join(p).display().to_string()))
    }

    /// How many of the embedded shaders the folder replaces, and how many it leaves embedded.
    pub fn coverage(&self) -> (usize, usize) {
        let replaced = SOURCES.iter().filter(|(p, _)| self.file(p).is_some()).count();
        (replaced, SOURCES.len() - replaced)
    }
}

/// Every composition the program builds a shader module from: each pass shader with every method lookup and
/// technique store function it takes, every caster stage and every sort size.
fn compositions(pass_files: &[&'static str]) -> Vec<Composition<'static>> {
    use crate::render::eye::lists::SORT_SIZES;
    let lookups: Vec<&'static str> = crate::methods::registry::all()
        .iter()
        .map(|m| m.lookup_wgsl())
        .collect();
    let techniques = crate::render::transparency::registry::all();
    let stores: Vec<&'static str> = techniques.iter().map(|t| t.info().hair_wgsl).collect();
    let casters: Vec<&'static str> = crate::render::LightStrands::ALL
        .iter()
        .map(|s| s.stage().wgsl)
        .collect();
    let own: Vec<&'static str> = techniques
        .iter()
        .flat_map(|t| t.info().pass_wgsl.iter().copied())
        .collect();
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for &path in pass_files.iter().chain(&own) {
        if !seen.insert(path) {
            continue;
        }
        let methods: Vec<Option<&'static str>> = if super::METHOD_PASSES.contains(&path) {
            lookups.iter().copied().map(Some).collect()
        } else {
            vec![None]
        };
        let stores: Vec<Option<&'static str>> = if super::TECHNIQUE_PASSES.contains(&path) {
            stores.iter().copied().map(Some).collect()
        } else {
            vec![None]
        };
        for &method in &methods {
            for &technique in &stores {
                for &caster in &casters {
                    out.push(Composition {
                        path,
                        method,
                        technique,
                        caster: Some(caster),
                        sizes: Some(&SORT_SIZES),
                    });
                }
            }
        }
    }
    out
}

/// The pass shaders: the embedded files outside the folders of pasted pieces.
fn pass_files() -> Vec<&'static str> {
    SOURCES
        .iter()
        .map(|(p, _)| *p)
        .filter(|p| {
            !["common/", "methods/", "transparency/", "casters/"]
                .iter()
                .any(|d| p.starts_with(d))
        })
        .collect()
}

/// Composes every shader the program uses from `folder`'s files over the embedded ones and validates each with
/// naga; the first error names its original file, line and column. Returns how many distinct shaders were
/// validated.
pub fn check_all(folder: Option<&Folder>) -> Result<usize, ShaderError> {
    let passes = pass_files();
    let mut checked = HashSet::new();
    for what in compositions(&passes) {
        let composed = super::compose_in(folder, &what)?;
        let mut h = DefaultHasher::new();
        composed.text.hash(&mut h);
        if checked.insert(h.finish()) {
            composed.check()?;
        }
    }
    Ok(checked.len())
}

/// Reads `dir`, validates every shader composed from it ([`check_all`]) and makes it the folder every later
/// composition reads ([`super::set_folder`]).
pub fn load(dir: &Path) -> Result<Arc<Folder>, LiveError> {
    let folder = Arc::new(Folder::read(dir)?);
    check_all(Some(&folder))?;
    super::set_folder(Some(folder.clone()));
    Ok(folder)
}

/// A shaders folder the window polls: a change that validates becomes the folder in use; one that does not is
/// reported once and the folder in use (the embedded shaders at first) stays.
pub struct Watch {
    dir: PathBuf,
    /// The folder's stamp when last read (`None`: not read yet).
    seen: Option<Stamp>,
    next: Instant,
}

impl Watch {
    /// Watches `dir`; the first [`Watch::poll`] loads it.
    pub fn new(dir: &Path) -> Watch {
        Watch {
            dir: dir.to_path_buf(),
            seen: None,
            next: Instant::now(),
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// At most every [`POLL_INTERVAL`]: when a file of the folder was added, removed or modified since the last
    /// look, [`load`]s it: `Some(Ok)` when it is now in use (every pipeline should be rebuilt), `Some(Err)` when it
    /// was refused (the shaders in use stay). `None` when nothing changed.
    pub fn poll(&mut self) -> Option<Result<Arc<Folder>, LiveError>> {
        let now = Instant::now();
        if now < self.next {
            return None;
        }
        self.next = now + POLL_INTERVAL;
        let current = match stamp(&self.dir) {
            Ok(s) => s,
            Err(e) => {
                // Report an unreadable folder once, as a change.
                return (self.seen.replace(Vec::new()) != Some(Vec::new())).then_some(Err(e));
            }
        };
        if self.seen.as_ref() == Some(&current) {
            return None;
        }
        self.seen = Some(current);
        let loaded = load(&self.dir);
        if let Ok(folder) = &loaded {
            self.seen = Some(folder.stamp.clone());
        }
        Some(loaded)
    }
}
