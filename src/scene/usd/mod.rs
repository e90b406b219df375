//! USD stages (`.usda`, `.usdc`, `.usdz`; Pixar's Universal Scene Description, <https://openusd.org>), read
//! through the pure-Rust [`openusd`] crate (pinned at 0.6.0, behind the default-on `usd` cargo feature): every
//! `BasisCurves` prim becomes hair strands and every `Mesh` prim an opaque mesh, in hairlab's world. `.usdc` and
//! `.usdz` go through the same `Stage::open` as `.usda`. The crate is kept patched in `vendor/openusd` so that a
//! malformed `.usdc` (alone or in a `.usdz`) is an error, never a panic or an abort (`HAIRLAB-PATCHES.md` there).
//!
//! **World.** hairlab's world is right-handed and Y-up. A USD stage says its own up axis (`upAxis`, `"Y"` or
//! `"Z"`, fallback Y) and unit (`metersPerUnit`, fallback 0.01 — USD's centimetres, `UsdGeomGetStageMetersPerUnit`),
//! so this reader converts: a Z-up stage is turned by −90° about X (`(x, y, z)` → `(x, z, −y)`) and everything is
//! scaled to metres. Each prim's points go through its world transform: the `xformOp`s of the prim and of every
//! ancestor, composed by the crate's `Xformable::local_to_parent_transform` prim by prim (a
//! `!resetXformStack!` stops the walk up), then the axis and unit conversion.
//!
//! **BasisCurves** (schema `UsdGeomBasisCurves`). The schema's fallbacks apply where the file authors nothing:
//! `type` cubic, `basis` bezier, `wrap` nonperiodic (the crate returns `None` for an unauthored attribute).
//! - `type = "linear"`: the vertices are the polyline (a curve of fewer than 2 vertices is dropped and counted).
//! - `type = "cubic"` with `basis` bezier (vstep 3), bspline or catmullRom (vstep 1): each span is evaluated at
//!   [`CUBIC_SEGMENTS_PER_SPAN`] segments (a constant), so a curve of `k` spans becomes `4k + 1` points. A
//!   nonperiodic bezier curve needs `4 + 3m` vertices, a nonperiodic bspline or catmullRom curve at least 4.
//!   `wrap = "pinned"` bspline and catmullRom curves get USD's phantom end points (`2·P0 − P1`, `2·Pn−1 − Pn−2`) so
//!   they pass through their end vertices (at least 2 vertices, `n − 1` spans); pinned bezier is nonperiodic.
//!   `basis = "hermite"` and `wrap = "periodic"` are refused by name.
//! - `widths` (diameters; interpolation `constant`, `uniform`, `varying` or `vertex`, fallback vertex) become per
//!   point thickness in metres: the width times the unit scale and the cube root of the transform's |det|.
//!   `primvars:displayColor` / `primvars:displayOpacity` (fallback interpolation constant, `:indices` honoured)
//!   become colour and alpha. A vertex value is evaluated with the curve's basis, a varying value linearly per span
//!   (USD's rules; `faceVarying` reads as varying on curves). Other primvars, normals and velocities are not read.
//!
//! **Mesh** prims: `faceVertexCounts` / `faceVertexIndices` polygons triangulated as fans (`orientation =
//! "leftHanded"` and mirroring transforms flip the winding), smooth normals computed, colour from a constant
//! `displayColor` (else grey). Other geometry prims (`NurbsCurves`, `HermiteCurves`, `Points`, …) are dropped and
//! listed in [`UsdScene::notes`].
//!
//! **Time.** `points.timeSamples` of the curves are read by [`read_usd_frames`] at the union of their time codes,
//! played at the stage's `timeCodesPerSecond` (fallback `framesPerSecond`, then 24); the topology (curve counts and
//! point counts) must not change, else the error names the time code. [`read_usd_file`] reads the first time code
//! when the curves have samples, else the default values.
//!
//! **Refusals.** Every error names the file, and for a prim's data the prim path and the attribute: missing
//! `points` or `curveVertexCounts`, counts that are negative or do not sum to the points, a curve too short for its
//! basis, an array of the wrong length for its interpolation, a value not finite, a width below 0, an opacity
//! outside [0, 1]. The crate parses the whole file before hairlab sees a count, so the bound on
//! memory is the crate's and [`crate::io::MAX_INPUT_BYTES`] on the file; what hairlab allocates from the file's
//! counts is checked against the arrays first (at most `CUBIC_SEGMENTS_PER_SPAN + 1` points per control point).
//! The crate 0.6.0 overflows the stack (an abort, not a panic) on a prim or xformOp name that is not an identifier
//! (`a}`); hairlab walks the stage itself and refuses such names before the crate resolves them. No other crash was
//! found in 2 × 1,000,000 mutated `.usda` stages, nor in 1,000,000 each of mutated `.usdc` and `.usdz` files; no
//! `catch_unwind` hides anything.
//!
//! **Composition** ([`stage`]). Every layer a stage brings in (sublayers, references, payloads) is read the way the
//! root is: a regular file (a named pipe, a device or a folder is refused by its metadata before it is opened, so
//! nothing blocks) of at most [`crate::io::MAX_INPUT_BYTES`] (the crate's `ar::set_max_asset_bytes`). A layer that
//! is missing or unreadable, and an arc dropped — the closing arc of a cycle through any arc, an arc more than 32
//! arcs deep — does not fail the read: it is one line of [`UsdScene::warnings`], which `info`, `convert`, `render`
//! and the window's status line say, and `--strict` turns into an error. The crate's text parser refuses prims
//! nested more than 2,048 deep and values nested more than 64 deep; nesting, sublayer chains and class chains are
//! walked without recursion, and the reader composes each prim's world transform once (a 2,000-deep stage reads in
//! time linear in its path bytes).

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3, DVec4};
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::usd::{Prim, SchemaBase, SchemaKind, Stage, TimeCode};
use openusd::{sdf, tf};
use thiserror::Error;

