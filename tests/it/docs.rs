//! The documentation is complete on its own: every registered shadow method and eye transparency technique has a
//! citation entry in `docs/citations.md` (an `<a id="name"></a>` anchor keyed by its registry name, followed by
//! the entry's text), and the README neither points outside the repository (`../shared`) nor at a `docs/` file
//! that does not exist; `docs/citations.bib` holds one well-formed BibTeX entry per registered name, matching its
//! citation entry.

use hairlab::methods::registry as methods;
use hairlab::render::transparency::registry as techniques;
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
    for file in ["docs/design.md", "docs/citations.md"] {
        assert!(linked.iter().any(|l| l == file), "README.md does not link {file}");
    }
    for l in &linked {
        assert!(
            root().join(l).is_file(),
            "README.md links {l}, which does not exist"
        );
    }
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
