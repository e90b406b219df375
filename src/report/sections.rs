//! The page's sections, each written only where its data exists: the scene and the machine, speed against
//! accuracy (the bench's chart and its whole `results.csv`), transparency (its chart and `transparency.csv`),
//! and motion (`motion_summary.csv` and a per-frame map-error chart drawn by the bench's chart writer). Every
//! file a section names is in the report's folder; [`super::write`] puts it there.

use super::Meta;
use super::data::{Motion, Shadows, Study, Transparency, Truth};
use super::page::{facts, figure, link, section, sortable_table};
use crate::bench::chart::{self, Axis, Chart, Point, Scale};
use anyhow::Result;
use serde_json::Value;

/// The folder of each part's files inside the report.
pub const SHADOWS_DIR: &str = "data/shadows";
pub const TRANSPARENCY_DIR: &str = "data/transparency";
pub const MOTION_DIR: &str = "data/motion";
/// The per-frame map-error chart the motion section draws.
pub const MOTION_CHART: &str = "motion_map_error_per_frame.svg";

/// The value at `path` of `json` as a reader is shown it (a number [`super::page::shown`]).
fn json_text(json: &Option<Value>, path: &[&str]) -> Option<String> {
    let mut v = json.as_ref()?;
    for key in path {
        v = v.get(key)?;
    }
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Null => None,
        Value::Number(n) => Some(super::page::shown(
            path.last().copied().unwrap_or(""),
            &n.to_string(),
        )),
        other => Some(other.to_string()),
    }
}

/// The scene: the thumbnail and what the bench's and the transparency bench's JSON say of it.
pub fn scene(study: &Study, meta: &Meta) -> Option<String> {
    let shadows = study.shadows.as_ref().map(|s| &s.json);
    let eye = study.transparency.as_ref().map(|t| &t.json);
    let mut pairs: Vec<(&str, String)> = Vec::new();
    if let Some(p) = &meta.preset {
        pairs.push(("preset", p.clone()));
    }
    if let Some(j) = shadows {
        for (name, key) in [
            ("strands", "strands"),
            ("segments", "segments"),
            ("light map size (texels a side)", "map_resolution"),
            ("light-map fragments", "fragments"),
            ("occupied texels", "occupied_texels"),
            ("light depth complexity, max", "max_depth_complexity"),
            ("light depth complexity, mean", "mean_depth_complexity"),
        ] {
            if let Some(v) = json_text(j, &["scene", key]) {
                pairs.push((name, v));
            }
        }
    }
    if let Some(j) = eye {
        for (name, key) in [
            ("hair pixels (eye view)", "hair_pixels"),
            ("eye depth complexity, max", "max_depth_complexity"),
            ("eye depth complexity, mean", "mean_depth_complexity"),
        ] {
            if let Some(v) = json_text(j, &[key]) {
                pairs.push((name, v));
            }
        }
    }
    if let Some(l) = &meta.light {
        pairs.push(("light", l.clone()));
    }
    let histogram = study
        .shadows
        .as_ref()
        .is_some_and(|s| s.depth_complexity.is_some());
    if pairs.is_empty() && meta.thumbnail.is_none() && !histogram {
        return None;
    }
    let mut content = String::new();
    if let Some(t) = &meta.thumbnail {
        content += &figure(
            t,
            "The study's scene rendered from the preset's camera with its default shadow method",
            "The scene (frame 0, the preset's camera and shadow method).",
        );
    }
    if study
        .shadows
        .as_ref()
        .is_some_and(|s| s.depth_complexity.is_some())
    {
        content += &figure(
            &format!("{SHADOWS_DIR}/{}", super::curves::HISTOGRAM_SVG),
            "Line chart of the light map's occupied texels by their depth complexity (fragments per texel)",
            "Light depth complexity: occupied texels by the number of fragments in them.",
        );
    }
    content += &facts(&pairs);
    Some(section("scene", "Scene", &content))
}

