//! The documentation is complete on its own: every registered shadow method and eye transparency technique has a
//! citation entry in `docs/citations.md` (an `<a id="name"></a>` anchor keyed by its registry name, followed by
//! the entry's text) and a row with its parameters in `docs/guide.md`, which also names every command and preset;
//! `docs/citations.bib` holds one well-formed BibTeX entry per registered name, matching its citation entry. The
//! README is a front door (at most 150 lines, its test command the one `.ci/run` runs), and no page points outside
//! the repository (`../shared`) or at a file or heading that does not exist.

use hairlab::methods::registry as methods;
use hairlab::render::transparency::registry as techniques;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The text of the citation entry anchored at `id`, headings left out: from the anchor to the next anchor or
/// section (`## `). `None` when there is no such anchor; panics when there are two.
fn entry(citations: &str, id: &str) -> Option<String> {
    let anchor = format!("<a id=\"{id}\"></a>");
    let mut found = citations.match_indices(&anchor);
    let (start, _) = found.next()?;
    assert!(
        found.next().is_none(),
        "docs/citations.md: anchor '{id}' appears twice"
    );
    let body = &citations[start + anchor.len()..];
    let end = [body.find("<a id="), body.find("\n## ")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(body.len());
    let text: Vec<&str> = body[..end]
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    Some(text.join(" "))
}

#[test]
fn every_registered_method_and_technique_has_a_citation_entry() {
    assert!(
        !methods::all().is_empty() && !techniques::all().is_empty(),
        "the registries are empty"
    );
    let citations = read(&root().join("docs/citations.md"));
    let names = methods::all()
        .iter()
        .map(|m| ("shadow method", m.name()))
        .chain(techniques::all().iter().map(|t| ("eye technique", t.name())));
    let mut missing = Vec::new();
    for (kind, name) in names {
        match entry(&citations, name) {
            // An anchor with only a heading after it is not an entry: ask for at least a sentence.
            Some(text) if text.len() >= 40 => {}
            Some(text) => missing.push(format!("{kind} '{name}': entry too short ({text:?})")),
            None => missing.push(format!("{kind} '{name}': no <a id=\"{name}\"></a> anchor")),
        }
    }
    assert!(
        missing.is_empty(),
        "docs/citations.md lacks entries:\n{}",
        missing.join("\n")
    );
}

#[test]
fn readme_stays_inside_the_repository() {
    let readme = read(&root().join("README.md"));
    let outside: Vec<_> = readme
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains("../shared"))
        .map(|(i, l)| format!("README.md:{}: {l}", i + 1))
        .collect();
    assert!(
        outside.is_empty(),
        "README.md points outside the repository:\n{}",
        outside.join("\n")
    );
    // Every `docs/…` file the README links to exists, and it links to the design notes and the citations.
    let mut linked = Vec::new();
    for (start, _) in readme.match_indices("](docs/") {
        let target = &readme[start + 2..];
        let end = target.find([')', '#']).expect("an unclosed docs/ link");
        linked.push(target[..end].to_string());
    }
    for file in [
        "docs/guide.md",
        "docs/design.md",
        "docs/citations.md",
        "docs/contributing.md",
    ] {
        assert!(linked.iter().any(|l| l == file), "README.md does not link {file}");
    }
    for l in &linked {
        assert!(
            root().join(l).is_file(),
            "README.md links {l}, which does not exist"
        );
    }
}

#[test]
fn readme_is_a_front_door() {
    let readme = read(&root().join("README.md"));
    let lines = readme.lines().count();
    assert!(
        lines <= 150,
        "README.md has {lines} lines; the front door keeps to 150 (the rest goes to docs/)"
    );
    // CI proves the README: its first test command (up to a closing backtick or the line's end) is what `.ci/run`
    // runs.
    let command = readme
        .lines()
        .find_map(|l| {
            l.find("cargo test")
                .map(|i| l[i..].split('`').next().unwrap_or_default())
        })
        .expect("README.md gives no `cargo test` command");
    let ci = read(&root().join(".ci/run"));
    assert!(
        ci.lines().any(|l| l.trim() == command.trim()),
        "README.md's test command '{command}' is not a line of .ci/run"
    );
}

