//! USD BasisCurves stages (issue 20): a stage written by hand loads with the counts, bounds and thicknesses derived
//! by hand below; `.hair` → `.usda` → `.hair` keeps every array; one groom as `.usda`, `.tfx` and `.data` gives the
//! same strands; bad stages are refused naming the file, the prim and the attribute.

use glam::Vec3;
use hairlab::scene::Strands;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::scene::load::{load_scene, save_strands};
use hairlab::scene::usd::{read_usd_file, read_usd_frames};
use hairlab::scene::usda_write::write_usda;

/// Z-up, centimetres, 12 time codes per second. `/Groom` translates by (10, 0, 0) after scaling by 2, so a local
/// point `p` is at `2p + (10, 0, 0)` in the stage, then `(x, y, z)` → `(x, z, −y)` (Z-up to Y-up) and × 0.01
/// (centimetres to metres). Widths scale by 2 × 0.01 = 0.02.
/// - `Linear`: linear, counts [3, 2], vertex widths, uniform colour (red, green).
/// - `Bezier`: nothing authored but counts and points (the schema's fallbacks: cubic bezier nonperiodic), one
///   curve of 4 control points, time-sampled at 0 and 2 (moved by +1 in x at 2), constant width 0.5.
/// - `Bspline`: cubic bspline, one curve of 5 control points (2 spans), varying widths [0.2, 0.4, 0.2], constant
///   opacity 0.5.
pub(crate) const HAND_STAGE: &str = r#"#usda 1.0
(
    upAxis = "Z"
    metersPerUnit = 0.01
    timeCodesPerSecond = 12
)

def Xform "Groom"
{
    double3 xformOp:translate = (10, 0, 0)
    float3 xformOp:scale = (2, 2, 2)
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]

    def BasisCurves "Linear"
    {
        uniform token type = "linear"
        int[] curveVertexCounts = [3, 2]
        point3f[] points = [(0, 0, 0), (0, 0, 1), (0, 0, 2), (1, 0, 0), (1, 0, 3)]
        float[] widths = [0.5, 0.25, 0.125, 1, 1] (
            interpolation = "vertex"
        )
        color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0)] (
            interpolation = "uniform"
        )
    }

    def BasisCurves "Bezier"
    {
        int[] curveVertexCounts = [4]
        point3f[] points.timeSamples = {
            0: [(0, 0, 0), (0, 8, 4), (0, 8, 8), (0, 0, 12)],
            2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)],
        }
        float[] widths = [0.5] (
            interpolation = "constant"
        )
    }

    def BasisCurves "Bspline"
    {
        uniform token type = "cubic"
        uniform token basis = "bspline"
        int[] curveVertexCounts = [5]
        point3f[] points = [(0, 0, 0), (6, 0, 0), (12, 6, 0), (18, 0, 0), (24, 0, 0)]
        float[] widths = [0.2, 0.4, 0.2] (
            interpolation = "varying"
        )
        float[] primvars:displayOpacity = [0.5] (
            interpolation = "constant"
        )
    }
}
"#;

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-6 * (1.0 + b.abs())
}

fn assert_points(got: &[Vec3], want: &[[f32; 3]], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            close(g.x, w[0]) && close(g.y, w[1]) && close(g.z, w[2]),
            "{what} point {i}: {g} != {w:?}"
        );
    }
}

