//! Reading stages: the hand-written stage's values derived by hand, time samples as frames, pinned Catmull-Rom
//! end points, a mesh prim under its transform, names the crate cannot walk, and `.usdc`/`.usdz` read like
//! `.usda`.

use super::{HAND_STAGE, write};
use glam::Vec3;
use hairlab::scene::load::load_scene;
use hairlab::scene::usd::{read_usd_file, read_usd_frames};

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
