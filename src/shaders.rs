//! WGSL sources embedded at compile time and a tiny include step: `#include "common/x.wgsl"` pastes a file of
//! `shaders/`, `#include_method` pastes the selected shadow method's lookup (`shaders/methods/<name>.wgsl`),
//! `#include_technique` the selected eye transparency technique's store function (`shaders/transparency/<name>.wgsl`).
//! Included files may include others; each file is pasted once per composed shader, where it is first named.
//! One more step serves the per-pixel lists' resolves (`crate::render::eye::lists`): the lines between
//! `#sort_sizes begin` and `#sort_sizes end` are written for 64 nodes and pasted once per sort size, `_64` and
//! `64u` replaced by the size, and `#sort_dispatch` becomes the line that calls the smallest size holding a pixel's
//! `n` nodes ([`compose_sorts`]; [`compose`] instantiates the 64 alone).

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
    "common/layer_build_uniforms.wgsl",
    "common/layer_pass.wgsl",
    "common/visibility.wgsl",
    "common/osm_uniforms.wgsl",
    "common/dom_uniforms.wgsl",
    "common/bom_uniforms.wgsl",
    "common/dc_uniforms.wgsl",
    "common/occupancy_uniforms.wgsl",
    "common/fom_uniforms.wgsl",
    "common/dsm_uniforms.wgsl",
    "common/msm_uniforms.wgsl",
    "common/msm_bound.wgsl",
    "common/mboit.wgsl",
    "common/shortcut.wgsl",
    "common/avsm_uniforms.wgsl",
    "common/fullscreen.wgsl",
    "common/list_node.wgsl",
    "methods/none.wgsl",
    "methods/adsm.wgsl",
    "methods/opaque_shadow_map.wgsl",
    "methods/reference.wgsl",
    "methods/osm.wgsl",
    "methods/dc.wgsl",
    "methods/dom.wgsl",
    "methods/bom.wgsl",
    "methods/occupancy.wgsl",
    "methods/fom.wgsl",
    "methods/dsm.wgsl",
    "methods/msm.wgsl",
    "methods/avsm.wgsl",
    "common/eye_vertex.wgsl",
    "common/eye_node.wgsl",
    "common/mesh_depth.wgsl",
    "common/eye_sort.wgsl",
    "common/list_resolve.wgsl",
    "common/list_count.wgsl",
    "fur/resolve.wgsl",
    "motion/simulate.wgsl",
    "fur/ribbon_count.wgsl",
    "transparency/sorted.wgsl",
    "transparency/sorted_count.wgsl",
    "transparency/sorted_resolve.wgsl",
    "transparency/wboit.wgsl",
    "transparency/wboit_resolve.wgsl",
    "transparency/weighted_average.wgsl",
    "transparency/weighted_average_resolve.wgsl",
    "transparency/opaque.wgsl",
    "transparency/opaque_resolve.wgsl",
    "transparency/depth_peel.wgsl",
    "transparency/depth_peel_count.wgsl",
    "transparency/depth_peel_under.wgsl",
    "transparency/depth_peel_resolve.wgsl",
    "common/occupancy_estimate.wgsl",
    "common/occupancy_order_uniforms.wgsl",
    "transparency/occupancy_order.wgsl",
    "transparency/occupancy_order_maps.wgsl",
    "transparency/occupancy_order_resolve.wgsl",
    "transparency/mboit.wgsl",
    "transparency/mboit_moments.wgsl",
    "transparency/mboit_resolve.wgsl",
    "transparency/shortcut.wgsl",
    "transparency/shortcut_depths.wgsl",
    "transparency/shortcut_resolve.wgsl",
    "light_depth.wgsl",
    "shadow_map.wgsl",
    "abuffer.wgsl",
    "depth_peel.wgsl",
    "layer_resolve.wgsl",
    "osm.wgsl",
    "dc.wgsl",
    "dom.wgsl",
    "bom.wgsl",
    "occupancy.wgsl",
    "fom.wgsl",
    "dsm.wgsl",
    "msm.wgsl",
    "avsm.wgsl",
    "fur/shell.wgsl",
    "fur/density.wgsl",
    "common/fur_face.wgsl",
    "common/fur_noise.wgsl",
    "mesh.wgsl",
    "hair.wgsl",
    "evaluate.wgsl",
];