use super::{Mesh, Strands};

mod curves;
mod mesh;
mod stage;

use curves::{Interp, Primvar, read_curves};
use mesh::read_mesh;
use stage::{open, warnings};

/// Segments each cubic span is evaluated at.
pub const CUBIC_SEGMENTS_PER_SPAN: usize = 4;

/// Everything that can go wrong reading a USD stage. Each message is one line.
#[derive(Debug, Error)]
pub enum UsdError {
    #[error("{file}: {cause}")]
    Stage { file: PathBuf, cause: String },
    #[error("{file}: prim {prim}, attribute {attribute}: {cause}")]
    Attribute {
        file: PathBuf,
        prim: String,
        attribute: String,
        cause: String,
    },
}

/// A stage as hairlab keeps it: strands and meshes in the world convention, and what was converted or dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct UsdScene {
    pub strands: Strands,
    pub meshes: Vec<Mesh>,
    /// The stage's `upAxis` ('Y' or 'Z', fallback 'Y').
    pub up_axis: char,
    /// The stage's `metersPerUnit` (fallback 0.01).
    pub meters_per_unit: f64,
    /// Time codes of the curves' `points.timeSamples` (all prims together, sorted); empty for a still stage.
    pub time_codes: Vec<f64>,
    pub time_codes_per_second: f64,
    /// One line per thing converted or dropped, e.g. "cubic bspline → polylines at 4 segments per span (/A, 3
    /// curves)".
    pub notes: Vec<String>,
    /// One line per thing composition could not do, e.g. "unresolved sublayer @./hair.usda@ introduced by
    /// @/show/groom.usda@": a layer missing or unreadable (the stage opens without it), an arc dropped for a cycle.
    pub warnings: Vec<String>,
}

/// The frames of a stage's time-sampled curves.
#[derive(Clone, Debug, PartialEq)]
pub struct UsdFrames {
    /// One [`Strands`] per time code, all with the same counts.
    pub frames: Vec<Strands>,
    /// The time code of each frame.
    pub time_codes: Vec<f64>,
    /// Time codes per second: frame `i` plays at `time_codes[i] / time_codes_per_second` seconds.
    pub time_codes_per_second: f64,
    /// The stage's composition warnings ([`UsdScene::warnings`]).
    pub warnings: Vec<String>,
}