fn assert_floats(got: &[f32], want: &[f32], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(close(*g, *w), "{what} {i}: {g} != {w}");
    }
}

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn hand_written_stage_loads_with_hand_computed_values() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "hand.usda", HAND_STAGE);
    let f = read_usd_file(&path).unwrap();
    assert_eq!((f.up_axis, f.meters_per_unit), ('Z', 0.01));
    assert_eq!(f.time_codes, [0.0, 2.0]);
    assert_eq!(f.time_codes_per_second, 12.0);
    let s = &f.strands;
    // Linear: 3 + 2 points; Bezier: 1 span at 4 segments = 5 points; Bspline: 2 spans = 9 points.
    assert_eq!(s.counts, [3, 2, 5, 9]);
    assert_eq!(
        (s.strand_count(), s.point_count(), s.segment_count()),
        (4, 19, 15)
    );

    // Linear, local (0,0,z) → stage (10, 0, 2z) → Y-up (10, 2z, 0) → metres (0.1, 0.02z, 0).
    assert_points(
        &s.points[0..5],
        &[
            [0.1, 0.0, 0.0],
            [0.1, 0.02, 0.0],
            [0.1, 0.04, 0.0],
            [0.12, 0.0, 0.0],
            [0.12, 0.06, 0.0],
        ],
        "Linear",
    );
    // Bezier at time 0, control y = [0, 8, 8, 0], z = [0, 4, 8, 12]: y(t) = 24t(1 − t), z(t) = 12t, so at t = 0,
    // ¼, ½, ¾, 1 the local points are (0, 0, 0), (0, 4.5, 3), (0, 6, 6), (0, 4.5, 9), (0, 0, 12); stage (10, 2y,
    // 2z); Y-up (10, 2z, −2y); metres (0.1, 0.02z, −0.02y).
    assert_points(
        &s.points[5..10],
        &[
            [0.1, 0.0, 0.0],
            [0.1, 0.06, -0.09],
            [0.1, 0.12, -0.12],
            [0.1, 0.18, -0.09],
            [0.1, 0.24, 0.0],
        ],
        "Bezier",
    );
    // Bspline, control x = [0, 6, 12, 18, 24] (linear, so x = 6(1 + span + t)), y = [0, 0, 6, 0, 0]: span 0 is 6·B2(t),
    // span 1 is 6·B1(t), with B2(¼) = 1.890625/6, B2(½) = 2.875/6, B2(¾) = 3.671875/6, B2(1) = 4/6 (and B1 the
    // mirror): y = 1, 1.890625, 2.875, 3.671875, 4, 3.671875, 2.875, 1.890625, 1. Metres: ((2x + 10)/100, 0, −2y/100).
    assert_points(
        &s.points[10..19],
        &[
            [0.22, 0.0, -0.02],
            [0.25, 0.0, -0.0378125],
            [0.28, 0.0, -0.0575],
            [0.31, 0.0, -0.0734375],
            [0.34, 0.0, -0.08],
            [0.37, 0.0, -0.0734375],
            [0.40, 0.0, -0.0575],
            [0.43, 0.0, -0.0378125],
            [0.46, 0.0, -0.02],
        ],
        "Bspline",
    );
    // Widths × 0.02: Linear vertex [0.5, 0.25, 0.125, 1, 1]; Bezier constant 0.5; Bspline varying 0.2 → 0.4 → 0.2
    // in quarter steps.
    assert_floats(
        s.thickness.as_ref().unwrap(),
        &[
            0.01, 0.005, 0.0025, 0.02, 0.02, //
            0.01, 0.01, 0.01, 0.01, 0.01, //
            0.004, 0.005, 0.006, 0.007, 0.008, 0.007, 0.006, 0.005, 0.004,
        ],
        "thickness",
    );
    // Colour only on Linear (uniform: red then green), white where a prim has none; opacity only on Bspline.
    let color = s.color.as_ref().unwrap();
    assert_eq!(color[0..3], [Vec3::X; 3]);
    assert_eq!(color[3..5], [Vec3::Y; 2]);
    assert!(color[5..].iter().all(|&c| c == Vec3::ONE));
    let alpha = s.alpha.as_ref().unwrap();
    assert!(alpha[..10].iter().all(|&a| a == 1.0) && alpha[10..].iter().all(|&a| a == 0.5));

    // Bounds: x from 0.1 (Linear, Bezier) to 0.46 (Bspline's end), y from 0 to 0.24 (Bezier's end), z from −0.12
    // (Bezier's middle) to 0.
    let scene = load_scene(&path).unwrap();
    let b = scene.strand_bounds();
    assert_points(&[b.min, b.max], &[[0.1, 0.0, -0.12], [0.46, 0.24, 0.0]], "bounds");
    assert!(
        f.notes
            .iter()
            .any(|n| n == "/Groom/Bezier: cubic bezier → polylines at 4 segments per span (1 curves)"),
        "{:?}",
        f.notes
    );
    assert!(
        f.notes
            .iter()
            .any(|n| n == "/Groom/Bspline: widths varying → per point"),
        "{:?}",
        f.notes
    );
}