/// Pass shaders that take a method lookup through `#include_method`.
pub const METHOD_PASSES: &[&str] = &["mesh.wgsl", "hair.wgsl", "evaluate.wgsl"];

/// Pass shaders that take an eye transparency technique's store function through `#include_technique`.
pub const TECHNIQUE_PASSES: &[&str] = &["hair.wgsl"];

/// Why a shader could not be composed; each names the include chain (`a.wgsl -> b.wgsl`) where it happened.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ShaderError {
    #[error("include cycle: {chain}")]
    Cycle { chain: String },
    #[error("{chain}: no such shader file")]
    NoSuchFile { chain: String },
    #[error("{chain}: needs a shadow method lookup")]
    NeedsMethod { chain: String },
    #[error("{chain}: needs an eye transparency technique")]
    NeedsTechnique { chain: String },
    #[error("{chain}: malformed include '{line}'")]
    MalformedInclude { chain: String, line: String },
    #[error("{at}: unpaired '#sort_sizes {directive}'")]
    UnpairedSortSizes { at: String, directive: String },
}

/// Composes the pass shader `path`, resolving includes; `method` is the method lookup file for
/// `#include_method` (e.g. `methods/none.wgsl`).
pub fn compose(path: &str, method: Option<&str>) -> Result<String, ShaderError> {
    compose_from(SOURCES, path, method, None)
}

/// [`compose`] of a list resolve with its sort instantiated for each of `sizes` (ascending, not empty).
pub fn compose_sorts(path: &str, sizes: &[u32]) -> Result<String, ShaderError> {
    let mut composer = Composer::new(SOURCES, None, None);
    composer.sizes = sizes;
    composer.paste(path)?;
    Ok(composer.out)
}

/// [`compose`] with `technique`, the store function file for `#include_technique` (e.g. `transparency/wboit.wgsl`).
pub fn compose_with(
    path: &str,
    method: Option<&str>,
    technique: Option<&str>,
) -> Result<String, ShaderError> {
    compose_from(SOURCES, path, method, technique)
}

/// [`compose_with`] over the files of `sources`.
fn compose_from(
    sources: &[(&str, &str)],
    path: &str,
    method: Option<&str>,
    technique: Option<&str>,
) -> Result<String, ShaderError> {
    let mut composer = Composer::new(sources, method, technique);
    composer.paste(path)?;
    Ok(composer.out)
}

/// The sort size the `#sort_sizes` template is written for.
const TEMPLATE_SIZE: u32 = 64;

struct Composer<'a> {
    sources: &'a [(&'a str, &'a str)],
    method: Option<&'a str>,
    technique: Option<&'a str>,
    /// The files being pasted, outermost first (for cycles and error messages).
    chain: Vec<&'a str>,
    /// Every file pasted so far.
    pasted: Vec<&'a str>,
    out: String,
    /// The sort sizes of `#sort_sizes` templates, and the template being collected (its output so far).
    sizes: &'a [u32],
    template: Option<String>,
}

impl<'a> Composer<'a> {
    fn new(sources: &'a [(&'a str, &'a str)], method: Option<&'a str>, technique: Option<&'a str>) -> Self {
        Composer {
            sources,
            method,
            technique,
            chain: Vec::new(),
            pasted: Vec::new(),
            out: String::new(),
            sizes: &[TEMPLATE_SIZE],
            template: None,
        }
    }

    /// `#sort_sizes begin` / `end`: collects the template, then pastes it once per size.
    fn sort_sizes(&mut self, directive: &str) -> Result<(), ShaderError> {
        let here = self.chain.join(" -> ");
        match (directive, self.template.take()) {
            ("begin", None) => {
                self.template = Some(std::mem::take(&mut self.out));
            }
            ("end", Some(before)) => {
                let template = std::mem::replace(&mut self.out, before);
                for s in self.sizes {
                    self.out.push_str(
                        &template
                            .replace(&format!("_{TEMPLATE_SIZE}"), &format!("_{s}"))
                            .replace(&format!("{TEMPLATE_SIZE}u"), &format!("{s}u")),
                    );
                }
            }
            _ => {
                return Err(ShaderError::UnpairedSortSizes {
                    at: here,
                    directive: directive.to_string(),
                });
            }
        }
        Ok(())
    }