/// Any prim as an [`Xformable`], to compose its `xformOp`s (the crate implements the trait on typed views only).
struct AnyXformable(Prim);

impl SchemaBase for AnyXformable {
    const KIND: SchemaKind = SchemaKind::ConcreteTyped;
    fn prim(&self) -> &Prim {
        &self.0
    }
}
impl Imageable for AnyXformable {}
impl Xformable for AnyXformable {}

/// The reading context: the stage, the file name for errors, and the stage-wide conversion.
struct Reader<'a> {
    file: &'a Path,
    stage: Stage,
    /// Axis and unit conversion, applied after each prim's world transform.
    to_world: DMat4,
    up_axis: char,
    meters_per_unit: f64,
    /// The world transforms composed so far (before the axis and unit conversion), by prim and time code bits.
    worlds: RefCell<HashMap<(sdf::Path, Option<u64>), DMat4>>,
}

/// The value of a [`sdf::Value`] as a token or string.
fn token(v: &sdf::Value) -> Option<&str> {
    match v {
        sdf::Value::Token(t) => Some(t.as_str()),
        sdf::Value::String(s) => Some(s.as_str()),
        _ => None,
    }
}

/// A value's variant name, for errors.
fn type_of(v: &sdf::Value) -> String {
    let d = format!("{v:?}");
    d.split(['(', ' ', '{']).next().unwrap_or("?").to_owned()
}

/// Floats, vectors and colours as 4-wide values.
fn vec4s(v: &sdf::Value) -> Option<Vec<DVec4>> {
    let f = |x: f64| DVec4::new(x, 0.0, 0.0, 0.0);
    Some(match v {
        sdf::Value::FloatVec(a) => a.iter().map(|&x| f(x.into())).collect(),
        sdf::Value::DoubleVec(a) => a.iter().map(|&x| f(x)).collect(),
        sdf::Value::HalfVec(a) => a.iter().map(|&x| f(x.to_f64())).collect(),
        sdf::Value::Float(x) => vec![f((*x).into())],
        sdf::Value::Double(x) => vec![f(*x)],
        sdf::Value::Vec3fVec(a) => a
            .iter()
            .map(|p| DVec4::new(p.x.into(), p.y.into(), p.z.into(), 0.0))
            .collect(),
        sdf::Value::Vec3dVec(a) => a.iter().map(|p| DVec4::new(p.x, p.y, p.z, 0.0)).collect(),
        sdf::Value::Vec3hVec(a) => a
            .iter()
            .map(|p| DVec4::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64(), 0.0))
            .collect(),
        sdf::Value::Vec3f(p) => vec![DVec4::new(p.x.into(), p.y.into(), p.z.into(), 0.0)],
        sdf::Value::Vec3d(p) => vec![DVec4::new(p.x, p.y, p.z, 0.0)],
        _ => return None,
    })
}

fn ints(v: &sdf::Value) -> Option<Vec<i64>> {
    Some(match v {
        sdf::Value::IntVec(a) => a.iter().map(|&x| x.into()).collect(),
        sdf::Value::UintVec(a) => a.iter().map(|&x| x.into()).collect(),
        sdf::Value::Int64Vec(a) => a.clone(),
        _ => return None,
    })
}

/// Where the values of an attribute are read: its default, or at a time code.
#[derive(Clone, Copy)]
enum When {
    Default,
    At(f64),
}