#[test]
fn time_samples_read_as_frames_with_constant_topology() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "hand.usda", HAND_STAGE);
    let f = read_usd_frames(&path).unwrap();
    assert_eq!(f.time_codes, [0.0, 2.0]);
    assert_eq!(f.time_codes_per_second, 12.0);
    assert_eq!(f.frames.len(), 2);
    let (a, b) = (&f.frames[0], &f.frames[1]);
    assert_eq!(a.counts, b.counts);
    // Only Bezier moves: +1 local x is +2 in the stage, +0.02 m.
    assert_eq!(a.points[..5], b.points[..5]);
    assert_eq!(a.points[10..], b.points[10..]);
    for (p, q) in a.points[5..10].iter().zip(&b.points[5..10]) {
        assert!(close(q.x - p.x, 0.02) && q.y == p.y && q.z == p.z, "{p} → {q}");
    }
    // A topology change names the time code: points that no longer fit the counts...
    let grown = HAND_STAGE.replace(
        "2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)],",
        "2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12), (1, 0, 13), (1, 0, 14), (1, 0, 15)],",
    );
    assert_ne!(grown, HAND_STAGE);
    let path = write(&dir, "grown.usda", &grown);
    let e = read_usd_frames(&path).unwrap_err().to_string();
    assert!(
        e.contains(
            "grown.usda: prim /Groom/Bezier, attribute curveVertexCounts: at time code 2: the counts sum to 4"
        ),
        "{e}"
    );
    // ... and counts that change with them (a valid bezier curve of 7 points at time code 2: 9 points, not 5).
    let recounted = grown.replace(
        "int[] curveVertexCounts = [4]",
        "int[] curveVertexCounts.timeSamples = {\n            0: [4],\n            2: [7],\n        }",
    );
    assert_ne!(recounted, grown);
    let path = write(&dir, "recounted.usda", &recounted);
    let e = read_usd_frames(&path).unwrap_err().to_string();
    assert!(
        e.contains(
            "recounted.usda: time code 2: 4 strands of 23 points, time code 0 has 4 strands of 19 points"
        ),
        "{e}"
    );
}

#[test]
fn pinned_catmull_rom_passes_through_its_end_points() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"#usda 1.0
(
    upAxis = "Y"
    metersPerUnit = 1
)
def BasisCurves "C"
{
    uniform token type = "cubic"
    uniform token basis = "catmullRom"
    uniform token wrap = "pinned"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 0, 0)]
}
"#;
    let path = write(&dir, "cr.usda", text);
    let s = read_usd_file(&path).unwrap().strands;
    // Phantom points (−1, −1) and (3, −1); 2 spans of 4 segments = 9 points. Span 0 at t = ½ with the weights
    // (−1/16, 9/16, 9/16, −1/16) over (−1,−1), (0,0), (1,1), (2,0): x = 1/16 + 9/16 − 2/16 = 0.5,
    // y = 1/16 + 9/16 = 0.625.
    assert_eq!(s.counts, [9]);
    assert_points(
        &[s.points[0], s.points[2], s.points[4], s.points[8]],
        &[
            [0.0, 0.0, 0.0],
            [0.5, 0.625, 0.0],
            [1.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ],
        "catmullRom pinned",
    );
}

#[test]
fn hair_to_usda_to_hair_keeps_every_array() {
    let dir = tempfile::tempdir().unwrap();
    let groom = crate::groom_formats::uniform_groom();
    let hair = dir.path().join("g.hair");
    write_hair_file(&hair, &HairFile::from_strands(&groom, "groom").unwrap()).unwrap();
    let usda = dir.path().join("g.usda");
    save_strands(&usda, &load_scene(&hair).unwrap().strands, "").unwrap();
    let back = dir.path().join("back.hair");
    save_strands(&back, &load_scene(&usda).unwrap().strands, "").unwrap();
    assert_eq!(load_scene(&back).unwrap().strands, groom);
}

#[test]
fn one_groom_as_usda_tfx_and_data_gives_the_same_strands() {
    use hairlab::scene::tfx::{TfxFile, write_tfx_file};
    use hairlab::scene::usc_data::write_data_file;
    let dir = tempfile::tempdir().unwrap();
    let groom = crate::groom_formats::uniform_groom();
    let (usda, tfx, data) = (
        dir.path().join("g.usda"),
        dir.path().join("g.tfx"),
        dir.path().join("g.data"),
    );
    std::fs::write(&usda, write_usda(std::slice::from_ref(&groom), 24.0).unwrap()).unwrap();
    write_tfx_file(&tfx, &TfxFile::from_strands(&groom).unwrap()).unwrap();
    write_data_file(&data, &groom).unwrap();
    let from_usda = load_scene(&usda).unwrap().strands;
    assert_eq!(from_usda, load_scene(&tfx).unwrap().strands);
    let from_data = load_scene(&data).unwrap().strands;
    assert_eq!(
        (&from_usda.points, &from_usda.counts),
        (&from_data.points, &from_data.counts)
    );
}