/// The markdown pages a user reads: the README, every page in `docs/` and the scripts' README.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md"), root().join("scripts/README.md")];
    let docs = std::fs::read_dir(root().join("docs")).expect("docs/");
    let mut in_docs: Vec<PathBuf> = docs
        .map(|e| e.expect("a docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    in_docs.sort();
    pages.extend(in_docs);
    pages
}

/// The lines of `text` outside fenced code blocks, with their line numbers (1-based).
fn prose(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, spaces to `-`, every character but letters, digits, `-` and `_`
/// dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// Every anchor a page defines: its headings' slugs (a repeated heading's `-1`, `-2`, … too) and its
/// `<a id="…"></a>` anchors.
fn anchors(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (_, line) in prose(text) {
        if let Some(heading) = line.strip_prefix('#') {
            let base = slug(heading.trim_start_matches('#'));
            let mut name = base.clone();
            let mut n = 0;
            while !out.insert(name.clone()) {
                n += 1;
                name = format!("{base}-{n}");
            }
        }
        for (i, _) in line.match_indices("<a id=\"") {
            let id = &line[i + 7..];
            out.insert(id[..id.find('"').unwrap_or(id.len())].to_string());
        }
    }
    out
}

#[test]
fn slugs_follow_github() {
    assert_eq!(
        slug(" The truth: a path-traced reference"),
        "the-truth-a-path-traced-reference"
    );
    assert_eq!(
        slug(" Temporal metrics (`src/measure/temporal.rs`, `src/measure/motion.rs`)"),
        "temporal-metrics-srcmeasuretemporalrs-srcmeasuremotionrs"
    );
    let a = anchors("# A\n```\n# not a heading\n```\n## A\n<a id=\"osm\"></a>\n");
    let got: Vec<&str> = a.iter().map(String::as_str).collect();
    assert_eq!(got, ["a", "a-1", "osm"]);
}

#[test]
fn every_relative_link_in_the_docs_resolves() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = read(&page);
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        for (n, line) in prose(&text) {
            if line.contains("../shared") {
                broken.push(format!("{name}:{n}: points outside the repository (../shared)"));
            }
            for (i, _) in line.match_indices("](") {
                let rest = &line[i + 2..];
                let target = &rest[..rest.find([')', ' ']).unwrap_or(rest.len())];
                if target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                let (file, anchor) = target.split_once('#').unwrap_or((target, ""));
                let path = if file.is_empty() {
                    page.clone()
                } else {
                    page.parent().unwrap().join(file)
                };
                if !path.exists() {
                    broken.push(format!("{name}:{n}: {target}: no such file"));
                } else if !anchor.is_empty() && !anchors(&read(&path)).contains(anchor) {
                    broken.push(format!("{name}:{n}: {target}: no such heading or anchor"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// `docs/guide.md`'s table row of a registered name: the line that starts `| `name` |`.
fn guide_row<'a>(guide: &'a str, name: &str) -> Option<&'a str> {
    let start = format!("| `{name}` |");
    guide.lines().find(|l| l.starts_with(&start))
}

#[test]
fn the_guide_lists_every_method_and_technique_with_its_parameters() {
    let guide = read(&root().join("docs/guide.md"));
    let plugins = methods::all()
        .iter()
        .map(|m| (m.name(), m.info().params))
        .chain(techniques::all().iter().map(|t| (t.name(), t.info().params)));
    let mut missing = Vec::new();
    for (name, params) in plugins {
        let Some(row) = guide_row(&guide, name) else {
            missing.push(format!("no row for '{name}'"));
            continue;
        };
        for p in params {
            if !row.contains(&format!("`{}`", p.key)) {
                missing.push(format!("'{name}': parameter '{}' not in its row", p.key));
            }
        }
    }
    assert!(missing.is_empty(), "docs/guide.md:\n{}", missing.join("\n"));
}

#[test]
fn the_guide_names_every_command_and_preset() {
    use clap::CommandFactory;
    // A command may wrap across lines: compare with the text's whitespace runs made one space.
    let text = read(&root().join("docs/guide.md"));
    let guide = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut missing = Vec::new();
    let cli = hairlab::cli::Cli::command();
    for c in cli.get_subcommands().filter(|c| c.get_name() != "help") {
        let subs: Vec<_> = c.get_subcommands().filter(|s| s.get_name() != "help").collect();
        let mut names = vec![format!("hairlab {}", c.get_name())];
        if !subs.is_empty() {
            names = subs
                .iter()
                .map(|s| format!("hairlab {} {}", c.get_name(), s.get_name()))
                .collect();
        }
        missing.extend(names.into_iter().filter(|n| !guide.contains(n.as_str())));
    }
    for entry in std::fs::read_dir(root().join("presets")).expect("presets/") {
        let path = entry.expect("a presets/ entry").path();
        let stem = path.file_stem().unwrap().to_string_lossy();
        if !guide.contains(&format!("`{stem}`")) && !guide.contains(&format!("presets/{stem}.toml")) {
            missing.push(format!("preset {stem}"));
        }
    }
    assert!(
        missing.is_empty(),
        "docs/guide.md does not name:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_code_map_has_a_row_per_top_level_module() {
    let map = read(&root().join("docs/contributing.md"));
    let src = root().join("src");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&src).expect("src/") {
        let path = entry.expect("a src/ entry").path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        // A folder beside a file of its name (`settings/` for `settings.rs`) holds that module's children.
        let cell = if path.is_dir() && !src.join(format!("{name}.rs")).exists() {
            format!("| `{name}/` |")
        } else if name.ends_with(".rs") && name != "lib.rs" && name != "main.rs" {
            format!("| `{name}` |")
        } else {
            continue;
        };
        if !map.lines().any(|l| l.contains(&cell)) {
            missing.push(cell);
        }
    }
    assert!(
        missing.is_empty(),
        "docs/contributing.md's code map has no row for:\n{}",
        missing.join("\n")
    );
}

/// One BibTeX entry: its type, its key and its fields (lower-case name, value without its outer braces).
struct BibEntry {
    kind: String,
    key: String,
    fields: Vec<(String, String)>,
}

impl BibEntry {
    fn field(&self, name: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }
}

/// The entries of a `.bib` file; outside entries only blank lines and `%` comments. Panics naming the entry and
/// the problem on malformed text (unbalanced braces, a field without `=`).
fn bib_entries(bib: &str) -> Vec<BibEntry> {
    let mut entries = Vec::new();
    let mut rest = bib;
    while !rest.is_empty() {
        if rest.starts_with('@') {
            let (entry, after) = bib_entry(rest);
            entries.push(entry);
            rest = after;
            continue;
        }
        let line = rest.split('\n').next().unwrap_or_default();
        assert!(
            line.trim().is_empty() || line.starts_with('%'),
            "docs/citations.bib: text outside an entry: {line:?}"
        );
        rest = &rest[(line.len() + 1).min(rest.len())..];
    }
    entries
}

/// The entry at the start of `text` (`@type{key, name = {value}, ...}`) and the text after it.
fn bib_entry(text: &str) -> (BibEntry, &str) {
    let head = text.split('\n').next().unwrap_or_default();
    let (kind, key) = head[1..]
        .split_once('{')
        .and_then(|(kind, rest)| Some((kind, rest.split_once(',')?.0)))
        .unwrap_or_else(|| panic!("docs/citations.bib: malformed entry head {head:?}"));
    let key = key.trim().to_string();
    let mut rest = &text[text.find(',').expect("a comma after the key") + 1..];
    let mut fields = Vec::new();
    loop {
        rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix('}') {
            let kind = kind.trim().to_lowercase();
            return (BibEntry { kind, key, fields }, after);
        }
        let eq = rest.find('=').unwrap_or_else(|| {
            panic!("docs/citations.bib, entry '{key}': a field without '=' or no closing brace")
        });
        let name = rest[..eq].trim().to_lowercase();
        assert!(
            !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric()),
            "docs/citations.bib, entry '{key}': bad field name {name:?}"
        );
        let value = rest[eq + 1..].trim_start();
        let (value, after) = if value.starts_with('{') {
            braced(value).unwrap_or_else(|| {
                panic!("docs/citations.bib, entry '{key}', field '{name}': unbalanced braces")
            })
        } else {
            let end = value.find([',', '}']).unwrap_or(value.len());
            (value[..end].trim(), &value[end..])
        };
        fields.push((name, value.to_string()));
        let after = after.trim_start();
        rest = after.strip_prefix(',').unwrap_or(after);
    }
}

/// The contents of the braced group at the start of `text` and the text after it; `None` when it does not close.
fn braced(text: &str) -> Option<(&str, &str)> {
    let mut depth = 0;
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some((&text[1..i], &text[i + 1..]));
                }
            }
            _ => {}
        }
    }
    None
}