impl Reader<'_> {
    fn err(&self, prim: &Prim, attribute: &str, cause: impl Into<String>) -> UsdError {
        UsdError::Attribute {
            file: self.file.to_owned(),
            prim: prim.path().as_str().to_owned(),
            attribute: attribute.to_owned(),
            cause: cause.into(),
        }
    }

    /// The raw value of `prim.name` (at `when` if it has time samples), `None` when unauthored.
    fn value(&self, prim: &Prim, name: &str, when: When) -> Result<Option<sdf::Value>, UsdError> {
        let attr = prim.attribute(name);
        let r = match when {
            When::Default => attr.get::<sdf::Value>(),
            When::At(t) => attr.get_at::<sdf::Value>(TimeCode::new(t)),
        };
        let v = r.map_err(|e| self.err(prim, name, format!("{e:#}")))?;
        // An attribute authored only as time samples, read without a time: its first sample.
        match (v, when) {
            (None, When::Default) => Ok(attr
                .time_samples()
                .map_err(|e| self.err(prim, name, format!("{e:#}")))?
                .and_then(|s| s.into_iter().next().map(|(_, v)| v))),
            (v, _) => Ok(v),
        }
    }

    /// A uniform token attribute, or `fallback` when unauthored.
    fn token(&self, prim: &Prim, name: &str, fallback: &str) -> Result<String, UsdError> {
        match self.value(prim, name, When::Default)? {
            None | Some(sdf::Value::ValueBlock) => Ok(fallback.to_owned()),
            Some(v) => token(&v)
                .map(str::to_owned)
                .ok_or_else(|| self.err(prim, name, format!("expected a token, found {}", type_of(&v)))),
        }
    }

    fn interp(&self, prim: &Prim, name: &str, fallback: Interp) -> Result<Interp, UsdError> {
        let v = prim
            .attribute(name)
            .get_metadata::<sdf::Value>("interpolation")
            .map_err(|e| self.err(prim, name, format!("interpolation: {e:#}")))?;
        let Some(v) = v else { return Ok(fallback) };
        match token(&v) {
            Some("constant") => Ok(Interp::Constant),
            Some("uniform") => Ok(Interp::Uniform),
            Some("varying" | "faceVarying") => Ok(Interp::Varying),
            Some("vertex") => Ok(Interp::Vertex),
            _ => Err(self.err(prim, name, format!("unknown interpolation {v:?}"))),
        }
    }

    /// A float or colour array attribute with its interpolation (indexed primvars expanded), `None` when
    /// unauthored or blocked.
    fn primvar(
        &self,
        prim: &Prim,
        name: &'static str,
        when: When,
        fallback: Interp,
    ) -> Result<Option<Primvar>, UsdError> {
        let Some(v) = self.value(prim, name, when)? else {
            return Ok(None);
        };
        if matches!(v, sdf::Value::ValueBlock) {
            return Ok(None);
        }
        let mut values = vec4s(&v).ok_or_else(|| {
            self.err(
                prim,
                name,
                format!("expected a float or vector array, found {}", type_of(&v)),
            )
        })?;
        let indices_name = format!("{name}:indices");
        if let Some(iv) = self.value(prim, &indices_name, when)? {
            let idx = ints(&iv).ok_or_else(|| {
                self.err(
                    prim,
                    &indices_name,
                    format!("expected int[], found {}", type_of(&iv)),
                )
            })?;
            values = idx
                .iter()
                .enumerate()
                .map(|(i, &k)| {
                    usize::try_from(k)
                        .ok()
                        .and_then(|k| values.get(k).copied())
                        .ok_or_else(|| {
                            self.err(
                                prim,
                                &indices_name,
                                format!("index {i} is {k}, outside the {} values", values.len()),
                            )
                        })
                })
                .collect::<Result<_, _>>()?;
        }
        if let Some((i, x)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(self.err(prim, name, format!("value {i} is not finite: {x}")));
        }
        let interp = self.interp(prim, name, fallback)?;
        Ok(Some(Primvar { name, values, interp }))
    }

    /// The prim's world transform (its `xformOp`s and its ancestors') at `when`, then the axis and unit conversion.
    /// Each prim's world transform is kept ([`Reader::worlds`]), so a deep stage composes each ancestor once, not
    /// once per prim below it.
    fn world(&self, prim: &Prim, when: When) -> Result<DMat4, UsdError> {
        let (time, key) = match when {
            When::Default => (TimeCode::new(0.0), None),
            When::At(t) => (TimeCode::new(t), Some(t.to_bits())),
        };
        let mut worlds = self.worlds.borrow_mut();
        // Up from the prim to an ancestor already composed, a `!resetXformStack!` or a root prim: each prim's local
        // transform.
        let mut chain = Vec::new();
        let mut path = prim.path().clone();
        let mut m = loop {
            if let Some(&w) = worlds.get(&(path.clone(), key)) {
                break w;
            }
            let (local, resets) = self.local_transform(&self.stage.prim(path.clone()), time)?;
            let parent = path.parent();
            chain.push((path, local));
            match parent {
                Some(parent) if !resets && parent != sdf::Path::abs_root() => path = parent,
                _ => break DMat4::IDENTITY,
            }
        };
        for (path, local) in chain.into_iter().rev() {
            m *= local;
            worlds.insert((path, key), m);
        }
        Ok(self.to_world * m)
    }

    /// A prim's own transform (its `xformOp`s at `time`) and whether it resets the transform stack.
    fn local_transform(&self, p: &Prim, time: TimeCode) -> Result<(DMat4, bool), UsdError> {
        let x = AnyXformable(p.clone());
        // The crate builds a property path from each op name and, for a name that is not an identifier
        // (`xformOp:a}b`), overflows the stack resolving it (found by the fuzz run): checked first.
        if let Some(order) = x
            .xform_op_order()
            .map_err(|e| self.err(p, "xformOpOrder", format!("{e:#}")))?
            && let Some(bad) = order.iter().find(|op| {
                let op = op.strip_prefix("!invert!").unwrap_or(op);
                op != "!resetXformStack!" && !is_property_name(op)
            })
        {
            return Err(self.err(p, "xformOpOrder", format!("{bad:?} is not an xformOp name")));
        }
        let local = x
            .local_to_parent_transform(time)
            .map_err(|e| self.err(p, "xformOpOrder", format!("{e:#}")))?;
        // The crate's matrices are row-major for row vectors (p' = p·M): read as columns, they are glam's.
        let local = DMat4::from_cols_array(&local.0);
        if !local.is_finite() {
            return Err(self.err(p, "xformOpOrder", "the transform is not finite"));
        }
        let resets = x
            .resets_xform_stack()
            .map_err(|e| self.err(p, "xformOpOrder", format!("{e:#}")))?;
        Ok((local, resets))
    }

    /// Points (`point3f[]` and kin) of a prim at `when`; missing points are an error.
    fn points(&self, prim: &Prim, when: When) -> Result<Vec<DVec3>, UsdError> {
        let v = self
            .value(prim, "points", when)?
            .ok_or_else(|| self.err(prim, "points", "missing"))?;
        let p = vec4s(&v)
            .filter(|_| {
                !matches!(
                    v,
                    sdf::Value::FloatVec(_) | sdf::Value::DoubleVec(_) | sdf::Value::HalfVec(_)
                )
            })
            .ok_or_else(|| {
                self.err(
                    prim,
                    "points",
                    format!("expected point3f[], found {}", type_of(&v)),
                )
            })?;
        if let Some((i, x)) = p.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(self.err(
                prim,
                "points",
                format!("point {i} is not finite: {}", x.truncate()),
            ));
        }
        Ok(p.into_iter().map(DVec4::truncate).collect())
    }

    /// Non-negative counts summing to `total`.
    fn counts(&self, prim: &Prim, name: &str, when: When, total: usize) -> Result<Vec<usize>, UsdError> {
        let v = self
            .value(prim, name, when)?
            .ok_or_else(|| self.err(prim, name, "missing"))?;
        let c =
            ints(&v).ok_or_else(|| self.err(prim, name, format!("expected int[], found {}", type_of(&v))))?;
        let mut sum = 0u64;
        let mut out = Vec::with_capacity(c.len().min(total + 1));
        for (i, &k) in c.iter().enumerate() {
            let k =
                u64::try_from(k).map_err(|_| self.err(prim, name, format!("count {i} is {k}, below 0")))?;
            sum = sum.saturating_add(k);
            if sum > total as u64 {
                break;
            }
            out.push(k as usize);
        }
        if sum != total as u64 || out.len() != c.len() {
            let sum: i128 = c.iter().map(|&k| i128::from(k)).sum();
            return Err(self.err(
                prim,
                name,
                format!("the counts sum to {sum}, the prim has {total} points"),
            ));
        }
        Ok(out)
    }
}

