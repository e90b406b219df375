//! The bench, a file per concern: the Pareto front and the charts on hand-made points (`charts`), small real bench
//! runs through the CLI binary (`runs`), the scaling run (`scaling`), Ctrl-C during a run (`sigint`), and the Bench
//! window driven headless (`window`). The tiny scene and the CSV readers they share are here.

mod charts;
mod runs;
mod scaling;
mod sigint;
mod window;

use std::path::Path;

/// The tiny scene of the CLI runs: 200 strands, a 64² light map.
const TINY: &[&str] = &[
    "--set",
    "scene.generator.strands=200",
    "--set",
    "render.map_resolution=64",
];

/// Splits one CSV line into fields (quoted fields may hold commas and doubled quotes).
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            _ => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// The CSV as (header, rows).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = csv_fields(lines.next().expect("a header"));
    let rows: Vec<Vec<String>> = lines.map(csv_fields).collect();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
    }
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}
