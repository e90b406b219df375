//! The About window: hairlab's version, the adapter in use, the licence, and every registered shadow method's and
//! eye transparency technique's full citation (from `docs/citations.md`) with a button that copies its BibTeX
//! entry (from `docs/citations.bib`). Both files are embedded and looked up by registry name.

use super::HairlabApp;
use crate::methods::registry as methods;
use crate::render::transparency::registry as techniques;

const CITATIONS: &str = include_str!("../../docs/citations.md");
const BIBTEX: &str = include_str!("../../docs/citations.bib");

/// The citation entry anchored at `name` in `markdown`: the text after its `### ` heading up to the next anchor or
/// section, as plain text, one string per paragraph or list item. `None` when there is no such anchor.
fn citation(markdown: &str, name: &str) -> Option<Vec<String>> {
    let anchor = format!("<a id=\"{name}\"></a>");
    let start = markdown.find(&anchor)? + anchor.len();
    let body = &markdown[start..];
    let end = [body.find("<a id="), body.find("\n## ")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(body.len());
    let mut paragraphs: Vec<String> = Vec::new();
    let mut current = String::new();
    for line in body[..end].lines().filter(|l| !l.starts_with('#')) {
        let text = line.trim();
        if text.is_empty() || text.starts_with("- ") {
            if !current.is_empty() {
                paragraphs.push(plain_text(&current));
            }
            current = text.strip_prefix("- ").unwrap_or_default().to_string();
        } else {
            if !current.is_empty() {
                current.push(' ');
            }
            current.push_str(text);
        }
    }
    if !current.is_empty() {
        paragraphs.push(plain_text(&current));
    }
    Some(paragraphs)
}

/// `markdown` without its inline markup: emphasis and code marks dropped, `[text](target)` as its text,
/// `<url>` as the URL.
fn plain_text(markdown: &str) -> String {
    let mut out = String::with_capacity(markdown.len());
    let mut rest = markdown;
    while let Some(c) = rest.chars().next() {
        let link = (c == '[')
            .then(|| rest.find("](").zip(rest.find(')')))
            .flatten()
            .filter(|(close, paren)| close < paren);
        let url = (c == '<').then(|| rest.find('>')).flatten();
        if let Some((close, paren)) = link {
            out.push_str(&rest[1..close]);
            rest = &rest[paren + 1..];
        } else if let Some(close) = url {
            out.push_str(&rest[1..close]);
            rest = &rest[close + 1..];
        } else {
            if c != '*' && c != '`' {
                out.push(c);
            }
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// The BibTeX entry keyed `key` in `bib`, from its `@` to its closing brace. `None` when there is no such entry
/// or its braces do not close.
fn bibtex_entry<'a>(bib: &'a str, key: &str) -> Option<&'a str> {
    let mut offset = 0;
    for line in bib.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        let Some((_, after)) = line.strip_prefix('@').and_then(|l| l.split_once('{')) else {
            continue;
        };
        if after.split(',').next().map(str::trim) != Some(key) {
            continue;
        }
        let mut depth = 0usize;
        for (i, b) in bib[start..].bytes().enumerate() {
            match b {
                b'{' => depth += 1,
                b'}' if depth == 1 => return Some(&bib[start..=start + i]),
                b'}' => depth = depth.checked_sub(1)?,
                _ => {}
            }
        }
        return None;
    }
    None
}

/// One method's or technique's label, its "Copy BibTeX" button and its citation.
fn entry_ui(ui: &mut egui::Ui, name: &str, label: &str) {
    ui.horizontal(|ui| {
        ui.strong(label);
        match bibtex_entry(BIBTEX, name) {
            Some(bib) => {
                if ui
                    .button("Copy BibTeX")
                    .on_hover_text(format!("copy the BibTeX entry '{name}' (docs/citations.bib)"))
                    .clicked()
                {
                    ui.ctx().copy_text(bib.to_string());
                }
            }
            None => {
                ui.weak(format!("no BibTeX entry '{name}'"));
            }
        }
    });
    match citation(CITATIONS, name) {
        Some(paragraphs) => {
            for p in paragraphs {
                ui.label(p);
            }
        }
        None => {
            ui.weak(format!("no citation entry '{name}' in docs/citations.md"));
        }
    }
    ui.add_space(6.0);
}

impl HairlabApp {
    /// The About window (opened from the About button next to Help, and from the Help window).
    pub(super) fn about_window(&mut self, ctx: &egui::Context) {
        let mut open = self.about_open;
        egui::Window::new("About")
            .open(&mut open)
            .default_size([560.0, 560.0])
            // Beside the side panel, not over it.
            .default_pos([340.0, 40.0])
            .show(ctx, |ui| {
                ui.heading(format!("hairlab {}", env!("CARGO_PKG_VERSION")));
                ui.label(format!("Adapter: {}", self.adapter));
                ui.label(format!("Licence: {}", env!("CARGO_PKG_LICENSE")));
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.heading("Shadow methods");
                    for m in methods::all() {
                        entry_ui(ui, m.name(), m.label());
                    }
                    ui.separator();
                    ui.heading("Eye transparency techniques");
                    for t in techniques::all() {
                        entry_ui(ui, t.name(), t.info().label);
                    }
                });
            });
        self.about_open = open;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MARKDOWN: &str = "## Family\n\n<a id=\"one\"></a>\n### `one` — the first\n\nA. Author. *Title*. \
        Venue, 2001.\nDOI [10.1/x](https://doi.org/10.1/x). See [two](#two) and <http://example.org/>.\n\n\
        Second paragraph.\n\n<a id=\"two\"></a>\n### `two` — the second\n\n- First item\n  continued.\n\
        - Second item `code`.\n\n## Other\n\nNot part of two.\n";

    #[test]
    fn about_citation_is_the_plain_text_between_the_heading_and_the_next_anchor() {
        assert_eq!(
            citation(MARKDOWN, "one").unwrap(),
            [
                "A. Author. Title. Venue, 2001. DOI 10.1/x. See two and http://example.org/.",
                "Second paragraph.",
            ]
        );
        assert_eq!(
            citation(MARKDOWN, "two").unwrap(),
            ["First item continued.", "Second item code."]
        );
        assert_eq!(citation(MARKDOWN, "three"), None);
    }

    #[test]
    fn about_plain_text_leaves_unmatched_brackets_alone() {
        assert_eq!(plain_text("a [b] c < d (e)"), "a [b] c < d (e)");
        assert_eq!(plain_text("*x* [y](z) <u>"), "x y u");
    }

    const BIB: &str = "% a comment naming @misc{one, in passing\n\n@article{one,\n  title = {A {Nested} Title},\n  \
        year = {2001}\n}\n\n@misc{one-more,\n  title = {B}\n}\n\n@misc{open,\n  title = {C}\n";

    #[test]
    fn about_bibtex_entry_is_the_whole_balanced_entry_of_that_key() {
        assert_eq!(
            bibtex_entry(BIB, "one"),
            Some("@article{one,\n  title = {A {Nested} Title},\n  year = {2001}\n}")
        );
        assert_eq!(
            bibtex_entry(BIB, "one-more"),
            Some("@misc{one-more,\n  title = {B}\n}")
        );
        assert_eq!(bibtex_entry(BIB, "on"), None);
        assert_eq!(bibtex_entry(BIB, "open"), None, "unclosed braces");
    }

    #[test]
    fn about_every_registered_name_has_a_citation_and_a_bibtex_entry() {
        let names = methods::all()
            .iter()
            .map(|m| m.name())
            .chain(techniques::all().iter().map(|t| t.name()));
        for name in names {
            let text = citation(CITATIONS, name).unwrap_or_else(|| panic!("no citation '{name}'"));
            assert!(!text.is_empty(), "citation '{name}' is empty");
            assert!(
                text.iter().all(|p| !p.contains("](") && !p.contains('`')),
                "citation '{name}' keeps markup: {text:?}"
            );
            let bib = bibtex_entry(BIBTEX, name).unwrap_or_else(|| panic!("no BibTeX entry '{name}'"));
            assert!(
                bib.starts_with('@') && bib.contains(&format!("{{{name},")),
                "{bib}"
            );
        }
    }
}
