//! `hairlab report` (issue 36): the page of a small study parsed with an HTML5 parser (`scraper`). Every `img`,
//! `source`, `a` and `link` reference is a file in the report's folder and no file of it names an `http` or
//! `https` address (the SVG namespace identifier `xmlns="http://www.w3.org/2000/svg"` aside, which SVG needs and
//! nothing fetches); each table's cells are its CSV's text (a rounded cell's in its title); each section is on
//! the page exactly when its data is; `--from` the folders of a finished study gives the same tables; bad input
//! is one error naming the file, with no page written. A file per concern: a fresh study, stopped or exported
//! from the window (`fresh`), and `--from` folders typed here or written by finished runs (`from_folders`). The
//! page's parsing and the self-containment check they share are here.

mod fresh;
mod from_folders;

use scraper::{Html, Selector};
use std::path::Path;

fn page(dir: &Path) -> Html {
    Html::parse_document(&std::fs::read_to_string(dir.join("index.html")).unwrap())
}

fn select<'a>(html: &'a Html, css: &str) -> Vec<scraper::ElementRef<'a>> {
    html.select(&Selector::parse(css).unwrap()).collect()
}

/// The ids of the page's sections, in order.
fn sections(html: &Html) -> Vec<String> {
    select(html, "section")
        .iter()
        .map(|s| s.value().attr("id").unwrap().to_string())
        .collect()
}

/// The table `id`'s header and body cells as text, a rounded cell's whole text (its title) in its place.
fn table(html: &Html, id: &str) -> (Vec<String>, Vec<Vec<String>>) {
    cells(html, id, |c| {
        c.value()
            .attr("title")
            .map_or_else(|| c.text().collect(), str::to_string)
    })
}

/// The table `id`'s header and body cells as the page shows them.
fn shown_table(html: &Html, id: &str) -> (Vec<String>, Vec<Vec<String>>) {
    cells(html, id, |c| c.text().collect())
}

fn cells(
    html: &Html,
    id: &str,
    text: impl Fn(&scraper::ElementRef) -> String,
) -> (Vec<String>, Vec<Vec<String>>) {
    let header = select(html, &format!("table#{id} thead th"))
        .iter()
        .map(|c| c.text().collect())
        .collect();
    let rows = select(html, &format!("table#{id} tbody tr"))
        .iter()
        .map(|r| {
            r.select(&Selector::parse("td").unwrap())
                .map(|c| text(&c))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The CSV file's header and rows, read by the `csv` crate.
fn csv_file(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().iter().map(str::to_string).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// Every reference of the page is a file in `dir`; no file in `dir` names an http(s) address; every image has
/// alt text; every table has header cells.
fn assert_self_contained(dir: &Path) {
    let html = page(dir);
    let mut refs = 0;
    for (css, attr) in [("img", "src"), ("source", "src"), ("a", "href"), ("link", "href")] {
        for e in select(&html, css) {
            let target = e
                .value()
                .attr(attr)
                .unwrap_or_else(|| panic!("a {css} without {attr}"));
            assert!(
                dir.join(target).is_file(),
                "{css} {attr}={target} is not a file in the report"
            );
            refs += 1;
        }
    }
    assert!(refs > 0, "no references checked");
    for img in select(&html, "img") {
        let alt = img.value().attr("alt").unwrap_or("");
        assert!(
            alt.len() > 20,
            "an image without alt text naming it: {:?}",
            img.value()
        );
    }
    for t in select(&html, "table") {
        assert!(
            t.select(&Selector::parse("th").unwrap()).count() > 0,
            "a table without headers"
        );
    }
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            let text = text.replace("xmlns=\"http://www.w3.org/2000/svg\"", "");
            assert!(
                !text.contains("http:") && !text.contains("https:"),
                "{} names an address",
                path.display()
            );
        }
    }
}