#[test]
fn several_frames_round_trip_through_usda_frame_by_frame() {
    let dir = tempfile::tempdir().unwrap();
    let a = crate::groom_formats::uniform_groom();
    let mut b = a.clone();
    b.points
        .iter_mut()
        .for_each(|p| *p += Vec3::new(0.5, -0.25, 0.125));
    let path = dir.path().join("m.usda");
    std::fs::write(&path, write_usda(&[a.clone(), b.clone()], 30.0).unwrap()).unwrap();
    let f = read_usd_frames(&path).unwrap();
    assert_eq!(f.time_codes, [0.0, 1.0]);
    assert_eq!(f.time_codes_per_second, 30.0);
    assert_eq!(f.frames, [a, b]);
    let e = write_usda(&[Strands::default(), crate::groom_formats::uniform_groom()], 24.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("frame 1"), "{e}");
}

#[test]
fn bad_stages_are_refused_naming_file_prim_and_attribute() {
    let dir = tempfile::tempdir().unwrap();
    let curve = |body: &str| {
        format!(
            "#usda 1.0\n(\n    metersPerUnit = 1\n)\ndef Xform \"G\"\n{{\n    def BasisCurves \"C\"\n    {{\n{body}\n    }}\n}}\n"
        )
    };
    let cases = [
        (
            "missing_points",
            "        uniform token type = \"linear\"\n        int[] curveVertexCounts = [2]",
            "attribute points: missing",
        ),
        (
            "bad_sum",
            "        uniform token type = \"linear\"\n        int[] curveVertexCounts = [2, 2]\n        point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0)]",
            "attribute curveVertexCounts: the counts sum to 4, the prim has 3 points",
        ),
        (
            "periodic",
            "        uniform token wrap = \"periodic\"\n        int[] curveVertexCounts = [4]\n        point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0), (0, 3, 0)]",
            "attribute wrap: periodic curves are refused",
        ),
        (
            "short_bezier",
            "        int[] curveVertexCounts = [5]\n        point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0), (0, 3, 0), (0, 4, 0)]",
            "attribute curveVertexCounts: curve 0 has 5 vertices; a bezier curve needs 4 + 3k",
        ),
        (
            "widths_length",
            "        uniform token type = \"linear\"\n        int[] curveVertexCounts = [2]\n        point3f[] points = [(0, 0, 0), (0, 1, 0)]\n        float[] widths = [1, 2, 3]",
            "attribute widths: 3 values, vertex interpolation needs 2",
        ),
        (
            "nan",
            "        uniform token type = \"linear\"\n        int[] curveVertexCounts = [2]\n        point3f[] points = [(0, 0, 0), (0, nan, 0)]",
            "attribute points: point 1 is not finite",
        ),
    ];
    for (name, body, want) in cases {
        let path = write(&dir, &format!("{name}.usda"), &curve(body));
        let e = format!("{:#}", load_scene(&path).unwrap_err());
        assert!(
            e.contains(&format!("{name}.usda: prim /G/C, {want}")),
            "{name}: {e}"
        );
    }
}