/// The geometry prims of a stage, in depth-first order.
struct GeomPrims {
    curves: Vec<Prim>,
    meshes: Vec<Prim>,
    /// One line per other geometry prim, dropped.
    notes: Vec<String>,
}

/// Whether `name` is a USD identifier (a letter or `_`, then letters, digits or `_`; Unicode letters allowed).
fn is_identifier(name: &str) -> bool {
    let mut c = name.chars();
    c.next().is_some_and(|f| f == '_' || f.is_alphabetic()) && c.all(|ch| ch == '_' || ch.is_alphanumeric())
}

/// Whether `name` is a namespaced property name (identifiers joined by `:`).
fn is_property_name(name: &str) -> bool {
    name.split(':').all(is_identifier)
}

/// The stage's geometry prims in depth-first order ([`GeomPrims`]). The walk is hairlab's, not the crate's `Stage::traverse`, so every child name is checked before a path
/// is built from it: the crate (0.6.0) accepts a prim named `a}`, whose path is then its own parent, and walking
/// its ancestors overflows the stack (found by the fuzz run). It keeps what OpenUSD's default traversal keeps:
/// active, loaded, defined, non-abstract prims and their descendants.
fn prims(r: &Reader) -> Result<GeomPrims, UsdError> {
    let (mut curves, mut meshes, mut notes) = (Vec::new(), Vec::new(), Vec::new());
    let mut stack = vec![r.stage.prim(sdf::Path::abs_root())];
    while let Some(prim) = stack.pop() {
        let crate_err = |what: &str, e: anyhow::Error| r.err(&prim, what, format!("{e:#}"));
        let names = prim.child_names().map_err(|e| crate_err("(children)", e))?;
        let mut children = Vec::with_capacity(names.len());
        for name in names {
            if !is_identifier(name.as_str()) {
                return Err(r.err(
                    &prim,
                    "(children)",
                    format!("the child prim name {:?} is not a USD identifier", name.as_str()),
                ));
            }
            let path = prim
                .path()
                .append_path(name.as_str())
                .map_err(|e| crate_err("(children)", e))?;
            children.push(r.stage.prim(path));
        }
        // Reversed onto the stack, so the first child is visited first. The walk only enters active `def` prims,
        // so each child's own opinions decide (the crate's `is_active`, `is_defined`, `is_abstract` walk every
        // ancestor again: the square of the depth per prim). Every payload is loaded, so active is loaded.
        for child in children.into_iter().rev() {
            let status_err = |e: anyhow::Error| r.err(&child, "(status)", format!("{e:#}"));
            let def = child.specifier().map_err(status_err)? == Some(sdf::Specifier::Def);
            if def && child.is_active_here().map_err(status_err)? {
                stack.push(child);
            }
        }
        if prim.path() == &sdf::Path::abs_root() {
            continue;
        }
        let ty = prim
            .type_name()
            .map_err(|e| r.err(&prim, "typeName", format!("{e:#}")))?;
        match ty.as_ref().map(tf::Token::as_str) {
            Some("BasisCurves") => curves.push(prim),
            Some("Mesh") => meshes.push(prim),
            Some(
                t
                @ ("NurbsCurves" | "HermiteCurves" | "Points" | "NurbsPatch" | "PointInstancer" | "TetMesh"),
            ) => {
                notes.push(format!("{}: {t} prim dropped (not read)", prim.path().as_str()));
            }
            _ => {}
        }
    }
    Ok(GeomPrims {
        curves,
        meshes,
        notes,
    })
}