/// The machine: the adapter the measurements ran on, the version, and the command that reproduces the page.
pub fn machine(study: &Study, meta: &Meta) -> String {
    let mut pairs: Vec<(&str, String)> = Vec::new();
    if let Some(a) = &meta.adapter {
        pairs.push(("adapter", a.name.clone()));
        pairs.push(("driver", a.driver.clone()));
        pairs.push(("backend", a.backend.clone()));
    }
    let devices = [
        study
            .shadows
            .as_ref()
            .and_then(|s| json_text(&s.json, &["device"])),
        study
            .transparency
            .as_ref()
            .and_then(|t| json_text(&t.json, &["device"])),
    ];
    for d in devices.into_iter().flatten() {
        if !pairs.iter().any(|(_, v)| *v == d) {
            pairs.push(("measured on", d));
        }
    }
    pairs.push(("hairlab version", meta.version.to_string()));
    let mut content = facts(&pairs);
    content += &format!(
        "<p>Reproduce this page:</p>\n<p><code>{}</code></p>\n",
        super::page::escape(&meta.command)
    );
    section("machine", "Machine and command", &content)
}

/// The files of a part, linked.
fn file_links(dir: &str, names: &[&str]) -> String {
    let links: Vec<String> = names.iter().map(|n| link(&format!("{dir}/{n}"), n)).collect();
    format!("<p>Files: {}</p>\n", links.join(", "))
}