#[test]
fn info_and_convert_report_the_stage_and_keep_its_frames() {
    use crate::common::cli::hairlab;
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "hand.usda", HAND_STAGE);
    let o = hairlab(&["info", path.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    for line in [
        "stage:     upAxis Z, metersPerUnit 0.01 (read as Y-up metres), 2 time samples at 12 time codes per second",
        "arrays:    points, widths, displayColor, displayOpacity",
        "converted: /Groom/Bezier: cubic bezier → polylines at 4 segments per span (1 curves)",
        "converted: /Groom/Bspline: cubic bspline → polylines at 4 segments per span (1 curves)",
        "converted: /Groom/Linear: primvars:displayColor uniform → per point",
        "converted: upAxis Z → Y-up (x, y, z) → (x, z, −y)",
        "converted: metersPerUnit 0.01 → metres",
        "meshes:    0 (0 triangles)",
        "strands:   4",
        "points:    19",
        "segments:  15",
        "bounds:    min (0.1000, 0.0000, -0.1200) max (0.4600, 0.2400, 0.0000)",
    ] {
        assert!(out.lines().any(|l| l == line), "{line:?} missing from:\n{out}");
    }
    let out_path = dir.path().join("out.usda");
    let o = hairlab(&["convert", path.to_str().unwrap(), out_path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("frames:    2 (time-sampled points)"));
    let (a, b) = (
        read_usd_frames(&path).unwrap(),
        read_usd_frames(&out_path).unwrap(),
    );
    assert_eq!(a.frames, b.frames);
    // The written stage plays its frames at time codes 0, 1 at the source's rate.
    assert_eq!(
        (b.time_codes.as_slice(), b.time_codes_per_second),
        ([0.0, 1.0].as_slice(), 12.0)
    );
}

#[test]
fn a_mesh_prim_is_triangulated_under_its_transform() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"#usda 1.0
(
    upAxis = "Y"
    metersPerUnit = 1
)
def Xform "Head"
{
    double3 xformOp:translate = (0, 1, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Mesh "Quad"
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 0, -1), (0, 0, -1)]
        color3f[] primvars:displayColor = [(0.25, 0.5, 0.75)]
    }
}
"#;
    let path = write(&dir, "head.usda", text);
    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    let m = &scene.meshes[0];
    // A quad as a fan: (0, 1, 2), (0, 2, 3); lifted by 1 in y; counter-clockwise seen from +y, so normals +y.
    assert_eq!(m.indices, [0, 1, 2, 0, 2, 3]);
    assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, -1.0));
    assert!(
        m.normals.iter().all(|n| (*n - Vec3::Y).length() < 1e-6),
        "{:?}",
        m.normals
    );
    assert_eq!(m.color, Vec3::new(0.25, 0.5, 0.75));
}

/// Regressions from the fuzz run (seeds 11 and 12): a `}` in a prim name or an xformOp name made the `openusd`
/// crate overflow the stack (the path of `C}` is its own parent); both are now refused before the crate sees them.
#[test]
fn names_the_crate_cannot_walk_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let prim_name = HAND_STAGE.replace("def BasisCurves \"Linear\"", "def BasisCurves \"Lin}ear\"");
    assert_ne!(prim_name, HAND_STAGE);
    let path = write(&dir, "prim_name.usda", &prim_name);
    let e = read_usd_file(&path).unwrap_err().to_string();
    assert!(
        e.contains("prim_name.usda: prim /Groom, attribute (children): the child prim name \"Lin}ear\" is not a USD identifier"),
        "{e}"
    );
    let op_name = HAND_STAGE.replace("[\"xformOp:translate\",", "[\"xformOp:transl}te\",");
    assert_ne!(op_name, HAND_STAGE);
    let path = write(&dir, "op_name.usda", &op_name);
    let e = read_usd_file(&path).unwrap_err().to_string();
    assert!(
        e.contains(
            "op_name.usda: prim /Groom, attribute xformOpOrder: \"xformOp:transl}te\" is not an xformOp name"
        ),
        "{e}"
    );
}

/// The hand stage re-encoded by the `openusd` crate as binary `.usdc` and as a `.usdz` archive reads as the text.
#[test]
fn usdc_and_usdz_read_like_usda() {
    let dir = tempfile::tempdir().unwrap();
    let usda = write(&dir, "hand.usda", HAND_STAGE);
    let text = read_usd_file(&usda).unwrap();
    let stage = openusd::usd::Stage::open(usda.to_str().unwrap()).unwrap();
    for ext in ["usdc", "usdz"] {
        let path = dir.path().join(format!("hand.{ext}"));
        stage.root_layer().export(path.to_str().unwrap()).unwrap();
        let binary = read_usd_file(&path).unwrap();
        assert_eq!(binary.strands, text.strands, ".{ext}");
        assert_eq!(binary.time_codes, text.time_codes, ".{ext}");
    }
}

