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
pub mod path_scene;
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
    //! The house's rules read from its own source. A file is a module: the crate's files are found from
    //! `lib.rs` down its `mod x;` declarations (`#[cfg(test)]` ones left out: tests may import anything). An
    //! import is a path through `crate::`, `super::`, `self::` or a child module the file declares, resolved to
    //! the longest module prefix it names (`crate::render::maps::storage_entry` is `render/maps.rs`).
    use std::collections::{BTreeMap, BTreeSet, VecDeque};
    use std::path::{Path, PathBuf};

    /// A module path below the crate root (`["render", "caster"]`); the root is empty.
    type ModPath = Vec<String>;

    /// Each module and the modules it imports, with one path (as resolved) that does.
    type Graph = BTreeMap<ModPath, BTreeMap<ModPath, String>>;

    /// `text` with its comments removed and its string and char literals emptied (`""`, `' '`), newlines kept.
    fn strip_literals(text: &str) -> String {
        let c: Vec<char> = text.chars().collect();
        let at = |k: usize| c.get(k).copied();
        let newlines =
            |from: usize, to: usize| c[from..to.min(c.len())].iter().filter(|&&x| x == '\n').count();
        let mut out = String::with_capacity(text.len());
        let mut i = 0;
        while i < c.len() {
            let start = i;
            if c[i] == '/' && at(i + 1) == Some('/') {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
                continue;
            } else if c[i] == '/' && at(i + 1) == Some('*') {
                let mut depth = 0;
                while i < c.len() {
                    if c[i] == '/' && at(i + 1) == Some('*') {
                        (depth, i) = (depth + 1, i + 2);
                    } else if c[i] == '*' && at(i + 1) == Some('/') {
                        (depth, i) = (depth - 1, i + 2);
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
            } else if c[i] == 'r'
                && (i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_'))
                && at(i + 1 + c[i + 1..].iter().take_while(|&&x| x == '#').count()) == Some('"')
            {
                // A raw string, r"…" or r#"…"#.
                let hashes = c[i + 1..].iter().take_while(|&&x| x == '#').count();
                let close: Vec<char> = std::iter::once('"')
                    .chain(std::iter::repeat_n('#', hashes))
                    .collect();
                i += hashes + 2;
                while i < c.len() && !c[i..].starts_with(&close) {
                    i += 1;
                }
                i += close.len();
                out.push_str("\"\"");
            } else if c[i] == '"' {
                i += 1;
                while i < c.len() && c[i] != '"' {
                    i += if c[i] == '\\' { 2 } else { 1 };
                }
                i += 1;
                out.push_str("\"\"");
            } else if c[i] == '\'' && (at(i + 1) == Some('\\') || at(i + 2) == Some('\'')) {
                // A char literal ('x', '\'', '\u{7f}'); a lifetime ('a) has no closing quote two on.
                i += if at(i + 1) == Some('\\') { 3 } else { 2 };
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
                out.push_str("' '");
            } else {
                out.push(c[i]);
                i += 1;
                continue;
            }
            out.extend(std::iter::repeat_n('\n', newlines(start, i)));
        }
        out
    }

    /// The code of a source file ([`strip_literals`]) without its `#[cfg(test)]` items: a `mod tests { … }`
    /// block to its closing brace, a `mod test_support;` declaration to its semicolon.
    fn code_of(text: &str) -> String {
        const TEST_ONLY: &str = "#[cfg(test)]";
        let code = strip_literals(text);
        let mut out = String::with_capacity(code.len());
        let mut rest = code.as_str();
        while let Some(at) = rest.find(TEST_ONLY) {
            out.push_str(&rest[..at]);
            rest = &rest[at + TEST_ONLY.len()..];
            // The item ends at its `;` outside brackets, or at the brace that closes its block.
            let mut depth = 0;
            let mut end = rest.len();
            for (k, ch) in rest.char_indices() {
                match ch {
                    '{' | '(' | '[' => depth += 1,
                    '}' | ')' | ']' => {
                        depth -= 1;
                        if depth == 0 && ch == '}' {
                            end = k + 1;
                            break;
                        }
                    }
                    ';' if depth == 0 => {
                        end = k + 1;
                        break;
                    }
                    _ => {}
                }
            }
            out.extend(rest[..end].chars().filter(|&ch| ch == '\n'));
            rest = &rest[end..];
        }
        out.push_str(rest);
        out
    }

    /// The tokens of `code`: identifiers, `::`, and single punctuation characters.
    fn tokens(code: &str) -> Vec<&str> {
        let mut out = Vec::new();
        let mut rest = code.trim_start();
        while let Some(first) = rest.chars().next() {
            let len = if first.is_alphanumeric() || first == '_' {
                rest.find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(rest.len())
            } else if rest.starts_with("::") {
                2
            } else {
                first.len_utf8()
            };
            out.push(&rest[..len]);
            rest = rest[len..].trim_start();
        }
        out
    }

    fn is_ident(token: &str) -> bool {
        token.starts_with(|c: char| c.is_alphanumeric() || c == '_')
    }

    /// The modules `code` declares as files (`mod x;`).
    fn child_modules(code: &str) -> BTreeSet<String> {
        let t = tokens(code);
        t.windows(3)
            .filter(|w| w[0] == "mod" && w[2] == ";")
            .map(|w| w[1].to_string())
            .collect()
    }

    /// Reads the path (or `use` tree) at `t[i..]` below `prefix` into `out` (`a::{b, c::{d, e as f}}` gives
    /// `a::b`, `a::c::d`, `a::c::e`); returns the index after it.
    fn read_path(t: &[&str], mut i: usize, mut prefix: ModPath, out: &mut Vec<ModPath>) -> usize {
        loop {
            match t.get(i) {
                Some(&"{") => {
                    i += 1;
                    loop {
                        match t.get(i) {
                            Some(&"}") | None => return i + 1,
                            Some(&",") => i += 1,
                            Some(&"as") => i += 2,
                            Some(_) => i = read_path(t, i, prefix.clone(), out).max(i + 1),
                        }
                    }
                }
                Some(&tok) if is_ident(tok) => {
                    if tok != "self" {
                        prefix.push(tok.to_string());
                    }
                    if t.get(i + 1) != Some(&"::") {
                        out.push(prefix);
                        return i + 1;
                    }
                    i += 2;
                }
                Some(&"*") => {
                    out.push(prefix);
                    return i + 1;
                }
                _ => {
                    out.push(prefix);
                    return i;
                }
            }
        }
    }

    /// The crate paths `code`, the file of module `here`, names: through `crate::`, `super::`, `self::` and the
    /// child modules it declares.
    fn paths_in(code: &str, here: &[String]) -> Vec<ModPath> {
        let children = child_modules(code);
        let t = tokens(code);
        let mut out = Vec::new();
        let mut i = 0;
        while i < t.len() {
            let starts = t.get(i + 1) == Some(&"::") && (i == 0 || t[i - 1] != "::");
            let (base, skip) = match t[i] {
                _ if !starts => (None, 1),
                "crate" => (Some(vec![]), 2),
                "self" => (Some(here.to_vec()), 2),
                "super" => {
                    let mut base = here.to_vec();
                    let mut k = i;
                    while t.get(k) == Some(&"super") && t.get(k + 1) == Some(&"::") {
                        base.pop();
                        k += 2;
                    }
                    (Some(base), k - i)
                }
                child if children.contains(child) => (Some(here.to_vec()), 0),
                _ => (None, 1),
            };
            i = match base {
                Some(base) => read_path(&t, i + skip, base, &mut out),
                None => i + skip,
            };
        }
        out
    }

    /// The crate's files by module path, each with its code ([`code_of`]).
    fn crate_files() -> BTreeMap<ModPath, (PathBuf, String)> {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = BTreeMap::new();
        let mut todo = vec![(ModPath::new(), src.join("lib.rs"))];
        while let Some((here, path)) = todo.pop() {
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let code = code_of(&text);
            let dir = here.iter().fold(src.clone(), |d, m| d.join(m));
            for child in child_modules(&code) {
                let flat = dir.join(format!("{child}.rs"));
                let file = if flat.is_file() {
                    flat
                } else {
                    dir.join(&child).join("mod.rs")
                };
                todo.push(([here.clone(), vec![child]].concat(), file));
            }
            let rel = path.strip_prefix(&src).unwrap().to_path_buf();
            files.insert(here, (rel, code));
        }
        files
    }

    /// The import graph between the crate's files, and each module's file (relative to `src/`).
    fn file_graph() -> (BTreeMap<ModPath, PathBuf>, Graph) {
        let files = crate_files();
        let mut graph = Graph::new();
        for (here, (_, code)) in &files {
            let edges = graph.entry(here.clone()).or_default();
            for path in paths_in(code, here) {
                let to = (0..=path.len())
                    .rev()
                    .map(|n| path[..n].to_vec())
                    .find(|m| files.contains_key(m));
                if let Some(to) = to.filter(|to| to != here) {
                    edges
                        .entry(to)
                        .or_insert_with(|| format!("crate::{}", path.join("::")));
                }
            }
        }
        (files.into_iter().map(|(m, (path, _))| (m, path)).collect(), graph)
    }

    /// The graph between top-level modules (folders counting as one, `lib.rs` left out), each import given with
    /// one file and path that make it, from the graph between files (`files` naming each module's file).
    fn module_graph(files: &BTreeMap<ModPath, PathBuf>, graph: &Graph) -> Graph {
        let mut out = Graph::new();
        for (from, edges) in graph.iter().filter(|(m, _)| !m.is_empty()) {
            let top = out.entry(from[..1].to_vec()).or_default();
            for (to, path) in edges.iter().filter(|(to, _)| !to.is_empty() && to[0] != from[0]) {
                let made = || format!("{} uses {path}", files[from].display());
                top.entry(to[..1].to_vec()).or_insert_with(made);
            }
        }
        out
    }

    /// A shortest route `from` ⇝ `to` in `graph` through modules for which `allowed` holds (both ends included).
    fn route(
        graph: &Graph,
        from: &ModPath,
        to: &ModPath,
        allowed: &dyn Fn(&ModPath) -> bool,
    ) -> Option<Vec<ModPath>> {
        let mut came_from: BTreeMap<&ModPath, &ModPath> = BTreeMap::new();
        let mut queue = VecDeque::from([from]);
        while let Some(m) = queue.pop_front() {
            if m == to {
                let mut path = vec![m.clone()];
                while let Some(&prev) = came_from.get(path.last().unwrap()) {
                    path.push(prev.clone());
                }
                path.reverse();
                return Some(path);
            }
            for next in graph.get(m).into_iter().flat_map(|e| e.keys()) {
                if next != from && allowed(next) && !came_from.contains_key(next) {
                    came_from.insert(next, m);
                    queue.push_back(next);
                }
            }
        }
        None
    }

    /// Each import `a -> b` of `graph` that closes a circle, `b` reaching `a` back through modules `m` for which
    /// `inside(a, b, m)` holds, written out along the circle with what makes each step; the shortest first.
    fn circles(
        graph: &Graph,
        name: &dyn Fn(&ModPath) -> String,
        inside: &dyn Fn(&ModPath, &ModPath, &ModPath) -> bool,
    ) -> Vec<String> {
        let mut out = Vec::new();
        for (from, edges) in graph {
            for to in edges.keys() {
                if let Some(back) = route(graph, to, from, &|m| inside(from, to, m)) {
                    let circle: Vec<_> = std::iter::once(from).chain(&back).collect();
                    let steps: Vec<String> = circle
                        .windows(2)
                        .map(|w| format!("{} -> {} ({})", name(w[0]), name(w[1]), graph[w[0]][w[1]]))
                        .collect();
                    out.push(steps.join("; "));
                }
            }
        }
        out.sort_by_key(|c| c.matches(" -> ").count());
        out
    }

    /// The shortest ten of `circles`, one a line, and how many more there are.
    fn listed(circles: &[String]) -> String {
        let more = circles.len().saturating_sub(10);
        let tail = (more > 0).then(|| format!("\n... and {more} more"));
        circles[..circles.len() - more].join("\n") + tail.as_deref().unwrap_or("")
    }

    #[test]
    fn a_test_module_declaration_hides_only_its_own_line() {
        let code =
            code_of("pub mod a;\n#[cfg(test)]\nmod test_support;\nuse crate::gpu;\npub(crate) mod c;\n");
        assert_eq!(code, "pub mod a;\n\n\nuse crate::gpu;\npub(crate) mod c;\n");
        assert_eq!(child_modules(&code).into_iter().collect::<Vec<_>>(), ["a", "c"]);
    }

    #[test]
    fn a_test_block_is_skipped_to_its_closing_brace_past_braces_in_literals() {
        let code = code_of(
            "#[cfg(test)]\nmod tests {\n    fn f() { let s = \"}\"; let c = '}'; /* } */ }\n    use crate::measure;\n\
             }\nuse crate::io;\n#[cfg(test)]\nfn g() -> [u8; 2] { crate::app::x() }\nuse crate::rng;\n",
        );
        let got: Vec<ModPath> = paths_in(&code, &[]);
        assert_eq!(got, [vec!["io"], vec!["rng"]]);
    }

    #[test]
    fn imports_are_read_through_groups_relative_paths_and_past_comments_and_literals() {
        let code = code_of(
            "use crate::{gpu, scene::Strands, render::{a, b as c, self}};\n// crate::app\nlet s = \"crate::bench\";\n\
             let r = r#\"crate::cli\"#;\nlet q = '\"'; /* crate::soak */ let l: &'static str = x;\n\
             use super::sibling::X;\nmod child;\nfn f() { crate::io::x(); child::run(); self::g(); }\n",
        );
        let got: Vec<String> = paths_in(&code, &["top".into(), "mid".into()])
            .iter()
            .map(|p| p.join("::"))
            .collect();
        assert_eq!(
            got,
            [
                "gpu",
                "scene::Strands",
                "render::a",
                "render::b",
                "render",
                "top::sibling::X",
                "io::x",
                "top::mid::child::run",
                "top::mid::g"
            ]
        );
    }

    /// Arrows between files run one way inside each folder: an import between two of the folder's parts (its
    /// files, its subfolders' files) is never closed into a circle by a route that stays in the folder and keeps
    /// off the folder's own file (`mod.rs`), which may use what is in the folder and be used by it.
    #[test]
    fn files_in_a_folder_import_each_other_one_way() {
        let (files, graph) = file_graph();
        assert!(files.len() > 200, "only {} files found", files.len());
        let name = |m: &ModPath| files[m].display().to_string();
        // The folder of import a -> b: the longest module path both lie under (none when one holds the other).
        let inside = |a: &ModPath, b: &ModPath, m: &ModPath| {
            let common = a.iter().zip(b).take_while(|(x, y)| x == y).count();
            common < a.len().min(b.len()) && m.len() > common && m[..common] == a[..common]
        };
        let found = circles(&graph, &name, &inside);
        assert!(
            found.is_empty(),
            "import circles between files:\n{}",
            listed(&found)
        );
    }

    /// Arrows between top-level modules run one way: no module reaches itself through the modules it imports.
    #[test]
    fn top_level_modules_import_each_other_one_way() {
        let (files, graph) = file_graph();
        let graph = module_graph(&files, &graph);
        assert!(graph.len() > 15, "only {} top-level modules found", graph.len());
        let found = circles(&graph, &|m| m.join("::"), &|_, _, _| true);
        assert!(
            found.is_empty(),
            "import circles between top-level modules:\n{}",
            listed(&found)
        );
    }

    /// The top-level modules in layers, lowest first, each with its job: a module imports only modules of the
    /// layers below its own.
    const LAYERS: &[(&str, &[&str])] = &[
        (
            "file reading and writing, progress, random numbers, WGSL composition, visibility functions",
            &["io", "progress", "rng", "shaders", "visibility"],
        ),
        (
            "the scene and its CPU models of shading and transparency",
            &["scene", "shading", "transparency"],
        ),
        ("the GPU device", &["gpu"]),
        ("fur on meshes", &["fur"]),
        (
            "the path tracer's core: fibres, BVH, BSDF, integrator",
            &["pathtrace"],
        ),
        ("the renderer and its light casters", &["render"]),
        (
            "what runs on the renderer: the shadow methods, the hair simulation",
            &["methods", "motion"],
        ),
        (
            "a view's settings, a selection of methods, live shader reload",
            &["settings", "selection", "live_shaders"],
        ),
        (
            "the path tracer's scene from the settings, its Mitsuba export",
            &["path_scene"],
        ),
        ("measurements", &["measure"]),
        (
            "what runs measurements: animations, the bench, the soak",
            &["animation", "bench", "soak"],
        ),
        ("reports", &["report"]),
        ("the command line", &["cli"]),
        ("the window", &["app"]),
    ];

    /// Dependencies run one way: every top-level module has its place in [`LAYERS`] and imports only from the
    /// layers below it (the renderer, the GPU, scene and CPU models never import the shadow methods, the
    /// settings, the app, the bench or `measure`).
    #[test]
    fn lower_layers_import_nothing_above_them() {
        let (files, graph) = file_graph();
        let graph = module_graph(&files, &graph);
        let layer_of: BTreeMap<&str, usize> = LAYERS
            .iter()
            .enumerate()
            .flat_map(|(k, (_, ms))| ms.iter().map(move |m| (*m, k)))
            .collect();
        let unplaced: Vec<&str> = graph
            .keys()
            .map(|m| m[0].as_str())
            .filter(|m| !layer_of.contains_key(m))
            .collect();
        assert!(
            unplaced.is_empty(),
            "top-level modules without a layer in LAYERS: {unplaced:?}"
        );
        for (m, &k) in &layer_of {
            let edges = graph
                .get(&vec![m.to_string()])
                .unwrap_or_else(|| panic!("no module {m}"));
            for (to, made) in edges {
                let j = layer_of[to[0].as_str()];
                assert!(
                    j < k,
                    "{m} ({}) imports {} ({}), a layer not below its own: {made}",
                    LAYERS[k].0,
                    to[0],
                    LAYERS[j].0
                );
            }
        }
    }
}
