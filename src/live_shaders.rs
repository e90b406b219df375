//! Live shaders (`--shaders DIR`, `HAIRLAB_SHADERS`): before a folder ([`crate::shaders::live::Folder`]) is used,
//! every shader the program composes — each pass with every method lookup and technique store of the registries —
//! is composed from it and validated with naga ([`check_all`]); the first error is reported at its original
//! `file:line:column`. The window polls the folder ([`Watch`]) and keeps the last folder that validated. Above the
//! shaders, methods and render modules, so that none of them imports the registries' users.

use crate::shaders::live::{Folder, LiveError, Stamp, stamp};
use crate::shaders::{
    Composition, METHOD_PASSES, SOURCES, ShaderError, TECHNIQUE_PASSES, compose_in, set_folder,
};
use std::collections::HashSet;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often [`Watch::poll`] looks at the folder's modification times.
pub const POLL_INTERVAL: Duration = Duration::from_millis(500);

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
        let methods: Vec<Option<&'static str>> = if METHOD_PASSES.contains(&path) {
            lookups.iter().copied().map(Some).collect()
        } else {
            vec![None]
        };
        let stores: Vec<Option<&'static str>> = if TECHNIQUE_PASSES.contains(&path) {
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
        let composed = compose_in(folder, &what)?;
        let mut h = DefaultHasher::new();
        composed.text.hash(&mut h);
        if checked.insert(h.finish()) {
            composed.check()?;
        }
    }
    Ok(checked.len())
}

/// Reads `dir`, validates every shader composed from it ([`check_all`]) and makes it the folder every later
/// composition reads ([`set_folder`]).
pub fn load(dir: &Path) -> Result<Arc<Folder>, LiveError> {
    let folder = Arc::new(Folder::read(dir)?);
    check_all(Some(&folder))?;
    set_folder(Some(folder.clone()));
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
            self.seen = Some(folder.stamp().clone());
        }
        Some(loaded)
    }
}
