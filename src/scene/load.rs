//! Loading a scene from a file, choosing the loader by extension (`.hair`, `.gltf`, `.glb`).

use std::path::Path;

use anyhow::bail;

use super::{Scene, gltf_load, hair};

/// Loads `path` as a scene: `.hair` files give strands only (no meshes); `.gltf`/`.glb` files give meshes and
/// strands. The extension is matched case-insensitively; anything else is an error naming the file.
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("hair") => {
            let strands = hair::read_hair_file(path)?
                .to_strands()
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
            Ok(Scene::new(strands, Vec::new()))
        }
        Some("gltf" | "glb") => Ok(gltf_load::load_gltf(path)?),
        _ => bail!(
            "{}: unsupported file type (supported: .hair, .gltf, .glb)",
            path.display()
        ),
    }
}
