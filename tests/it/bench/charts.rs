//! The Pareto front on hand-made points, and the PNG and SVG charts of a hand-made chart: points where the data
//! puts them, one SVG circle per point and the names.

use hairlab::bench::{chart, pareto_front};

#[test]
fn pareto_front_keeps_the_points_nothing_beats() {
    let points = [
        [1.0, 5.0],      // 0: fastest of those with error 5
        [2.0, 3.0],      // 1
        [3.0, 4.0],      // 2: beaten by 1 on both
        [4.0, 1.0],      // 3
        [0.0, 9.0],      // 4: 0 ms, the worst error: still nothing is faster
        [5.0, 1.0],      // 5: as accurate as 3 but slower
        [2.0, 3.5],      // 6: as fast as 1 but less accurate
        [f64::NAN, 0.0], // 7: not measured
        [6.0, 0.0],      // 8: the most accurate
    ];
    assert_eq!(pareto_front(&points), [4, 0, 1, 3, 8]);
    // Exact duplicates do not beat each other.
    assert_eq!(pareto_front(&[[1.0, 1.0], [1.0, 1.0], [2.0, 2.0]]), [0, 1]);
    assert!(pareto_front(&[]).is_empty());
}

/// A chart with three red points on linear axes at (2, 1), (6, 3), (10, 2), and a line.
fn three_point_chart(name: &str) -> chart::Chart {
    let point = |x: f64, y: f64| chart::Point {
        x,
        y,
        label: format!("p{x}"),
        row: None,
    };
    chart::Chart {
        title: "Three points × 2".to_string(),
        notes: vec!["a note with Δ and σ²".to_string()],
        x: chart::Axis {
            label: "x".to_string(),
            scale: chart::Scale::Linear,
        },
        y: chart::Axis {
            label: "y".to_string(),
            scale: chart::Scale::Linear,
        },
        series: vec![
            chart::Series {
                name: name.to_string(),
                color: RED,
                mark: chart::Mark::Points,
                points: vec![point(2.0, 1.0), point(6.0, 3.0), point(10.0, 2.0)],
            },
            chart::Series {
                name: String::new(),
                color: [0, 0, 255],
                mark: chart::Mark::Line,
                points: vec![point(2.0, 0.5), point(10.0, 0.5)],
            },
        ],
        front: None,
    }
}

const RED: [u8; 3] = [214, 39, 40];

/// Centroids of the 4-connected groups of pixels of exactly `color`, left to right.
fn blobs(img: &image::RgbImage, color: [u8; 3]) -> Vec<(f64, f64, usize)> {
    let (w, h) = img.dimensions();
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for start in 0..w * h {
        if seen[start as usize] || img.get_pixel(start % w, start / w).0 != color {
            continue;
        }
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0);
        let mut stack = vec![start];
        seen[start as usize] = true;
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            sx += x as f64;
            sy += y as f64;
            n += 1;
            let next = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ];
            for j in next.into_iter().flatten() {
                if !seen[j as usize] && img.get_pixel(j % w, j / w).0 == color {
                    seen[j as usize] = true;
                    stack.push(j);
                }
            }
        }
        out.push((sx / n as f64, sy / n as f64, n));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

#[test]
fn png_chart_draws_the_points_where_the_data_puts_them() {
    let png = chart::png(&three_point_chart(""), 600, 400).unwrap();
    let img = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (600, 400));
    assert_eq!(img.get_pixel(2, 2).0, [255, 255, 255], "background");
    // Exactly three red discs (the series has no name, so no legend marker).
    let b = blobs(&img, RED);
    assert_eq!(b.len(), 3, "{b:?}");
    assert!(b.iter().all(|&(_, _, n)| n >= 50), "discs of radius 5: {b:?}");
    // x 2, 6, 10: equally spaced; y 1, 3, 2: the second highest, the first lowest, the third halfway.
    let (dx1, dx2) = (b[1].0 - b[0].0, b[2].0 - b[1].0);
    assert!(dx1 > 50.0 && (dx1 - dx2).abs() <= 1.5, "{b:?}");
    let (rise1, rise2) = (b[0].1 - b[1].1, b[0].1 - b[2].1);
    assert!(rise1 > 50.0 && (rise1 - 2.0 * rise2).abs() <= 1.5, "{b:?}");
    // The fit line is drawn in its colour, and there is text and axes in dark ink.
    assert!(img.pixels().filter(|p| p.0 == [0, 0, 255]).count() > 100);
    assert!(img.pixels().filter(|p| p.0.iter().all(|c| *c < 100)).count() > 500);
}

#[test]
fn svg_chart_is_xml_with_one_circle_per_point_and_the_names() {
    use quick_xml::events::Event;
    let svg = chart::svg(&three_point_chart("red series"), 600, 400).unwrap();
    let mut reader = quick_xml::Reader::from_str(&svg);
    let (mut root, mut red_circles, mut texts) = (None, 0, Vec::new());
    let mut in_text = false;
    loop {
        match reader.read_event().unwrap() {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                root.get_or_insert(name.clone());
                let fill = e
                    .attributes()
                    .flatten()
                    .find(|a| a.key.as_ref() == b"fill")
                    .map(|a| a.value.to_vec());
                if name == "circle" && fill.as_deref() == Some(b"#D62728") {
                    red_circles += 1;
                }
                in_text = name == "text";
            }
            Event::Text(t) if in_text => texts.push(t.decode().unwrap().trim().to_string()),
            Event::End(_) => in_text = false,
            _ => {}
        }
    }
    assert_eq!(root.as_deref(), Some("svg"));
    // Three points and the legend's marker.
    assert_eq!(red_circles, 4);
    for t in ["red series", "Three points × 2", "a note with Δ and σ²", "x", "y"] {
        assert!(texts.iter().any(|s| s == t), "no text {t:?} in {texts:?}");
    }
}
