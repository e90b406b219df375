//! hairlab: a workbench for real-time hair self-shadowing methods, side by side on the same strands.
#![allow(clippy::too_many_arguments)]

pub mod animation;
pub mod app;
pub mod bench;
pub mod cli;
pub mod fur;
pub mod gpu;
pub mod io;
pub mod live_shaders;
pub mod measure;
pub mod methods;
pub mod motion;
pub mod pathtrace;
pub mod progress;
pub mod render;
pub mod report;
pub mod rng;
pub mod scene;
pub mod selection;
pub mod settings;
pub mod shaders;
pub mod shading;
pub mod soak;
pub mod transparency;
pub mod visibility;

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::{Path, PathBuf};

    /// Every `.rs` file under `dir`.
    fn rust_files(dir: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        let mut stack = vec![dir.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "rs") {
                    out.push(path);
                }
            }
        }
        out
    }

    /// The code of a source file without comments, string literals and `#[cfg(test)]` modules (tests may import
    /// anything).
    fn code_of(text: &str) -> String {
        let mut out = String::new();
        let mut skip_depth: Option<i32> = None;
        let mut lines = text.lines().peekable();
        while let Some(line) = lines.next() {
            let code = line.split("//").next().unwrap_or("");
            if let Some(depth) = &mut skip_depth {
                *depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
                if *depth <= 0 && code.contains('}') {
                    skip_depth = None;
                }
                continue;
            }
            if line.trim() == "#[cfg(test)]"
                && lines.peek().is_some_and(|l| l.trim_start().starts_with("mod "))
            {
                lines.next();
                skip_depth = Some(1);
                continue;
            }
            // String literals hold no imports ("crate::x" in a message).
            let mut in_string = false;
            for c in code.chars() {
                if c == '"' {
                    in_string = !in_string;
                } else if !in_string {
                    out.push(c);
                }
            }
            out.push('\n');
        }
        out
    }

    /// The top-level modules `code` names through `crate::`, including each item of `crate::{a, b::c}`.
    fn crate_imports(code: &str) -> BTreeSet<String> {
        let ident = |s: &str| -> String {
            s.trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect()
        };
        let mut out = BTreeSet::new();
        for (i, _) in code.match_indices("crate::") {
            let rest = &code[i + "crate::".len()..];
            if let Some(group) = rest.strip_prefix('{') {
                // Items at brace depth 0 of the group, split at its commas.
                let (mut depth, mut start) = (0, 0);
                for (k, c) in group.char_indices() {
                    match c {
                        '{' => depth += 1,
                        '}' if depth == 0 => {
                            out.insert(ident(&group[start..k]));
                            break;
                        }
                        '}' => depth -= 1,
                        ',' if depth == 0 => {
                            out.insert(ident(&group[start..k]));
                            start = k + 1;
                        }
                        _ => {}
                    }
                }
            } else {
                out.insert(ident(rest));
            }
        }
        out.retain(|m| !m.is_empty() && m != "self");
        out
    }

    /// The top-level module graph of `src/`: each module and the modules it imports (with one file that does).
    fn module_graph() -> BTreeMap<String, BTreeMap<String, PathBuf>> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut graph: BTreeMap<String, BTreeMap<String, PathBuf>> = BTreeMap::new();
        for path in rust_files(&root) {
            let rel = path.strip_prefix(&root).unwrap();
            let top = rel.components().next().unwrap().as_os_str().to_string_lossy();
            let top = top.trim_end_matches(".rs").to_string();
            if top == "lib" || top == "main" {
                continue;
            }
            let code = code_of(&std::fs::read_to_string(&path).unwrap());
            let edges = graph.entry(top.clone()).or_default();
            for m in crate_imports(&code) {
                if m != top {
                    edges.entry(m).or_insert_with(|| rel.to_path_buf());
                }
            }
        }
        graph
    }

    #[test]
    fn imports_are_read_through_groups_and_past_comments_and_strings() {
        let code = code_of(
            "use crate::{gpu, scene::Strands, render::{a, b}};\n// crate::app\nlet s = \"crate::bench\";\n\
             #[cfg(test)]\nmod tests {\n    use crate::measure;\n}\nfn f() { crate::io::x(); }\n",
        );
        let got: Vec<String> = crate_imports(&code).into_iter().collect();
        assert_eq!(got, ["gpu", "io", "render", "scene"]);
    }

    /// Arrows between top-level modules run one way: no module reaches itself through the modules it imports.
    #[test]
    fn top_level_modules_import_each_other_one_way() {
        let graph = module_graph();
        assert!(graph.len() > 15, "only {} top-level modules found", graph.len());
        for start in graph.keys() {
            // Depth-first from `start`, keeping the path, to report a circle back to it.
            let mut stack = vec![(start.clone(), vec![start.clone()])];
            let mut seen = BTreeSet::new();
            while let Some((m, path)) = stack.pop() {
                for (next, file) in graph.get(&m).into_iter().flatten() {
                    assert!(
                        next != start,
                        "import circle {} -> {start} (the last import in {})",
                        path.join(" -> "),
                        file.display()
                    );
                    if seen.insert(next.clone()) {
                        let mut p = path.clone();
                        p.push(next.clone());
                        stack.push((next.clone(), p));
                    }
                }
            }
        }
    }

    /// Dependencies run one way: the renderer (and the GPU, scene and CPU-model modules under it) never import
    /// the shadow methods, the settings, the app, the bench or `measure`, which sit above it.
    #[test]
    fn lower_layers_import_nothing_above_them() {
        let graph = module_graph();
        let above = ["methods", "settings", "app", "bench", "measure"];
        let below = [
            "render",
            "gpu",
            "scene",
            "visibility",
            "transparency",
            "fur",
            "motion",
            "shading",
        ];
        for low in below {
            let edges = graph.get(low).unwrap_or_else(|| panic!("no module {low}"));
            for a in above {
                assert!(
                    !edges.contains_key(a),
                    "{low} imports {a} ({})",
                    edges[a].display()
                );
            }
        }
    }
}
