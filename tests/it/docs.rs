//! The documentation is complete on its own: every registered shadow method and eye transparency technique has a
//! citation entry in `docs/citations.md` (an `<a id="name"></a>` anchor keyed by its registry name, followed by
//! the entry's text), and the README neither points outside the repository (`../shared`) nor at a `docs/` file
//! that does not exist.

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