fn present_names(dir: &std::path::Path, names: &[&'static str]) -> Vec<&'static str> {
    names.iter().copied().filter(|n| dir.join(n).is_file()).collect()
}

/// Speed against accuracy: the bench's chart (Pareto front marked) and the whole `results.csv`, sortable.
pub fn shadows(s: &Shadows) -> String {
    let mut content = String::new();
    if s.chart.is_some() {
        content += &figure(
            &format!("{SHADOWS_DIR}/speed_vs_accuracy.svg"),
            "Chart of each shadow-method configuration's GPU time per frame against its map error, the Pareto \
             front connected",
            "GPU time against accuracy, the Pareto front connected (the bench's chart).",
        );
    }
    let front: Vec<&str> = (0..s.results.rows.len())
        .filter(|&i| s.results.text(i, "pareto") == Some("true"))
        .filter_map(|i| s.results.text(i, "label"))
        .collect();
    if !front.is_empty() {
        content += &format!(
            "<p>Pareto front (table order): {}</p>\n",
            super::page::escape(&front.join(", "))
        );
    }
    content += &sortable_table(
        "results",
        "results.csv: every configuration (click a header to sort)",
        &s.results,
    );
    content += &file_links(
        SHADOWS_DIR,
        &present_names(
            &s.dir,
            &[
                "results.csv",
                "results.json",
                "speed_vs_accuracy.svg",
                "speed_vs_accuracy.png",
            ],
        ),
    );
    section("speed-accuracy", "Speed against accuracy", &content)
}

/// Transparency: the techniques' chart and their table.
pub fn transparency(t: &Transparency) -> String {
    let mut content = String::new();
    if t.chart.is_some() {
        content += &figure(
            &format!("{TRANSPARENCY_DIR}/transparency_speed_vs_accuracy.svg"),
            "Chart of each eye transparency technique's GPU time against its hair-pixel RMSE, the Pareto front \
             connected",
            "Eye transparency: GPU time against hair-pixel RMSE (the bench's chart).",
        );
    }
    if let (Some(measured), Some(paper)) = (
        json_text(&t.json, &["peel_over_occupancy"]),
        json_text(&t.json, &["paper_peel_over_occupancy"]),
    ) {
        content += &format!(
            "<p>t(depth peel) / t(occupancy order): {} measured; the paper's Fig. 2: {}.</p>\n",
            super::page::escape(&measured),
            super::page::escape(&paper)
        );
    }
    content += &super::images::fig2(t, &format!("{TRANSPARENCY_DIR}/{}", super::data::IMAGES));
    content += &sortable_table(
        "transparency",
        "transparency.csv: every technique configuration",
        &t.table,
    );
    content += &file_links(
        TRANSPARENCY_DIR,
        &present_names(
            &t.dir,
            &[
                "transparency.csv",
                "transparency.json",
                "transparency_speed_vs_accuracy.svg",
                "transparency_speed_vs_accuracy.png",
            ],
        ),
    );
    section("transparency", "Eye transparency", &content)
}

/// The per-frame map error of every configuration of `m`, one line each, as the bench's chart model.
pub fn motion_chart(m: &Motion) -> Chart {
    let f = &m.frames;
    let mut lines: Vec<(String, Vec<Point>)> = Vec::new();
    for i in 0..f.rows.len() {
        let (Some(config), Some(frame), Some(error)) = (
            f.text(i, "config"),
            f.number(i, "frame"),
            f.number(i, "map_error"),
        ) else {
            continue;
        };
        let point = Point {
            x: frame,
            y: error,
            label: String::new(),
            row: Some(i),
        };
        match lines.iter_mut().find(|(name, _)| name == config) {
            Some((_, points)) => points.push(point),
            None => lines.push((config.to_string(), vec![point])),
        }
    }
    let series = lines
        .into_iter()
        .flat_map(|(name, points)| {
            let method = name.split(':').next().unwrap_or(&name).to_string();
            super::curves::named_line(name, chart::method_color(&method), points)
        })
        .collect();
    Chart {
        title: "Map error per frame".to_string(),
        notes: vec!["mean |ΔV| per occupied texel against the exact reference, each frame".to_string()],
        x: Axis {
            label: "frame".to_string(),
            scale: Scale::Linear,
        },
        y: Axis {
            label: "map error".to_string(),
            scale: Scale::Linear,
        },
        series,
        front: None,
    }
}

/// The motion chart's SVG.
pub fn motion_chart_svg(m: &Motion) -> Result<String> {
    let (w, h) = chart::CHART_SIZE;
    chart::svg(&motion_chart(m), w, h)
}

/// Motion: the summary table (flicker, pop rate, map error) and the per-frame chart.
pub fn motion(m: &Motion) -> String {
    let mut content = figure(
        &format!("{MOTION_DIR}/{MOTION_CHART}"),
        "Line chart of each configuration's light-map error against the exact reference, frame by frame over \
         the motion",
        "Map error per frame over the motion.",
    );
    content += &super::animations::figures(m, &format!("{MOTION_DIR}/{}", super::data::ANIMATIONS));
    content += &sortable_table(
        "motion",
        "motion_summary.csv: flicker, pop rate and map error per configuration",
        &m.summary,
    );
    content += &file_links(
        MOTION_DIR,
        &present_names(
            &m.dir,
            &["motion_summary.csv", "motion_frames.csv", "motion_point.csv"],
        ),
    );
    section("motion", "Motion", &content)
}

/// The path-traced truth: its image and each configuration's error decomposed under each shading model.
pub fn truth(t: &Truth) -> String {
    let mut content = format!(
        "<p>Each configuration's error against the path-traced image, split by physical effect under each \
         shading model (hairlab's docs/truth.md): \
         one chain of images turns the real-time model's effects on one at a time — <em>mesh bounce</em> (the \
         light the meshes bounce after the first hit dropped), <em>multiple scattering</em> (every event \
         against one), <em>shadowing</em> (the fibres' traced shadow against the reference's light map), \
         <em>shading</em> (Chiang et al. 2016's fibre BSDF against the raster's lobes and light, one event), \
         <em>scattered light</em> (the raster's stand-ins for the light beyond one event: ambient, probe, \
         forward and multiple-scattering terms), <em>eye coverage</em> (round fibres against blended strand \
         fragments), <em>method</em> (the exact light map against the method's) — and the <em>total</em>. Each \
         step's RMSE of sRGB (the path-traced images' noise removed), its ratio of mean linear luminance (later \
         over earlier; the ratios multiply to the total's) and its coarse RMSE (over {b} × {b}-pixel blocks, the \
         scale of locks) are taken over the hair and over the shadow receivers apart, from the path tracer's \
         first hits; <code>hair_sd</code> is how far the truth's noise moves the hair's RMSE (from the figures \
         its two renders give apart), and the chart's note sets the configurations' spread against it.</p>\n",
        b = crate::measure::decompose::BLOCK,
    );
    if t.image.is_some() {
        content += &figure(
            &format!("{SHADOWS_DIR}/{}", super::data::TRUTH_PNG),
            "The scene path-traced: the hair as fibres under Chiang et al.'s BSDF with multiple scattering",
            "The path-traced truth (the measurement's size and render.spp samples per pixel).",
        );
    }
    if t.chart.is_some() {
        content += &figure(
            &format!("{SHADOWS_DIR}/{}", super::data::TRUTH_CHART_FILES[1]),
            "GPU time per frame against each configuration's image RMSE against the path-traced image",
            "Speed against accuracy judged by the path-traced truth (the decomposition's total over the hair, \
             under the settings' shading model), its Pareto front ringed.",
        );
    }
    content += &sortable_table(
        "decomposition",
        "decomposition.csv: each configuration's error by effect under each shading model (click a header to sort)",
        &t.table,
    );
    content += &file_links(SHADOWS_DIR, &[super::data::DECOMPOSITION_CSV]);
    section("truth", "Against the path-traced truth", &content)
}
