//! WGSL sources embedded at compile time and a tiny include step: `#include "common/x.wgsl"` pastes a file of
//! `shaders/`, `#include_method` pastes the selected shadow method's lookup (`shaders/methods/<name>.wgsl`),
//! `#include_technique` the selected eye transparency technique's store function (`shaders/transparency/<name>.wgsl`),
//! `#include_caster` the light caster's vertex stage (`shaders/casters/<name>.wgsl`, [`compose_light`]; the
//! strands' lines, `casters/lines.wgsl`, where none is named).
//! Included files may include others; each file is pasted once per composed shader, where it is first named.
//! One more step serves the per-pixel lists' resolves (`crate::render::eye::lists`): the lines between
//! `#sort_sizes begin` and `#sort_sizes end` are written for 64 nodes and pasted once per sort size, the whole
//! tokens `…_64` and `64u` replaced by the size (WGSL's `override` cannot do this: one module holds every size,
//! and a function-local array's length must be a constant), and `#sort_dispatch` becomes the line that calls the smallest size holding a pixel's
//! `n` nodes ([`compose_sorts`]; [`compose`] instantiates the 64 alone).
//!
//! Composition keeps a source map ([`Composed`]): the file and line every line of the composed shader came from,
//! so a naga error in it is reported at the original place, `shaders/common/x.wgsl:12:5: message`
//! ([`Composed::check`], no device needed). The sources are the embedded ones, or a folder's over them
//! ([`live`]: `--shaders DIR`, reloaded on change).

pub mod live;

use std::sync::{Arc, RwLock};

/// Every WGSL file under `shaders/`, by path relative to that folder: listed by the build script (`build.rs`)
/// walking the folder, so adding a shader file is no edit here.
pub const SOURCES: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/shader_sources.rs"));

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
    /// A naga parse or validation error at `at`, the original `file:line:column`.
    #[error("{at}: {message}")]
    Wgsl { at: String, message: String },
}

/// The folder whose shaders replace the embedded ones of the same path ([`live`]); `None`: the embedded alone.
static FOLDER: RwLock<Option<Arc<live::Folder>>> = RwLock::new(None);

/// The folder every composition reads over the embedded sources from now on (`None`: the embedded alone).
pub fn set_folder(folder: Option<Arc<live::Folder>>) {
    *FOLDER.write().unwrap_or_else(|e| e.into_inner()) = folder;
}

/// The folder set by [`set_folder`].
pub fn folder() -> Option<Arc<live::Folder>> {
    FOLDER.read().unwrap_or_else(|e| e.into_inner()).clone()
}

/// What a shader is composed from: the pass file and what its directives paste.
#[derive(Clone, Copy, Debug)]
pub struct Composition<'a> {
    pub path: &'a str,
    /// The method lookup for `#include_method`.
    pub method: Option<&'a str>,
    /// The store function for `#include_technique`.
    pub technique: Option<&'a str>,
    /// The caster vertex stage for `#include_caster` ([`DEFAULT_CASTER`] when `None`).
    pub caster: Option<&'a str>,
    /// The sort sizes of `#sort_sizes` templates (the template's 64 alone when `None`).
    pub sizes: Option<&'a [u32]>,
}

impl<'a> Composition<'a> {
    /// The pass `path` with nothing pasted by its directives.
    pub fn of(path: &'a str) -> Self {
        Composition {
            path,
            method: None,
            technique: None,
            caster: None,
            sizes: None,
        }
    }
}

/// A composed shader and its source map.
#[derive(Clone, Debug)]
pub struct Composed {
    pub text: String,
    /// Every pasted file as reported: `shaders/<path>` when embedded, `<folder>/<path>` from a folder.
    files: Vec<String>,
    /// For each line of `text`: its file (index into `files`) and 1-based line there.
    lines: Vec<(usize, u32)>,
}

impl Composed {
    /// The file and 1-based line that the composed text's 1-based `line` came from.
    pub fn origin(&self, line: u32) -> Option<(&str, u32)> {
        let &(file, at) = self.lines.get((line as usize).checked_sub(1)?)?;
        Some((&self.files[file], at))
    }