    /// `#sort_dispatch`: `resolve_<size>(head, n)` of the smallest size holding `n` nodes, the last clamped.
    fn sort_dispatch(&mut self) {
        let (last, smaller) = self.sizes.split_last().expect("at least one sort size");
        self.out.push_str("    ");
        for s in smaller {
            self.out
                .push_str(&format!("if n <= {s}u {{ return resolve_{s}(head, n); }}\n    "));
        }
        self.out
            .push_str(&format!("return resolve_{last}(head, min(n, {last}u));\n"));
    }
    /// The include chain ending in `last`, e.g. `hair.wgsl -> common/frame.wgsl -> last`.
    fn chain_to(&self, last: &str) -> String {
        let mut chain = self.chain.join(" -> ");
        if !chain.is_empty() {
            chain.push_str(" -> ");
        }
        chain + last
    }

    fn paste(&mut self, path: &'a str) -> Result<(), ShaderError> {
        if self.chain.contains(&path) {
            return Err(ShaderError::Cycle {
                chain: self.chain_to(path),
            });
        }
        if self.pasted.contains(&path) {
            return Ok(());
        }
        let &(name, src) =
            self.sources
                .iter()
                .find(|(p, _)| *p == path)
                .ok_or_else(|| ShaderError::NoSuchFile {
                    chain: self.chain_to(path),
                })?;
        self.chain.push(name);
        self.pasted.push(name);
        for line in src.lines() {
            let trimmed = line.trim();
            if trimmed == "#include_method" {
                let m = self.method.ok_or_else(|| ShaderError::NeedsMethod {
                    chain: self.chain.join(" -> "),
                })?;
                self.paste(m)?;
            } else if trimmed == "#include_technique" {
                let t = self.technique.ok_or_else(|| ShaderError::NeedsTechnique {
                    chain: self.chain.join(" -> "),
                })?;
                self.paste(t)?;
            } else if let Some(directive) = trimmed.strip_prefix("#sort_sizes ") {
                self.sort_sizes(directive.trim())?;
            } else if trimmed == "#sort_dispatch" {
                self.sort_dispatch();
            } else if let Some(rest) = trimmed.strip_prefix("#include ") {
                let inc = rest
                    .trim()
                    .strip_prefix('"')
                    .and_then(|r| r.strip_suffix('"'))
                    .ok_or_else(|| ShaderError::MalformedInclude {
                        chain: self.chain.join(" -> "),
                        line: trimmed.to_string(),
                    })?;
                self.paste(inc)?;
            } else {
                self.out.push_str(line);
                self.out.push('\n');
            }
        }
        self.chain.pop();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::compose_from;

    const FILES: &[(&str, &str)] = &[
        (
            "pass.wgsl",
            "#include \"a.wgsl\"\n#include \"b.wgsl\"\nfn pass() {}",
        ),
        ("a.wgsl", "#include \"c.wgsl\"\nfn a() {}"),
        ("b.wgsl", "#include \"c.wgsl\"\n#include \"a.wgsl\"\nfn b() {}"),
        ("c.wgsl", "fn c() {}"),
        (
            "method_pass.wgsl",
            "#include \"c.wgsl\"\n#include_method\nfn main() {}",
        ),
        ("m.wgsl", "#include \"c.wgsl\"\nfn visibility_at() {}"),
        ("cycle1.wgsl", "#include \"cycle2.wgsl\""),
        ("cycle2.wgsl", "#include \"cycle3.wgsl\""),
        ("cycle3.wgsl", "#include \"cycle1.wgsl\""),
        ("self.wgsl", "#include \"self.wgsl\""),
        ("missing.wgsl", "#include \"a.wgsl\"\n#include \"d.wgsl\""),
        ("nested_missing.wgsl", "#include \"missing.wgsl\""),
        ("unquoted.wgsl", "#include c.wgsl"),
        (
            "eye_pass.wgsl",
            "#include_method\n#include_technique\n#include \"c.wgsl\"\nfn main() {}",
        ),
        ("t.wgsl", "#include \"c.wgsl\"\nfn store_hair() {}"),
        (
            "sorts.wgsl",
            "#include \"c.wgsl\"\n#sort_sizes begin\nfn resolve_64() -> array<u32, 64u> {}\n#sort_sizes end\nfn main() {\n#sort_dispatch\n}",
        ),
        ("unpaired.wgsl", "#sort_sizes end"),
    ];

    #[test]
    fn a_sort_template_is_pasted_once_per_size_and_dispatched_to_the_smallest() {
        let mut composer = super::Composer::new(FILES, None, None);
        composer.sizes = &[16, 128];
        composer.paste("sorts.wgsl").unwrap();
        assert_eq!(
            composer.out,
            "fn c() {}\nfn resolve_16() -> array<u32, 16u> {}\nfn resolve_128() -> array<u32, 128u> {}\nfn main() {\n    \
             if n <= 16u { return resolve_16(head, n); }\n    return resolve_128(head, min(n, 128u));\n}\n"
        );
        let one = compose_from(FILES, "sorts.wgsl", None, None).unwrap();
        assert!(
            one.contains("fn resolve_64() -> array<u32, 64u> {}\n")
                && one.contains("return resolve_64(head, min(n, 64u));")
        );
        assert_eq!(
            compose_from(FILES, "unpaired.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "unpaired.wgsl: unpaired '#sort_sizes end'"
        );
    }

    #[test]
    fn includes_recurse_and_each_file_is_pasted_once_where_first_named() {
        let out = compose_from(FILES, "pass.wgsl", None, None).unwrap();
        assert_eq!(out, "fn c() {}\nfn a() {}\nfn b() {}\nfn pass() {}\n");
    }

    #[test]
    fn the_method_lookup_is_pasted_once_too() {
        let out = compose_from(FILES, "method_pass.wgsl", Some("m.wgsl"), None).unwrap();
        assert_eq!(out, "fn c() {}\nfn visibility_at() {}\nfn main() {}\n");
        assert_eq!(
            compose_from(FILES, "method_pass.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "method_pass.wgsl: needs a shadow method lookup"
        );
        assert_eq!(
            compose_from(FILES, "method_pass.wgsl", Some("nope.wgsl"), None)
                .unwrap_err()
                .to_string(),
            "method_pass.wgsl -> nope.wgsl: no such shader file"
        );
    }

    #[test]
    fn the_technique_store_function_is_pasted_after_the_method_and_once() {
        let out = compose_from(FILES, "eye_pass.wgsl", Some("m.wgsl"), Some("t.wgsl")).unwrap();
        assert_eq!(
            out,
            "fn c() {}\nfn visibility_at() {}\nfn store_hair() {}\nfn main() {}\n"
        );
        assert_eq!(
            compose_from(FILES, "eye_pass.wgsl", Some("m.wgsl"), None)
                .unwrap_err()
                .to_string(),
            "eye_pass.wgsl: needs an eye transparency technique"
        );
        assert_eq!(
            compose_from(FILES, "eye_pass.wgsl", Some("m.wgsl"), Some("nope.wgsl"))
                .unwrap_err()
                .to_string(),
            "eye_pass.wgsl -> nope.wgsl: no such shader file"
        );
    }

    #[test]
    fn an_include_cycle_is_an_error_naming_the_chain() {
        assert_eq!(
            compose_from(FILES, "cycle1.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "include cycle: cycle1.wgsl -> cycle2.wgsl -> cycle3.wgsl -> cycle1.wgsl"
        );
        assert_eq!(
            compose_from(FILES, "self.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "include cycle: self.wgsl -> self.wgsl"
        );
    }

    #[test]
    fn a_missing_file_is_an_error_naming_the_chain() {
        assert_eq!(
            compose_from(FILES, "nested_missing.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "nested_missing.wgsl -> missing.wgsl -> d.wgsl: no such shader file"
        );
        assert_eq!(
            compose_from(FILES, "none.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "none.wgsl: no such shader file"
        );
    }

    #[test]
    fn an_unquoted_include_is_an_error() {
        assert_eq!(
            compose_from(FILES, "unquoted.wgsl", None, None)
                .unwrap_err()
                .to_string(),
            "unquoted.wgsl: malformed include '#include c.wgsl'"
        );
    }
}