/// The hand stage as a preset's scene renders hair, and as `motion.path` plays as a motion of its two time codes:
/// frame 1 (time code 2, the bezier moved by 2 cm) differs from frame 0 on screen and equals, bit for bit, a
/// fresh render of a still stage holding time code 2's points (one camera, and `light.fit = per-frame` so
/// each frame's light frame is fitted to its own strands as the still render's is).
#[test]
fn the_hand_stage_renders_and_plays_as_a_motion() {
    let Some(_gpu) = hairlab::gpu::Gpu::for_tests() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    write(&dir, "hand.usda", HAND_STAGE);
    let preset = dir.path().join("hand.toml");
    std::fs::write(
        &preset,
        "[scene]\nfile = \"hand.usda\"\n[render]\nwidth = 96\nheight = 72\nmap_resolution = 128\n\
         [motion]\nsource = \"sequence\"\npath = \"hand.usda\"\n",
    )
    .unwrap();
    let load = || hairlab::settings::Settings::load_preset(preset.to_str().unwrap(), &[]).unwrap();
    let (_, motion) = load().open_motion().unwrap();
    assert_eq!(motion.frame_count(&load().motion), 2);
    let background = load().render.background;
    let [first, second] = [0, 1].map(|k| hairlab::cli::render::render_frame_image(&mut load(), k).unwrap());
    let hair = first
        .pixels()
        .filter(|p| {
            let bg = background.map(|c| (c.powf(1.0 / 2.2) * 255.0) as i32);
            (0..3).any(|i| (p.0[i] as i32 - bg[i]).abs() > 16)
        })
        .count();
    assert!(hair > 50, "only {hair} pixels differ from the background");
    let moved = first
        .pixels()
        .zip(second.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(moved > 0, "time code 2 moved nothing on screen");
    let sample0 = "0: [(0, 0, 0), (0, 8, 4), (0, 8, 8), (0, 0, 12)],\n";
    let sample2 = "2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)],\n";
    let timed =
        format!("point3f[] points.timeSamples = {{\n            {sample0}            {sample2}        }}");
    assert!(HAND_STAGE.contains(&timed), "the stage's time samples");
    let still_stage = HAND_STAGE.replace(
        &timed,
        "point3f[] points = [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)]",
    );
    write(&dir, "hand-at-2.usda", &still_stage);
    let still_preset = dir.path().join("hand-at-2.toml");
    std::fs::write(
        &still_preset,
        "[scene]\nfile = \"hand-at-2.usda\"\n[render]\nwidth = 96\nheight = 72\nmap_resolution = 128\n",
    )
    .unwrap();
    let (scene, _) = load().open_motion().unwrap();
    let mut camera = load().camera;
    camera.frame(&scene.framing_bounds());
    let pinned = |mut s: hairlab::settings::Settings| {
        s.camera = camera;
        s.light.fit = hairlab::scene::LightFit::PerFrame;
        s
    };
    let played = hairlab::cli::render::render_frame_image(&mut pinned(load()), 1).unwrap();
    let still = hairlab::settings::Settings::load_preset(still_preset.to_str().unwrap(), &[]).unwrap();
    let fresh = hairlab::cli::render::render_frame_image(&mut pinned(still), 0).unwrap();
    assert_eq!(
        played.as_raw(),
        fresh.as_raw(),
        "frame 1 against a still render of time code 2"
    );
}

/// The malformed binary stages of issue 34 (each once aborted or panicked inside `openusd`'s usdc reader).
fn malformed_usdc() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/usdc-malformed");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "usdc"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 17, "{}", dir.display());
    files
}

