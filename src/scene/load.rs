//! Loading a scene from a file, choosing the loader by extension (`.hair`, `.gltf`, `.glb`, `.tfx`, `.data`, and
//! with the `usd` feature `.usda`, `.usdc`, `.usdz`).
//!
//! hairlab's world is right-handed and Y-up. `.hair` and glTF (Y-up by its specification, metres) are taken as they
//! are, in the units of the file; so are TressFX `.tfx` (Y-up, as TressFX runtimes expect) and USC-HairSalon `.data`
//! (Y-up, aligned to the database's head model). A USD stage states its up axis and unit, so its reader turns a
//! Z-up stage to Y-up and scales to metres. What each reader keeps and drops is stated in its module:
//! [`super::hair`], [`super::gltf_load`], [`super::tfx`], [`super::usc_data`], `super::usd`.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::bail;

use super::{Scene, gltf_load, hair, tfx, usc_data};

/// Every extension [`load_scene`] reads (lower case), for file dialogs.
#[cfg(feature = "usd")]
pub const SCENE_EXTENSIONS: &[&str] = &["hair", "gltf", "glb", "tfx", "data", "usda", "usdc", "usdz"];
/// Every extension [`load_scene`] reads (lower case), for file dialogs (built without the `usd` feature).
#[cfg(not(feature = "usd"))]
pub const SCENE_EXTENSIONS: &[&str] = &["hair", "gltf", "glb", "tfx", "data"];

/// Loads `path` as a scene: `.hair`, `.tfx` and `.data` files give strands only (no meshes); `.gltf`/`.glb` files
/// and USD stages give meshes and strands (a time-sampled stage its first time code). The extension is matched case-insensitively; anything else is an error naming the
/// file.
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    load_scene_with(path, &mut crate::progress::Quiet)
}

/// [`load_scene`] telling `progress` how far a `.hair`, `.tfx` or `.data` file's read (and a `.data` file's
/// parse) got ([`super::progress`]); once it answers `false` the load stops (an error, or the strands so far).
pub fn load_scene_with(path: &Path, progress: &mut dyn crate::progress::Progress) -> anyhow::Result<Scene> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("hair") => {
            let strands = hair::read_hair_file_with(path, progress)?
                .to_strands()
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
            Ok(Scene::new(strands, Vec::new()))
        }
        Some("gltf" | "glb") => Ok(gltf_load::load_gltf(path)?),
        Some("tfx") => Ok(Scene::new(
            tfx::read_tfx_file_with(path, progress)?.to_strands(),
            Vec::new(),
        )),
        Some("data") => Ok(Scene::new(
            usc_data::read_data_file_with(path, progress)?.strands,
            Vec::new(),
        )),
        #[cfg(feature = "usd")]
        Some("usda" | "usdc" | "usdz") => {
            let s = super::usd::read_usd_file(path)?;
            check_warnings(path, &s.warnings)?;
            let mut scene = Scene::new(s.strands, s.meshes);
            scene.warnings = s.warnings;
            Ok(scene)
        }
        _ => bail!(
            "{}: unsupported file type (supported: .{})",
            path.display(),
            SCENE_EXTENSIONS.join(", .")
        ),
    }
}

/// Whether a warning reading a scene (a USD layer missing or unreadable, an arc dropped) fails the load: the
/// `--strict` flag of `info`, `convert` and `render`, for scripts. Process-wide: the command sets it once.
static STRICT: AtomicBool = AtomicBool::new(false);

/// Makes every later scene load fail on a warning ([`check_warnings`]).
pub fn set_strict(strict: bool) {
    STRICT.store(strict, Ordering::Relaxed);
}

/// Under [`set_strict`], fails when `path` gave warnings, naming them.
pub fn refuse_if_strict(path: &Path, warnings: &[String]) -> anyhow::Result<()> {
    if STRICT.load(Ordering::Relaxed) && !warnings.is_empty() {
        bail!(
            "{}: {} warning(s) and --strict: {}",
            path.display(),
            warnings.len(),
            warnings.join("; ")
        );
    }
    Ok(())
}

/// Logs each of `path`'s warnings (a line on stderr from a command, in the log from the window); under
/// [`set_strict`], fails with them instead.
pub fn check_warnings(path: &Path, warnings: &[String]) -> anyhow::Result<()> {
    refuse_if_strict(path, warnings)?;
    for w in warnings {
        log::warn!("{}: {w}", path.display());
    }
    Ok(())
}

/// Every extension [`save_strands`] writes (lower case).
pub const STRAND_EXTENSIONS: [&str; 4] = ["hair", "tfx", "data", "usda"];

/// Writes `strands` to `path` in the format its extension names (`.hair`, `.tfx`, `.data`, `.usda`, any case), whole or not
/// at all (each writer goes through [`crate::io::write_atomic_io`]). `info` is the `.hair` info string. A groom the
/// format cannot hold (a `.tfx` needs equal strand lengths, ...) is an error naming the file; a `.data` file holds
/// positions only, so thickness, alpha and colour are not written to it (the caller says so).
pub fn save_strands(path: &Path, strands: &super::Strands, info: &str) -> anyhow::Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let in_file = |e: &dyn std::fmt::Display| anyhow::anyhow!("{}: {e}", path.display());
    match ext.as_deref() {
        Some("hair") => {
            let h = hair::HairFile::from_strands(strands, info).map_err(|e| in_file(&e))?;
            Ok(hair::write_hair_file(path, &h)?)
        }
        Some("tfx") => {
            let f = tfx::TfxFile::from_strands(strands).map_err(|e| in_file(&e))?;
            Ok(tfx::write_tfx_file(path, &f)?)
        }
        Some("data") => Ok(usc_data::write_data_file(path, strands)?),
        Some("usda") => super::usda_write::write_usda_file(path, std::slice::from_ref(strands), 24.0),
        _ => bail!(
            "{}: cannot write this file type (written: .{})",
            path.display(),
            STRAND_EXTENSIONS.join(", .")
        ),
    }
}