    /// `file:line:column` of a naga span in the composed text (the composed line when it maps nowhere).
    fn place(&self, span: naga::Span) -> String {
        let loc = span.location(&self.text);
        match self.origin(loc.line_number) {
            Some((file, line)) => format!("{file}:{line}:{}", loc.line_position),
            None => format!("composed:{}:{}", loc.line_number, loc.line_position),
        }
    }

    /// Parses and validates the composed text with naga, reporting the first error at its original file, line
    /// and column.
    pub fn check(&self) -> Result<naga::Module, ShaderError> {
        let module = naga::front::wgsl::parse_str(&self.text).map_err(|e| {
            let at = match e.labels().next() {
                Some((span, _)) => self.place(span),
                None => self.files[0].clone(),
            };
            ShaderError::Wgsl {
                at,
                message: e.message().to_string(),
            }
        })?;
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .map_err(|e| {
            // Spans run from the outermost (the function) to the innermost (the statement or expression).
            let at = match e.spans().last() {
                Some((span, _)) => self.place(*span),
                None => self.files[0].clone(),
            };
            let mut message = e.as_inner().to_string();
            let mut cause = std::error::Error::source(e.as_inner());
            while let Some(c) = cause {
                message.push_str(&format!(": {c}"));
                cause = c.source();
            }
            ShaderError::Wgsl { at, message }
        })?;
        Ok(module)
    }
}

/// Composes `what` from the sources in use (the embedded ones under the [`set_folder`] folder), keeping the
/// source map.
pub fn compose_mapped(what: &Composition) -> Result<Composed, ShaderError> {
    compose_in(folder().as_deref(), what)
}

/// [`compose_mapped`] from `folder`'s files over the embedded ones.
pub fn compose_in(folder: Option<&live::Folder>, what: &Composition) -> Result<Composed, ShaderError> {
    compose_over(SOURCES, folder, what)
}

fn compose_over(
    sources: &[(&str, &str)],
    folder: Option<&live::Folder>,
    what: &Composition,
) -> Result<Composed, ShaderError> {
    let mut composer = Composer::new(sources, what.method, what.technique);
    composer.folder = folder;
    if let Some(c) = what.caster {
        composer.caster = c;
    }
    if let Some(s) = what.sizes {
        composer.sizes = s;
    }
    composer.paste(what.path)?;
    Ok(Composed {
        text: composer.out,
        files: composer.files,
        lines: composer.lines,
    })
}

/// Composes the pass shader `path`, resolving includes; `method` is the method lookup file for
/// `#include_method` (e.g. `methods/none.wgsl`).
pub fn compose(path: &str, method: Option<&str>) -> Result<String, ShaderError> {
    compose_with(path, method, None)
}

/// The caster a light pass is composed with when none is named: the strands as lines.
pub const DEFAULT_CASTER: &str = "casters/lines.wgsl";

/// [`compose`] of a light pass with `caster`'s vertex stage for `#include_caster` (e.g. `casters/ribbons.wgsl`).
pub fn compose_light(path: &str, caster: &str) -> Result<String, ShaderError> {
    let what = Composition {
        caster: Some(caster),
        ..Composition::of(path)
    };
    Ok(compose_mapped(&what)?.text)
}

/// [`compose`] of a list resolve with its sort instantiated for each of `sizes` (ascending, not empty).
pub fn compose_sorts(path: &str, sizes: &[u32]) -> Result<String, ShaderError> {
    let what = Composition {
        sizes: Some(sizes),
        ..Composition::of(path)
    };
    Ok(compose_mapped(&what)?.text)
}

/// [`compose`] with `technique`, the store function file for `#include_technique` (e.g. `transparency/wboit.wgsl`).
pub fn compose_with(
    path: &str,
    method: Option<&str>,
    technique: Option<&str>,
) -> Result<String, ShaderError> {
    let what = Composition {
        method,
        technique,
        ..Composition::of(path)
    };
    Ok(compose_mapped(&what)?.text)
}

/// [`compose_with`] over the files of `sources` alone (no folder).
#[cfg(test)]
fn compose_from(
    sources: &[(&str, &str)],
    path: &str,
    method: Option<&str>,
    technique: Option<&str>,
) -> Result<String, ShaderError> {
    let what = Composition {
        method,
        technique,
        ..Composition::of(path)
    };
    Ok(compose_over(sources, None, &what)?.text)
}