/// CRC-32 (IEEE), bitwise: enough for the small archives these tests write.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A `.usdz`: one stored (uncompressed) zip entry whose data starts on a 64-byte boundary, as USDZ requires.
pub(crate) fn usdz_of(name: &str, data: &[u8]) -> Vec<u8> {
    let crc = crc32(data);
    let size = u32::try_from(data.len()).unwrap();
    let name_len = u16::try_from(name.len()).unwrap();
    let mut extra = (64 - (30 + name.len()) % 64) % 64;
    if extra > 0 && extra < 4 {
        extra += 64;
    }
    let mut z = Vec::new();
    z.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
    z.extend_from_slice(&[20, 0, 0, 0, 0, 0, 0, 0, 0, 0]); // version, flags, method stored, time, date
    z.extend_from_slice(&crc.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&name_len.to_le_bytes());
    z.extend_from_slice(&u16::try_from(extra).unwrap().to_le_bytes());
    z.extend_from_slice(name.as_bytes());
    if extra > 0 {
        // An unknown extra field (id 0x1986, as Pixar's writer uses) padding the data to 64 bytes.
        z.extend_from_slice(&0x1986u16.to_le_bytes());
        z.extend_from_slice(&u16::try_from(extra - 4).unwrap().to_le_bytes());
        z.resize(z.len() + extra - 4, 0);
    }
    assert_eq!(z.len() % 64, 0);
    z.extend_from_slice(data);
    let central = z.len();
    z.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
    z.extend_from_slice(&[20, 0, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0]); // made by, needed, flags, method, time, date
    z.extend_from_slice(&crc.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&name_len.to_le_bytes());
    z.extend_from_slice(&[0; 12]); // extra, comment, disk, internal and external attributes
    z.extend_from_slice(&0u32.to_le_bytes()); // local header offset
    z.extend_from_slice(name.as_bytes());
    let central_len = u32::try_from(z.len() - central).unwrap();
    z.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    z.extend_from_slice(&[0, 0, 0, 0, 1, 0, 1, 0]);
    z.extend_from_slice(&central_len.to_le_bytes());
    z.extend_from_slice(&u32::try_from(central).unwrap().to_le_bytes());
    z.extend_from_slice(&[0, 0]);
    z
}

/// The issue-34 reproducers, bare and each inside a valid `.usdz`.
fn malformed_usd_files(dir: &tempfile::TempDir) -> Vec<std::path::PathBuf> {
    let mut files = malformed_usdc();
    for f in malformed_usdc() {
        let bytes = std::fs::read(&f).unwrap();
        let stem = f.file_stem().unwrap().to_str().unwrap();
        let z = dir.path().join(format!("{stem}.usdz"));
        std::fs::write(&z, usdz_of(&format!("{stem}.usdc"), &bytes)).unwrap();
        files.push(z);
    }
    files
}

/// Every malformed binary stage is refused with an error naming the file: no panic, no abort (issue 34).
#[test]
fn malformed_usdc_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    for f in malformed_usd_files(&dir) {
        let name = f.file_name().unwrap().to_str().unwrap().to_string();
        let r = std::panic::catch_unwind(|| load_scene(&f));
        let r = r.unwrap_or_else(|_| panic!("{name}: load_scene panicked"));
        match r {
            Err(e) => {
                let e = format!("{e:#}");
                assert!(e.contains(&name), "{name}: {e}");
            }
            // 05's bad token list is in a field the patched crate now refuses and skips; what remains is an empty stage.
            Ok(scene) => assert!(
                name.starts_with("05-") && scene.strands.strand_count() == 0,
                "{name}: loaded"
            ),
        }
    }
}

/// A valid stage inside the test's own `.usdz` writer reads, so the archive above is not what is refused.
#[test]
fn the_test_usdz_writer_makes_a_readable_archive() {
    let dir = tempfile::tempdir().unwrap();
    let usda = write(&dir, "hand.usda", HAND_STAGE);
    let stage = openusd::usd::Stage::open(usda.to_str().unwrap()).unwrap();
    let usdc = dir.path().join("hand.usdc");
    stage.root_layer().export(usdc.to_str().unwrap()).unwrap();
    let z = dir.path().join("hand.usdz");
    std::fs::write(&z, usdz_of("hand.usdc", &std::fs::read(&usdc).unwrap())).unwrap();
    assert_eq!(
        read_usd_file(&z).unwrap().strands,
        read_usd_file(&usda).unwrap().strands
    );
}

/// `hairlab info` on each malformed stage exits non-zero with one line of stderr naming the file, no panic.
#[test]
fn info_on_malformed_usdc_says_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for f in malformed_usd_files(&dir) {
        let name = f.file_name().unwrap().to_str().unwrap().to_string();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
            .arg("info")
            .arg(&f)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            !err.contains("panicked") && !out.contains("panicked"),
            "{name}: {err}"
        );
        if name.starts_with("05-") && o.status.success() {
            // See above: an empty stage, said on stdout.
            assert!(out.contains(&name) && err.is_empty(), "{name}: {out}");
            continue;
        }
        assert!(!o.status.success(), "{name}: exit {:?}", o.status);
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(&name), "{name}: {err}");
    }
}
