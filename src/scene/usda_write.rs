//! A small `.usda` writer (Pixar's USD text format, <https://openusd.org/release/spec_usdpreview.html> for the layer
//! syntax and the `UsdGeomBasisCurves` schema for the prim): strands as one `BasisCurves` prim of `type = "linear"`.
//!
//! The stage authors `upAxis = "Y"` and `metersPerUnit = 1`, so hairlab's reader ([`super::usd`]) takes the points
//! back unscaled and unturned. The prim `/Groom/Strands` holds `curveVertexCounts`, `points`, `widths` (vertex
//! interpolation, from the thickness) and the primvars `displayColor` / `displayOpacity` (vertex interpolation, from
//! colour and alpha), each written only when the strands have it. Given several frames (same topology), `points` is
//! written as `timeSamples` at time codes 0, 1, 2, … with the stage's `timeCodesPerSecond`, `startTimeCode` and
//! `endTimeCode`. Floats are written with Rust's shortest round-trip formatting, so every f32 reads back exactly.
//! Needs no crate: it is built with or without the `usd` feature.

use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;

use super::Strands;

/// Why frames cannot be written as one `.usda` layer.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum UsdaWriteError {
    #[error("no frames to write")]
    NoFrames,
    #[error(
        "frame {frame} has {strands} strands of {points} points, frame 0 has {first_strands} strands of \
         {first_points} points; every frame of a .usda needs the same topology"
    )]
    Topology {
        frame: usize,
        strands: usize,
        points: usize,
        first_strands: usize,
        first_points: usize,
    },
    #[error("frame {frame} has a point that is not finite: {point}")]
    NotFinite { frame: usize, point: Vec3 },
    #[error("timeCodesPerSecond {0} must be finite and positive")]
    TimeCodesPerSecond(f64),
}

/// Encodes `frames` (at least one; every frame with the first frame's counts, arrays taken from the first frame)
/// as a `.usda` layer: one frame gives a static `points`, several give `points.timeSamples` at time codes `0..n`
/// played at `time_codes_per_second`. An error says which frame does not match.
pub fn write_usda(frames: &[Strands], time_codes_per_second: f64) -> Result<String, UsdaWriteError> {
    let first = frames.first().ok_or(UsdaWriteError::NoFrames)?;
    for (frame, f) in frames.iter().enumerate() {
        if f.counts != first.counts || f.points.len() != first.points.len() {
            return Err(UsdaWriteError::Topology {
                frame,
                strands: f.counts.len(),
                points: f.points.len(),
                first_strands: first.counts.len(),
                first_points: first.points.len(),
            });
        }
        if let Some(&point) = f.points.iter().find(|p| !p.is_finite()) {
            return Err(UsdaWriteError::NotFinite { frame, point });
        }
    }
    if !(time_codes_per_second.is_finite() && time_codes_per_second > 0.0) {
        return Err(UsdaWriteError::TimeCodesPerSecond(time_codes_per_second));
    }
    let mut s = String::new();
    s.push_str("#usda 1.0\n(\n    defaultPrim = \"Groom\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n");
    if frames.len() > 1 {
        let _ = writeln!(
            s,
            "    startTimeCode = 0\n    endTimeCode = {}\n    timeCodesPerSecond = {time_codes_per_second}",
            frames.len() - 1
        );
    }
    s.push_str(")\n\ndef Xform \"Groom\"\n{\n    def BasisCurves \"Strands\"\n    {\n");
    s.push_str("        uniform token type = \"linear\"\n        uniform token wrap = \"nonperiodic\"\n");
    let ints: Vec<String> = first.counts.iter().map(u32::to_string).collect();
    let _ = writeln!(s, "        int[] curveVertexCounts = [{}]", ints.join(", "));
    if frames.len() == 1 {
        let _ = writeln!(s, "        point3f[] points = {}", vec3s(&first.points));
    } else {
        s.push_str("        point3f[] points.timeSamples = {\n");
        for (i, f) in frames.iter().enumerate() {
            let _ = writeln!(s, "            {i}: {},", vec3s(&f.points));
        }
        s.push_str("        }\n");
    }
    if let Some(t) = &first.thickness {
        let _ = writeln!(
            s,
            "        float[] widths = {} (\n            interpolation = \"vertex\"\n        )",
            floats(t)
        );
    }
    if let Some(c) = &first.color {
        let _ = writeln!(
            s,
            "        color3f[] primvars:displayColor = {} (\n            interpolation = \"vertex\"\n        )",
            vec3s(c)
        );
    }
    if let Some(a) = &first.alpha {
        let _ = writeln!(
            s,
            "        float[] primvars:displayOpacity = {} (\n            interpolation = \"vertex\"\n        )",
            floats(a)
        );
    }
    s.push_str("    }\n}\n");
    Ok(s)
}

fn floats(v: &[f32]) -> String {
    let v: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", v.join(", "))
}

fn vec3s(v: &[Vec3]) -> String {
    let v: Vec<String> = v
        .iter()
        .map(|p| format!("({:?}, {:?}, {:?})", p.x, p.y, p.z))
        .collect();
    format!("[{}]", v.join(", "))
}

/// [`write_usda`] to `path`, whole or not at all ([`crate::io::write_atomic_io`]); errors name the file.
pub fn write_usda_file(path: &Path, frames: &[Strands], time_codes_per_second: f64) -> anyhow::Result<()> {
    let text =
        write_usda(frames, time_codes_per_second).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    crate::io::write_atomic_io(path, text.as_bytes()).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