/// The sorted union of the time codes of the curves' `points.timeSamples`.
fn time_codes(r: &Reader, curves: &[Prim]) -> Result<Vec<f64>, UsdError> {
    let mut t = Vec::new();
    for prim in curves {
        let times = prim
            .attribute("points")
            .time_sample_times()
            .map_err(|e| r.err(prim, "points", format!("timeSamples: {e:#}")))?;
        if let Some(x) = times.iter().find(|x| !x.is_finite()) {
            return Err(r.err(prim, "points", format!("time code {x} is not finite")));
        }
        t.extend(times);
    }
    t.sort_by(f64::total_cmp);
    t.dedup();
    Ok(t)
}

fn read_strands(
    r: &Reader,
    curves: &[Prim],
    when: When,
    notes: &mut Vec<String>,
) -> Result<Strands, UsdError> {
    let mut strands = Strands::default();
    for prim in curves {
        strands.append(&read_curves(r, prim, when, notes)?);
    }
    Ok(strands)
}

/// Reads a stage (`.usda`, `.usdc`, `.usdz`): its curves at their first time code (or their default values when
/// none is sampled) and its meshes, in hairlab's world (Y-up, metres). Errors name the file, prim and attribute.
pub fn read_usd_file(path: &Path) -> Result<UsdScene, UsdError> {
    let r = open(path)?;
    let GeomPrims {
        curves,
        meshes: mesh_prims,
        mut notes,
    } = prims(&r)?;
    let time_codes = time_codes(&r, &curves)?;
    let when = time_codes.first().map_or(When::Default, |&t| When::At(t));
    let strands = read_strands(&r, &curves, when, &mut notes)?;
    let meshes = mesh_prims
        .iter()
        .map(|p| read_mesh(&r, p))
        .collect::<Result<Vec<_>, _>>()?;
    if r.up_axis == 'Z' {
        notes.push("upAxis Z → Y-up (x, y, z) → (x, z, −y)".into());
    }
    if r.meters_per_unit != 1.0 {
        notes.push(format!("metersPerUnit {} → metres", r.meters_per_unit));
    }
    Ok(UsdScene {
        strands,
        meshes,
        up_axis: r.up_axis,
        meters_per_unit: r.meters_per_unit,
        time_codes_per_second: r.stage.time_codes_per_second(),
        time_codes,
        notes,
        warnings: warnings(&r),
    })
}