/// The sort size the `#sort_sizes` template is written for.
const TEMPLATE_SIZE: u32 = 64;

/// `template` written for `size` nodes: each whole token `<name>_64` and `64u` of it (never `164u`, `_640` or
/// `x64u`) with the size in place of 64.
fn sized(template: &str, size: u32) -> String {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let (suffix, literal) = (format!("_{TEMPLATE_SIZE}"), format!("{TEMPLATE_SIZE}u"));
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(c) = rest.chars().next() {
        let before = out.chars().next_back();
        let after = |n: usize| rest[n..].chars().next();
        if rest.starts_with(&suffix) && before.is_some_and(ident) && !after(suffix.len()).is_some_and(ident) {
            out += &format!("_{size}");
            rest = &rest[suffix.len()..];
        } else if rest.starts_with(&literal)
            && !before.is_some_and(ident)
            && !after(literal.len()).is_some_and(ident)
        {
            out += &format!("{size}u");
            rest = &rest[literal.len()..];
        } else {
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

struct Composer<'a> {
    sources: &'a [(&'a str, &'a str)],
    /// Files read before `sources`.
    folder: Option<&'a live::Folder>,
    method: Option<&'a str>,
    technique: Option<&'a str>,
    /// The light caster file for `#include_caster`.
    caster: &'a str,
    /// The files being pasted, outermost first (for cycles and error messages).
    chain: Vec<&'a str>,
    /// Every file pasted so far.
    pasted: Vec<&'a str>,
    out: String,
    /// The source map of `out` ([`Composed`]).
    files: Vec<String>,
    lines: Vec<(usize, u32)>,
    /// The sort sizes of `#sort_sizes` templates, and the template being collected (the output and its lines
    /// so far).
    sizes: &'a [u32],
    template: Option<(String, Vec<(usize, u32)>)>,
}

impl<'a> Composer<'a> {
    fn new(sources: &'a [(&'a str, &'a str)], method: Option<&'a str>, technique: Option<&'a str>) -> Self {
        Composer {
            sources,
            folder: None,
            method,
            technique,
            caster: DEFAULT_CASTER,
            chain: Vec::new(),
            pasted: Vec::new(),
            out: String::new(),
            files: Vec::new(),
            lines: Vec::new(),
            sizes: &[TEMPLATE_SIZE],
            template: None,
        }
    }

    /// `#sort_sizes begin` / `end`: collects the template, then pastes it once per size.
    fn sort_sizes(&mut self, directive: &str) -> Result<(), ShaderError> {
        let here = self.chain.join(" -> ");
        match (directive, self.template.take()) {
            ("begin", None) => {
                self.template = Some((std::mem::take(&mut self.out), std::mem::take(&mut self.lines)));
            }
            ("end", Some((before, before_lines))) => {
                let template = std::mem::replace(&mut self.out, before);
                let template_lines = std::mem::replace(&mut self.lines, before_lines);
                for s in self.sizes {
                    self.out.push_str(&sized(&template, *s));
                    self.lines.extend_from_slice(&template_lines);
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

    /// `#sort_dispatch`: `resolve_<size>(head, n)` of the smallest size holding `n` nodes, the last clamped;
    /// every line it writes maps to the directive's line `at`.
    fn sort_dispatch(&mut self, at: (usize, u32)) {
        let (last, smaller) = self.sizes.split_last().expect("at least one sort size");
        self.out.push_str("    ");
        for s in smaller {
            self.out
                .push_str(&format!("if n <= {s}u {{ return resolve_{s}(head, n); }}\n    "));
            self.lines.push(at);
        }
        self.out
            .push_str(&format!("return resolve_{last}(head, min(n, {last}u));\n"));
        self.lines.push(at);
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
        let from_folder = self.folder.and_then(|f| f.file(path));
        let (name, src, shown) =
            match from_folder {
                Some((name, src, shown)) => (name, src, shown),
                None => {
                    let &(name, src) = self.sources.iter().find(|(p, _)| *p == path).ok_or_else(|| {
                        ShaderError::NoSuchFile {
                            chain: self.chain_to(path),
                        }
                    })?;
                    (name, src, format!("shaders/{name}"))
                }
            };
        self.chain.push(name);
        self.pasted.push(name);
        let file = self.files.len();
        self.files.push(shown);
        for (i, line) in src.lines().enumerate() {
            let at = (file, i as u32 + 1);
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
            } else if trimmed == "#include_caster" {
                self.paste(self.caster)?;
            } else if let Some(directive) = trimmed.strip_prefix("#sort_sizes ") {
                self.sort_sizes(directive.trim())?;
            } else if trimmed == "#sort_dispatch" {
                self.sort_dispatch(at);
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
                self.lines.push(at);
            }
        }
        self.chain.pop();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{Composition, ShaderError, compose_from, compose_over};

    /// Passes with an error in an included file: a syntax error on `typo.wgsl`'s line 3, a type error on
    /// `wrong.wgsl`'s line 3, and a sort template pasted twice before a line of its own file.
    const BROKEN: &[(&str, &str)] = &[
        (
            "broken.wgsl",
            "#include \"fine.wgsl\"\n#include \"typo.wgsl\"\nfn main() {}",
        ),
        ("fine.wgsl", "fn fine() -> f32 {\n    return 1.0;\n}"),
        (
            "typo.wgsl",
            "fn typo() -> f32 {\n    let x = 1.0;\n    return x +;\n}",
        ),
        ("mistyped.wgsl", "#include \"fine.wgsl\"\n#include \"wrong.wgsl\""),
        (
            "wrong.wgsl",
            "// returns a u32 from an f32 function\nfn wrong() -> f32 {\n    return 1u;\n}",
        ),
        (
            "sorted.wgsl",
            "#include \"fine.wgsl\"\n#sort_sizes begin\nfn resolve_64() -> u32 { return 64u; }\n#sort_sizes end\nfn after() {}",
        ),
    ];

    fn wgsl_error(path: &str) -> (String, String) {
        let composed = compose_over(BROKEN, None, &Composition::of(path)).unwrap();
        match composed.check().unwrap_err() {
            ShaderError::Wgsl { at, message } => (at, message),
            e => panic!("not a WGSL error: {e}"),
        }
    }

    #[test]
    fn a_syntax_error_in_an_included_file_names_that_file_line_and_column() {
        // Composed line 6 is `typo.wgsl`'s line 3, `    return x +;`: the `;` is column 15.
        let (at, message) = wgsl_error("broken.wgsl");
        assert_eq!(at, "shaders/typo.wgsl:3:15");
        assert!(message.contains("expected"), "{message}");
    }

    #[test]
    fn a_validation_error_in_an_included_file_names_that_file_and_line() {
        // `wrong.wgsl`'s line 3, `    return 1u;` (composed line 6): the returned value `1u`, naga's innermost span,
        // starts at column 12.
        let (at, message) = wgsl_error("mistyped.wgsl");
        assert_eq!(at, "shaders/wrong.wgsl:3:12");
        assert!(message.contains("return"), "{message}");
    }

    #[test]
    fn the_source_map_follows_includes_and_sort_templates() {
        let what = Composition {
            sizes: Some(&[16, 128]),
            ..Composition::of("sorted.wgsl")
        };
        let composed = compose_over(BROKEN, None, &what).unwrap();
        let origins: Vec<_> = (1..=6).map(|l| composed.origin(l)).collect();
        assert_eq!(
            origins,
            [
                Some(("shaders/fine.wgsl", 1)),
                Some(("shaders/fine.wgsl", 2)),
                Some(("shaders/fine.wgsl", 3)),
                Some(("shaders/sorted.wgsl", 3)),
                Some(("shaders/sorted.wgsl", 3)),
                Some(("shaders/sorted.wgsl", 5)),
            ]
        );
        assert_eq!(composed.origin(7), None);
        assert_eq!(composed.origin(0), None);
    }

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

    /// Only whole tokens change: `164u`, `x64u`, `resolve_640` and `a_64b` are left as written.
    #[test]
    fn a_size_replaces_whole_tokens_only() {
        assert_eq!(
            super::sized(
                "fn resolve_64() -> array<u32, 64u> { let a = 164u + x64u; resolve_640(a_64b, 64u); }",
                16
            ),
            "fn resolve_16() -> array<u32, 16u> { let a = 164u + x64u; resolve_640(a_64b, 16u); }"
        );
    }

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
