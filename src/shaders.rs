//! WGSL sources embedded at compile time and a tiny include step: `#include "common/x.wgsl"` pastes a shared file,
//! `#include_method` pastes the selected shadow method's lookup (`shaders/methods/<name>.wgsl`).

/// Embeds files of `shaders/` by their path relative to that folder.
macro_rules! embed {
    ($($path:literal),* $(,)?) => {
        &[$(($path, include_str!(concat!("../shaders/", $path)))),*]
    };
}

/// Every WGSL file under `shaders/`, by path relative to that folder (a test checks none is missing).
pub const SOURCES: &[(&str, &str)] = embed![
    "common/frame.wgsl",
    "common/scene_bindings.wgsl",
    "common/kajiya_kay.wgsl",
    "common/light_vertex.wgsl",
    "common/method_lookup.wgsl",
    "common/cumulative_targets.wgsl",
    "methods/none.wgsl",
    "methods/opaque_shadow_map.wgsl",
    "methods/reference.wgsl",
    "methods/osm.wgsl",
    "methods/dc.wgsl",
    "methods/dom.wgsl",
    "methods/bom.wgsl",
    "methods/occupancy.wgsl",
    "light_depth.wgsl",
    "shadow_map.wgsl",
    "abuffer.wgsl",
    "depth_peel.wgsl",
    "osm.wgsl",
    "dc.wgsl",
    "dom.wgsl",
    "bom.wgsl",
    "occupancy.wgsl",
    "mesh.wgsl",
    "hair.wgsl",
    "composite.wgsl",
    "evaluate.wgsl",
];

/// Pass shaders that take a method lookup through `#include_method`.
pub const METHOD_PASSES: &[&str] = &["mesh.wgsl", "hair.wgsl", "evaluate.wgsl"];

/// The embedded source of `path`.
pub fn source(path: &str) -> Option<&'static str> {
    SOURCES.iter().find(|(p, _)| *p == path).map(|(_, s)| *s)
}

/// Composes the pass shader `path`, resolving includes; `method` is the method lookup file for
/// `#include_method` (e.g. `methods/none.wgsl`).
pub fn compose(path: &str, method: Option<&str>) -> Result<String, String> {
    let src = source(path).ok_or_else(|| format!("no embedded shader '{path}'"))?;
    let mut out = String::with_capacity(src.len() * 2);
    for line in src.lines() {
        let trimmed = line.trim();
        if trimmed == "#include_method" {
            let m = method.ok_or_else(|| format!("{path} needs a shadow method lookup"))?;
            let body = source(m).ok_or_else(|| format!("{path}: no method lookup '{m}'"))?;
            out.push_str(body);
        } else if let Some(rest) = trimmed.strip_prefix("#include ") {
            let inc = rest.trim_matches('"');
            let body = source(inc).ok_or_else(|| format!("{path}: cannot include '{inc}'"))?;
            out.push_str(body);
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    Ok(out)
}