/// Reads the curves of a stage at every time code of their `points.timeSamples` (one frame at the default values
/// when none is sampled), at the stage's `timeCodesPerSecond`. The topology must stay the frame's first: a
/// different curve count or point count is an error naming the time code.
pub fn read_usd_frames(path: &Path) -> Result<UsdFrames, UsdError> {
    let r = open(path)?;
    let curves = prims(&r)?.curves;
    let codes = time_codes(&r, &curves)?;
    let whens: Vec<When> = if codes.is_empty() {
        vec![When::Default]
    } else {
        codes.iter().map(|&t| When::At(t)).collect()
    };
    let mut frames: Vec<Strands> = Vec::with_capacity(whens.len());
    for (i, &when) in whens.iter().enumerate() {
        let s = read_strands(&r, &curves, when, &mut Vec::new()).map_err(|e| match (e, when) {
            (
                UsdError::Attribute {
                    file,
                    prim,
                    attribute,
                    cause,
                },
                When::At(t),
            ) => UsdError::Attribute {
                file,
                prim,
                attribute,
                cause: format!("at time code {t}: {cause}"),
            },
            (e, _) => e,
        })?;
        if let Some(f0) = frames.first()
            && (s.counts != f0.counts || s.points.len() != f0.points.len())
        {
            return Err(UsdError::Stage {
                file: path.to_owned(),
                cause: format!(
                    "time code {}: {} strands of {} points, time code {} has {} strands of {} points (the \
                     topology of a sequence must not change)",
                    codes[i],
                    s.counts.len(),
                    s.points.len(),
                    codes[0],
                    f0.counts.len(),
                    f0.points.len()
                ),
            });
        }
        frames.push(s);
    }
    Ok(UsdFrames {
        frames,
        time_codes: codes,
        time_codes_per_second: r.stage.time_codes_per_second(),
        warnings: warnings(&r),
    })
}
