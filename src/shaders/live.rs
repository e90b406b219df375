//! A shaders folder (`--shaders DIR`, `HAIRLAB_SHADERS`) as read: its `.wgsl` files replace the embedded ones of
//! the same path relative to it (a file it lacks is the embedded one). Checking every composition against it and
//! watching it are `crate::live_shaders`' (above the method and technique registries it enumerates).

use super::{SOURCES, ShaderError};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

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
pub type Stamp = Vec<(PathBuf, Option<SystemTime>, u64)>;

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

/// The `.wgsl` files under `dir` with their modification times and lengths: what a change of the folder changes.
pub fn stamp(dir: &Path) -> Result<Stamp, LiveError> {
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

    /// The folder's [`Stamp`] when it was read.
    pub fn stamp(&self) -> &Stamp {
        &self.stamp
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