/// The DOIs a citation entry gives (`DOI [10.…](…)`).
fn dois(text: &str) -> Vec<&str> {
    text.match_indices("DOI [")
        .filter_map(|(i, m)| text[i + m.len()..].split(']').next())
        .collect()
}

#[test]
fn bib_parser_rejects_unbalanced_braces() {
    let result = std::panic::catch_unwind(|| bib_entries("@misc{k,\n  title = {A {b}\n}\n"));
    assert!(result.is_err(), "an unclosed title was accepted");
    let ok = bib_entries("% c\n\n@misc{k,\n  title = {A {b} c},\n  year = 2001\n}\n");
    assert_eq!(ok.len(), 1);
    assert_eq!((ok[0].kind.as_str(), ok[0].key.as_str()), ("misc", "k"));
    assert_eq!(ok[0].field("title"), Some("A {b} c"));
    assert_eq!(ok[0].field("year"), Some("2001"));
}

#[test]
fn every_registered_method_and_technique_has_one_bibtex_entry() {
    let citations = read(&root().join("docs/citations.md"));
    let entries = bib_entries(&read(&root().join("docs/citations.bib")));
    let names: Vec<&str> = methods::all()
        .iter()
        .map(|m| m.name())
        .chain(techniques::all().iter().map(|t| t.name()))
        .collect();
    let kinds = [
        "article",
        "inproceedings",
        "phdthesis",
        "mastersthesis",
        "techreport",
        "misc",
    ];
    let mut problems = Vec::new();
    for name in &names {
        let found: Vec<_> = entries.iter().filter(|e| e.key == *name).collect();
        let [e] = found[..] else {
            problems.push(format!("'{name}': {} entries", found.len()));
            continue;
        };
        let text = entry(&citations, name).unwrap_or_default();
        if !kinds.contains(&e.kind.as_str()) {
            problems.push(format!("'{name}': entry type @{}", e.kind));
        }
        if e.field("title").is_none_or(str::is_empty) {
            problems.push(format!("'{name}': no title"));
        }
        match e.field("year") {
            Some(year) if !text.contains(year) => {
                problems.push(format!("'{name}': year {year} is not in its citations.md entry"))
            }
            Some(_) => {}
            // No paper, or a year that could not be confirmed: the note says so.
            None if e.field("note").is_none() => problems.push(format!("'{name}': no year and no note")),
            None => {}
        }
        let given = dois(&text);
        match e.field("doi") {
            Some(doi) if !given.contains(&doi) => problems.push(format!(
                "'{name}': doi {doi} is not one citations.md gives ({given:?})"
            )),
            None if !given.is_empty() => {
                problems.push(format!("'{name}': no doi, citations.md gives {given:?}"))
            }
            _ => {}
        }
    }
    for e in &entries {
        if !names.contains(&e.key.as_str()) && entry(&citations, &e.key).is_none() {
            problems.push(format!(
                "'{}': neither a registered name nor a citations.md entry",
                e.key
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "docs/citations.bib:\n{}",
        problems.join("\n")
    );
}
