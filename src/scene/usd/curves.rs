//! `BasisCurves` prims to strands: the schema's bases and wraps evaluated per span, primvars by their
//! interpolation, every array's length checked against its curve before it is read (the parent module's doc has
//! the rules).

use super::{CUBIC_SEGMENTS_PER_SPAN, Reader, UsdError, When};
use crate::scene::Strands;
use glam::DVec4;
use openusd::usd::Prim;

/// How a primvar's values map onto a curve batch or mesh (USD's `interpolation` metadata).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Interp {
    Constant,
    Uniform,
    Varying,
    Vertex,
}

impl Interp {
    fn name(self) -> &'static str {
        match self {
            Interp::Constant => "constant",
            Interp::Uniform => "uniform",
            Interp::Varying => "varying",
            Interp::Vertex => "vertex",
        }
    }
}

/// One array attribute as read: 4-wide values (a float uses `x`, a colour `xyz`), its interpolation and name.
pub(super) struct Primvar {
    pub(super) name: &'static str,
    pub(super) values: Vec<DVec4>,
    pub(super) interp: Interp,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Basis {
    Bezier,
    Bspline,
    CatmullRom,
}

impl Basis {
    fn vstep(self) -> usize {
        match self {
            Basis::Bezier => 3,
            Basis::Bspline | Basis::CatmullRom => 1,
        }
    }
    fn name(self) -> &'static str {
        match self {
            Basis::Bezier => "bezier",
            Basis::Bspline => "bspline",
            Basis::CatmullRom => "catmullRom",
        }
    }
    /// The four weights of a span's control points at `t` in [0, 1] (the basis matrices of `UsdGeomBasisCurves`).
    fn weights(self, t: f64) -> [f64; 4] {
        let (t2, t3, s) = (t * t, t * t * t, 1.0 - t);
        match self {
            Basis::Bezier => [s * s * s, 3.0 * t * s * s, 3.0 * t2 * s, t3],
            Basis::Bspline => [
                s * s * s / 6.0,
                (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
                (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
                t3 / 6.0,
            ],
            Basis::CatmullRom => [
                (-t3 + 2.0 * t2 - t) / 2.0,
                (3.0 * t3 - 5.0 * t2 + 2.0) / 2.0,
                (-3.0 * t3 + 4.0 * t2 + t) / 2.0,
                (t3 - t2) / 2.0,
            ],
        }
    }
}

/// A curve batch's shape: linear, or cubic with a basis and whether bspline/catmullRom ends are pinned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Shape {
    Linear,
    Cubic { basis: Basis, pinned: bool },
}

impl Shape {
    /// Spans of a curve of `n` vertices, or why it cannot be one (None for a linear curve of < 2 vertices, which
    /// is dropped, not refused).
    fn spans(self, n: usize) -> Result<Option<usize>, String> {
        match self {
            Shape::Linear => Ok((n >= 2).then(|| n - 1)),
            Shape::Cubic {
                basis: Basis::Bezier, ..
            } => {
                if n >= 4 && (n - 4).is_multiple_of(3) {
                    Ok(Some((n - 1) / 3))
                } else {
                    Err(format!("{n} vertices; a bezier curve needs 4 + 3k"))
                }
            }
            Shape::Cubic { basis, pinned: true } => {
                if n >= 2 {
                    Ok(Some(n - 1))
                } else {
                    Err(format!(
                        "{n} vertices; a pinned {} curve needs at least 2",
                        basis.name()
                    ))
                }
            }
            Shape::Cubic { basis, pinned: false } => {
                if n >= 4 {
                    Ok(Some(n - 3))
                } else {
                    Err(format!(
                        "{n} vertices; a nonperiodic {} curve needs at least 4",
                        basis.name()
                    ))
                }
            }
        }
    }
    /// Varying values of a curve of `spans` spans (USD: spans + 1 for open curves; the vertex count for linear).
    fn varying(self, spans: usize) -> usize {
        spans + 1
    }
}

/// Checks a primvar's length against its interpolation: `constant` 1, `uniform` one per curve or face, `vertex`
/// one per point, `varying` `varying` values.
pub(super) fn check_len(
    r: &Reader,
    prim: &Prim,
    pv: &Primvar,
    elements: usize,
    vertices: usize,
    varying: usize,
) -> Result<(), UsdError> {
    let expected = match pv.interp {
        Interp::Constant => 1,
        Interp::Uniform => elements,
        Interp::Vertex => vertices,
        Interp::Varying => varying,
    };
    let what = pv.interp.name();
    if pv.values.len() != expected {
        return Err(r.err(
            prim,
            pv.name,
            format!(
                "{} values, {what} interpolation needs {expected}",
                pv.values.len()
            ),
        ));
    }
    Ok(())
}

/// One BasisCurves prim at `when` as polylines in the world, with notes.
pub(super) fn read_curves(
    r: &Reader,
    prim: &Prim,
    when: When,
    notes: &mut Vec<String>,
) -> Result<Strands, UsdError> {
    let path = prim.path().as_str().to_owned();
    let ty = r.token(prim, "type", "cubic")?;
    let shape = match ty.as_str() {
        "linear" => Shape::Linear,
        "cubic" => {
            let wrap = r.token(prim, "wrap", "nonperiodic")?;
            let pinned = match wrap.as_str() {
                "nonperiodic" => false,
                "pinned" => true,
                "periodic" => {
                    return Err(r.err(
                        prim,
                        "wrap",
                        "periodic curves are refused (hairlab reads open strands)",
                    ));
                }
                w => return Err(r.err(prim, "wrap", format!("unknown wrap {w:?}"))),
            };
            let basis = match r.token(prim, "basis", "bezier")?.as_str() {
                "bezier" => Basis::Bezier,
                "bspline" => Basis::Bspline,
                "catmullRom" => Basis::CatmullRom,
                "hermite" => {
                    return Err(r.err(prim, "basis", "hermite curves are refused (no tangents read)"));
                }
                b => return Err(r.err(prim, "basis", format!("unknown basis {b:?}"))),
            };
            Shape::Cubic {
                basis,
                pinned: pinned && basis != Basis::Bezier,
            }
        }
        t => return Err(r.err(prim, "type", format!("unknown type {t:?}"))),
    };
    if shape == Shape::Linear && r.token(prim, "wrap", "nonperiodic")? == "periodic" {
        return Err(r.err(
            prim,
            "wrap",
            "periodic curves are refused (hairlab reads open strands)",
        ));
    }
    let points = r.points(prim, when)?;
    let counts = r.counts(prim, "curveVertexCounts", when, points.len())?;
    // Spans per curve (None: a linear curve of < 2 vertices, dropped), and the varying values.
    let mut spans = Vec::with_capacity(counts.len());
    for (i, &n) in counts.iter().enumerate() {
        spans.push(
            shape
                .spans(n)
                .map_err(|e| r.err(prim, "curveVertexCounts", format!("curve {i} has {e}")))?,
        );
    }
    let varying: usize = counts
        .iter()
        .zip(&spans)
        .map(|(&n, s)| s.map_or(n, |s| shape.varying(s)))
        .sum();
    let widths = r.primvar(prim, "widths", when, Interp::Vertex)?;
    let color = r.primvar(prim, "primvars:displayColor", when, Interp::Constant)?;
    let opacity = r.primvar(prim, "primvars:displayOpacity", when, Interp::Constant)?;
    for pv in [&widths, &color, &opacity].into_iter().flatten() {
        check_len(r, prim, pv, counts.len(), points.len(), varying)?;
    }
    if let Some(w) = &widths
        && let Some((i, x)) = w.values.iter().enumerate().find(|(_, x)| x.x < 0.0)
    {
        return Err(r.err(prim, "widths", format!("width {i} is {}, below 0", x.x)));
    }
    if let Some(o) = &opacity
        && let Some((i, x)) = o
            .values
            .iter()
            .enumerate()
            .find(|(_, x)| !(0.0..=1.0).contains(&x.x))
    {
        return Err(r.err(
            prim,
            "primvars:displayOpacity",
            format!("opacity {i} is {}, outside [0, 1]", x.x),
        ));
    }
    let m = r.world(prim, when)?;
    let width_scale = m.determinant().abs().cbrt();
    let n_seg = match shape {
        Shape::Linear => 1,
        Shape::Cubic { .. } => CUBIC_SEGMENTS_PER_SPAN,
    };
    let out_points: usize = spans.iter().flatten().map(|s| s * n_seg + 1).sum();
    let mut out = Strands {
        points: Vec::with_capacity(out_points),
        counts: Vec::with_capacity(counts.len()),
        thickness: widths.as_ref().map(|_| Vec::with_capacity(out_points)),
        alpha: opacity.as_ref().map(|_| Vec::with_capacity(out_points)),
        color: color.as_ref().map(|_| Vec::with_capacity(out_points)),
    };
    let p4: Vec<DVec4> = points.iter().map(|p| p.extend(0.0)).collect();
    let (mut first, mut first_varying, mut dropped) = (0usize, 0usize, 0usize);
    for (c, (&n, s)) in counts.iter().zip(&spans).enumerate() {
        let range = first..first + n;
        let vrange = first_varying..first_varying + s.map_or(n, |s| shape.varying(s));
        (first, first_varying) = (range.end, vrange.end);
        let Some(spans) = *s else {
            dropped += 1;
            continue;
        };
        // The parameters of the output points: (span, t); a linear curve's vertices are its points.
        let params: Vec<(usize, f64)> = match shape {
            Shape::Linear => (0..n).map(|i| (i, 0.0)).collect(),
            Shape::Cubic { .. } => std::iter::once((0, 0.0))
                .chain((0..spans).flat_map(|s| (1..=n_seg).map(move |k| (s, k as f64 / n_seg as f64))))
                .collect(),
        };
        let sample = |pv: &Primvar| -> Vec<DVec4> {
            match pv.interp {
                Interp::Constant => vec![pv.values[0]; params.len()],
                Interp::Uniform => vec![pv.values[c]; params.len()],
                Interp::Varying => {
                    let v = &pv.values[vrange.clone()];
                    params
                        .iter()
                        .map(|&(s, t)| if t == 0.0 { v[s] } else { v[s].lerp(v[s + 1], t) })
                        .collect()
                }
                Interp::Vertex => eval_vertex(shape, &pv.values[range.clone()], &params),
            }
        };
        let pts = eval_vertex(shape, &p4[range.clone()], &params);
        out.points
            .extend(pts.iter().map(|p| m.transform_point3(p.truncate()).as_vec3()));
        out.counts.push(params.len() as u32);
        if let (Some(w), Some(t)) = (&widths, out.thickness.as_mut()) {
            t.extend(sample(w).iter().map(|v| (v.x.max(0.0) * width_scale) as f32));
        }
        if let (Some(o), Some(a)) = (&opacity, out.alpha.as_mut()) {
            a.extend(sample(o).iter().map(|v| v.x.clamp(0.0, 1.0) as f32));
        }
        if let (Some(k), Some(col)) = (&color, out.color.as_mut()) {
            col.extend(sample(k).iter().map(|v| v.truncate().as_vec3()));
        }
    }
    if let Some((i, p)) = out.points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(r.err(
            prim,
            "points",
            format!("output point {i} is not finite after the transform: {p}"),
        ));
    }
    if let Shape::Cubic { basis, pinned } = shape {
        notes.push(format!(
            "{path}: cubic {}{} → polylines at {CUBIC_SEGMENTS_PER_SPAN} segments per span ({} curves)",
            basis.name(),
            if pinned { " pinned" } else { "" },
            counts.len() - dropped
        ));
    }
    if dropped > 0 {
        notes.push(format!("{path}: {dropped} curves with < 2 points dropped"));
    }
    for pv in [&widths, &color, &opacity].into_iter().flatten() {
        if pv.interp != Interp::Vertex || shape != Shape::Linear {
            notes.push(format!("{path}: {} {} → per point", pv.name, pv.interp.name()));
        }
    }
    Ok(out)
}

/// A vertex-interpolated array of one curve evaluated at `params` with the curve's shape.
pub(super) fn eval_vertex(shape: Shape, ctrl: &[DVec4], params: &[(usize, f64)]) -> Vec<DVec4> {
    match shape {
        Shape::Linear => params.iter().map(|&(i, _)| ctrl[i]).collect(),
        Shape::Cubic { basis, pinned } => {
            let ext: Vec<DVec4>;
            let ctrl = if pinned {
                let n = ctrl.len();
                ext = std::iter::once(2.0 * ctrl[0] - ctrl[1])
                    .chain(ctrl.iter().copied())
                    .chain(std::iter::once(2.0 * ctrl[n - 1] - ctrl[n - 2]))
                    .collect();
                &ext[..]
            } else {
                ctrl
            };
            params
                .iter()
                .map(|&(s, t)| {
                    let w = basis.weights(t);
                    let c = &ctrl[s * basis.vstep()..s * basis.vstep() + 4];
                    c[0] * w[0] + c[1] * w[1] + c[2] * w[2] + c[3] * w[3]
                })
                .collect()
        }
    }
}
