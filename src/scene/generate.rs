//! Seeded, deterministic procedural hair: a head (an ellipsoid scalp grown with hair), a hair patch (roots on
//! a square, growing up), hair grown on a loaded scalp mesh, or guard hairs on the paper's fur base meshes
//! (Andersen et al. 2016, Table 1: [`crate::scene::fur_shapes`]).
//!
//! Every strand is traced with `segments` steps of exactly `length / segments`, so its points are evenly
//! spaced in arc length and it is `length` long. Each step goes along the strand's growth direction, which
//! starts along the root normal and turns towards −Y with `gravity` (head and scalp only); the style tilts
//! each step sideways — a sine for wavy hair (lateral amplitude `wave_amplitude`, `wave_frequency` waves over
//! the length), a helix for curly hair (radius `curl_radius`, `curl_turns` turns over the length) — with a
//! random phase per strand. On the generated head a step that would enter the head slides along it instead.
//! Clumping then makes each strand follow its nearest clump centre strand, offset by the difference of their
//! roots, the offset shrinking towards the tip by `clump_strength`.
//!
//! With `strand_colors` each strand gets a slight random variation around a brown; without, the strands have
//! no colour array and take the renderer's hair colour. Per-point thickness and alpha arrays are written only
//! when `taper` or `tip_transparency` is not neutral ([`crate::scene::style::style`]).
//!
//! Randomness comes from [`crate::rng::SplitMix64`] streams derived from `seed` (one for roots, one per strand), so the same
//! parameters give bit-identical output.

use super::progress::BATCH;
use crate::progress::{Progress, Quiet, share};
use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

mod mesh_roots;
mod meshes;

use super::fur_shapes as shapes;
use super::style;
use super::{Mesh, Scene, Strands};
use crate::rng::SplitMix64 as Rng;
use mesh_roots::{SCALP_MIN_NORMAL_Y, mesh_roots, mesh_triangles};
use meshes::{ellipsoid_mesh, floor_mesh};

/// Most points [`generate`] produces (about 1.2 GB of positions and colours).
pub const MAX_POINTS: u64 = 50_000_000;
/// Longest strand [`generate`] accepts, in world units (keeps every coordinate far from `f32` overflow).
pub const MAX_LENGTH: f32 = 10_000.0;
/// Radii of the generated head ellipsoid (x: ear to ear, y: up, z: towards the face, which looks down +Z).
pub const HEAD_RADII: Vec3 = Vec3::new(0.09, 0.115, 0.10);
const BROWN: Vec3 = Vec3::new(0.30, 0.19, 0.11);
/// Turning rate towards −Y, in radians per strand length, at `gravity` = 1.
const GRAVITY_TURN: f32 = 8.0;
/// The largest sideways tilt (sine of the angle) a style may give a step.
const MAX_TILT: f32 = 0.95;
/// Direction head hair is combed in at the root (back and a little down, away from the face).
const COMB: Vec3 = Vec3::new(0.0, -0.4, -1.0);
/// Weight of the normal against the unit comb direction in a head root's start direction (0.6: about 59° off
/// the normal), so hair lies along the scalp instead of standing up where gravity cannot bend it (at the
/// crown).
const ROOT_LIFT: f32 = 0.6;
/// Steps landing inside this multiple of the head's radii slide along the head instead of entering it.
const HEAD_SHELL: f32 = 1.03;

/// What to grow hair on. The names (kebab-case) are the same in presets and on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum GenKind {
    /// An ellipsoid head, included as an opaque mesh, with hair on its upper and back part.
    #[default]
    #[value(help = "an ellipsoid head with hair on its upper and back part")]
    Head,
    /// A block of hair (or grass): roots on a square at y = 0, growing up +Y; `gravity` does not apply.
    #[value(help = "a block of hair (or grass) growing up from a square")]
    Patch,
    /// Stress scene (Sintorn & Assarsson Fig. 4/5a): a dense clump of `strands` and `clumps` (at least one)
    /// stray strands a clump width in front of it towards +X, where the stress presets put the light, spread
    /// across the clump's width. Breaks Deep Opacity Maps: a stray strand sets its texels' start depth and
    /// their layers end before the clump.
    #[value(help = "a dense clump with stray strands in front of it (breaks Deep Opacity Maps)")]
    StrayStrand,
    /// Stress scene (Voicu §4.1/5.5): a short wide patch (a tenth of `length`) beside a tall narrow clump, both
    /// growing up +Y, lit from above: one fixed layer depth cannot fit both. Bounding Opacity Maps fit each.
    #[value(help = "a short wide patch beside a tall narrow clump (one layer depth cannot fit both)")]
    MixedSizes,
    /// Stress scene (Mertens et al. Fig. 5): `clumps` (Q) thin horizontal sheets of hair stacked along +Y and
    /// lit from above, so every texel sees Q separated clusters; Density Clustering has K = 4.
    #[value(help = "`clumps` stacked sheets of hair (more clusters than Density Clustering's four)")]
    ManyClumps,
    /// Fur (Andersen et al. 2016, Fig. 1 / Table 1): the 3584-triangle cylinder of
    /// [`shapes::fur_cylinder`] as an opaque mesh, guard hairs grown on all of it.
    #[value(help = "guard hairs on the paper's 3584-triangle cylinder (fur, Fig. 1)")]
    FurCylinder,
    /// Fur (Andersen et al. 2016, Fig. 9 / Table 1): the 5632-triangle hat of [`shapes::fur_hat`] as an
    /// opaque mesh, guard hairs grown on all of it.
    #[value(help = "guard hairs on the paper's 5632-triangle hat (fur, Fig. 9)")]
    FurHat,
}

/// Shape of each strand.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum HairStyle {
    Straight,
    #[default]
    Wavy,
    Curly,
}

/// Generator parameters, as written in presets (TOML) and set from the CLI and GUI.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GenParams {
    pub kind: GenKind,
    pub style: HairStyle,
    /// Strand count before density scaling.
    pub strands: u32,
    /// Multiplier on `strands` (rounded to the nearest whole strand).
    pub density: f32,
    /// Segments per strand (1..=65535, the `.hair` limit).
    pub segments: u32,
    /// Strand length in world units.
    pub length: f32,
    /// Number of clumps; 0 = no clumping.
    pub clumps: u32,
    /// 0..1: how far tips pull towards their clump centre strand.
    pub clump_strength: f32,
    /// Wavy: lateral amplitude in world units.
    pub wave_amplitude: f32,
    /// Wavy: waves over the strand length.
    pub wave_frequency: f32,
    /// Curly: helix radius in world units.
    pub curl_radius: f32,
    /// Curly: helix turns over the strand length.
    pub curl_turns: f32,
    /// How much hair droops (head and scalp): 0 = grows straight along the root normal.
    pub gravity: f32,
    pub seed: u64,
    /// Adds a ground quad under the hair, an opaque mesh that receives hair shadows.
    pub floor: bool,
    /// Writes a per-strand brown colour variation. Off by default: strands without colours take the
    /// renderer's hair colour, so the colour control applies.
    pub strand_colors: bool,
    /// Tip thickness over root thickness, in [0, 1]; the thickness falls linearly from root to tip (truncated
    /// cones). 1 (the default) writes no thickness array.
    pub taper: f32,
    /// τ_tip ≥ 0: per-point alpha `exp(−τ_tip · s)`, s = 0 at the root to 1 at the tip (B.3 #14). 0 (the
    /// default) writes no alpha array.
    pub tip_transparency: f32,
}

impl Default for GenParams {
    /// A wavy head of 3000 strands × 24 segments = 72 000 segments.
    fn default() -> Self {
        GenParams {
            kind: GenKind::Head,
            style: HairStyle::Wavy,
            strands: 3000,
            density: 1.0,
            segments: 24,
            length: 0.25,
            clumps: 120,
            clump_strength: 0.5,
            wave_amplitude: 0.006,
            wave_frequency: 3.0,
            curl_radius: 0.006,
            curl_turns: 4.0,
            gravity: 1.0,
            seed: 1,
            floor: true,
            strand_colors: false,
            taper: 1.0,
            tip_transparency: 0.0,
        }
    }
}

/// Invalid generator parameters or scalp meshes. Each message names the parameter at fault.
#[derive(Debug, Error, PartialEq)]
pub enum GenError {
    #[error("invalid {param} = {value}: {rule}")]
    Param {
        param: &'static str,
        value: String,
        rule: &'static str,
    },
    #[error("strands × density = {strands} × {density} rounds to no strands; at least 1 is needed")]
    NoStrands { strands: u32, density: f32 },
    #[error("{strands} strands × ({segments} segments + 1) = {points} points, more than the cap of {cap}")]
    TooManyPoints {
        strands: u64,
        segments: u32,
        points: u64,
        cap: u64,
    },
    #[error("scalp mesh: {reason}")]
    BadScalp { reason: String },
    #[error("scalp mesh has no upward-facing triangles (normal.y > -0.2) to grow hair on")]
    NoScalpArea,
    #[error("fur base mesh has no triangles of non-zero area to grow guard hairs on")]
    NoMeshArea,
}

/// Generates the scene `p` describes: hair plus the head mesh (head kind) or the fur base mesh (fur kinds)
/// and the floor (if `p.floor`), the strands styled by `taper` and `tip_transparency`.
pub fn generate(p: &GenParams) -> Result<Scene, GenError> {
    generate_with(p, &mut Quiet)
}

/// [`generate`] telling `progress` the share of the strands grown every [`BATCH`] strands; once it answers
/// `false` the growth stops and the scene holds the strands grown so far.
pub fn generate_with(p: &GenParams, progress: &mut dyn Progress) -> Result<Scene, GenError> {
    let n = validate(p)?;
    let mut rng = Rng::stream(p.seed, 0);
    let (mut strands, mut meshes) = match p.kind {
        GenKind::Head => {
            let roots: Vec<Root> = (0..n).map(|_| head_root(&mut rng)).collect();
            (
                grow_all(p, p.gravity, &roots, Some(HEAD_RADII), progress),
                vec![ellipsoid_mesh(HEAD_RADII)],
            )
        }
        GenKind::Patch => (
            grow_all(p, 0.0, &patch_roots(n, p.length * 0.6, &mut rng), None, progress),
            Vec::new(),
        ),
        GenKind::StrayStrand => (stray_strand(p, n, &mut rng, progress), Vec::new()),
        GenKind::MixedSizes => (mixed_sizes(p, n, &mut rng, progress), Vec::new()),
        GenKind::ManyClumps => (many_clumps(p, n, &mut rng, progress), Vec::new()),
        GenKind::FurCylinder | GenKind::FurHat => {
            let mesh = if p.kind == GenKind::FurCylinder {
                shapes::fur_cylinder()
            } else {
                shapes::fur_hat()
            };
            (grow_on_mesh(p, &mesh, progress)?, vec![mesh])
        }
    };
    style::style(&mut strands, p.taper, p.tip_transparency);
    if p.floor {
        let floor_y = match p.kind {
            GenKind::Patch | GenKind::StrayStrand | GenKind::MixedSizes => Some(0.0),
            GenKind::Head | GenKind::ManyClumps | GenKind::FurCylinder | GenKind::FurHat => None,
        };
        meshes.push(floor_mesh(&strands, &meshes, floor_y));
    }
    Ok(Scene::new(strands, meshes))
}

/// Grows hair on a loaded scalp mesh: roots on random points of its upward-facing triangles (normal.y >
/// -0.2), area-weighted, growing along the interpolated normal and drooping with gravity. `p.kind` is
/// ignored; the scene holds the scalp mesh itself, the hair and (if `p.floor`) a floor. Strands are not kept
/// out of the mesh.
pub fn generate_on_scalp(p: &GenParams, scalp: &Mesh) -> Result<Scene, GenError> {
    generate_on_scalp_with(p, scalp, &mut Quiet)
}

/// [`generate_on_scalp`] telling `progress` as [`generate_with`] does.
pub fn generate_on_scalp_with(
    p: &GenParams,
    scalp: &Mesh,
    progress: &mut dyn Progress,
) -> Result<Scene, GenError> {
    let n = validate(p)?;
    let tris = mesh_triangles(scalp, Some(SCALP_MIN_NORMAL_Y))?;
    if tris.last().is_none_or(|t| t.cum_area <= 0.0) {
        return Err(GenError::NoScalpArea);
    }
    let mut strands = grow_all(p, p.gravity, &mesh_roots(scalp, &tris, n, p.seed), None, progress);
    style::style(&mut strands, p.taper, p.tip_transparency);
    let mut meshes = vec![scalp.clone()];
    if p.floor {
        meshes.push(floor_mesh(&strands, &meshes, None));
    }
    Ok(Scene::new(strands, meshes))
}

/// Grows `p`'s strands on every triangle of `mesh` (area-weighted roots, along the interpolated normal,
/// drooping with gravity), unstyled: the growth [`generate_on_scalp`] does, without its upward-facing filter,
/// for fur base meshes ([`crate::scene::style`]). `p.kind`, `p.floor`, `p.taper` and `p.tip_transparency`
/// are not used here.
pub fn grow_on_mesh(p: &GenParams, mesh: &Mesh, progress: &mut dyn Progress) -> Result<Strands, GenError> {
    let n = validate(p)?;
    let tris = mesh_triangles(mesh, None)?;
    if tris.last().is_none_or(|t| t.cum_area <= 0.0) {
        return Err(GenError::NoMeshArea);
    }
    Ok(grow_all(
        p,
        p.gravity,
        &mesh_roots(mesh, &tris, n, p.seed),
        None,
        progress,
    ))
}

/// Checks the parameters and returns the strand count after density scaling.
fn validate(p: &GenParams) -> Result<usize, GenError> {
    fn param(param: &'static str, value: impl ToString, rule: &'static str) -> GenError {
        GenError::Param {
            param,
            value: value.to_string(),
            rule,
        }
    }
    if !(1..=65535).contains(&p.segments) {
        return Err(param(
            "segments",
            p.segments,
            "must be in 1..=65535 (the .hair format stores u16 counts)",
        ));
    }
    if !(p.length > 0.0 && p.length <= MAX_LENGTH) {
        return Err(param("length", p.length, "must be positive and at most 10000"));
    }
    if !(p.density.is_finite() && p.density >= 0.0) {
        return Err(param("density", p.density, "must be finite and not negative"));
    }
    if !(0.0..=1.0).contains(&p.clump_strength) {
        return Err(param("clump_strength", p.clump_strength, "must lie in [0, 1]"));
    }
    for (name, v) in [
        ("wave_amplitude", p.wave_amplitude),
        ("wave_frequency", p.wave_frequency),
        ("curl_radius", p.curl_radius),
        ("curl_turns", p.curl_turns),
        ("gravity", p.gravity),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(param(name, v, "must be finite and not negative"));
        }
    }
    if !(0.0..=1.0).contains(&p.taper) {
        return Err(param(
            "taper",
            p.taper,
            "must lie in [0, 1] (tip thickness / root thickness)",
        ));
    }
    if !(p.tip_transparency.is_finite() && p.tip_transparency >= 0.0) {
        return Err(param(
            "tip_transparency",
            p.tip_transparency,
            "must be finite and not negative",
        ));
    }
    for (name, v) in [("wave_frequency", p.wave_frequency), ("curl_turns", p.curl_turns)] {
        if !(std::f32::consts::TAU * v / p.length).is_finite() {
            return Err(param(name, v, "is too large for the strand length"));
        }
    }
    let n = (f64::from(p.strands) * f64::from(p.density)).round();
    if n < 1.0 {
        return Err(GenError::NoStrands {
            strands: p.strands,
            density: p.density,
        });
    }
    let points = n * (f64::from(p.segments) + 1.0);
    if points > MAX_POINTS as f64 {
        return Err(GenError::TooManyPoints {
            strands: n as u64,
            segments: p.segments,
            points: points as u64,
            cap: MAX_POINTS,
        });
    }
    Ok(n as usize)
}

#[derive(Clone, Copy, Debug)]
struct Root {
    pos: Vec3,
    /// Unit initial growth direction.
    dir: Vec3,
}

/// Is the unit-sphere direction `w` on the scalp? Above a hairline that runs from the nape (low at the back)
/// over the ears to the forehead (high at the front), so the face and the neck stay bare.
fn on_scalp(w: Vec3) -> bool {
    w.y > 0.133 + 0.633 * w.z
}

/// A root on the scalp part of the head ellipsoid, uniform in area (rejection sampling).
fn head_root(rng: &mut Rng) -> Root {
    let r = HEAD_RADII;
    let min_r = r.min_element();
    loop {
        let y = rng.range(-1.0, 1.0);
        let phi = rng.angle();
        let s = (1.0 - y * y).max(0.0).sqrt();
        let w = Vec3::new(s * phi.cos(), y, s * phi.sin());
        // The map w ↦ r·w scales area by r.x·r.y·r.z·|w / r|; accept in proportion to it.
        let accept = (w / r).length() * min_r;
        if on_scalp(w) && rng.unit() < accept {
            let normal = (w / r).normalize_or(Vec3::Y);
            // Combed back and down: lean the start direction into the scalp's tangent plane along COMB.
            let comb = COMB.reject_from_normalized(normal).normalize_or(Vec3::NEG_Z);
            return Root {
                pos: w * r,
                dir: (normal * ROOT_LIFT + comb).normalize_or(normal),
            };
        }
    }
}

/// `n` roots jittered in the cells of a square grid of side `side` at y = 0 (a random subset of cells when
/// `n` is not a square), growing up +Y with a slight random tilt.
fn patch_roots(n: usize, side: f32, rng: &mut Rng) -> Vec<Root> {
    let mut m = n.isqrt();
    if m * m < n {
        m += 1;
    }
    let mut cells: Vec<usize> = (0..m * m).collect();
    for i in 0..n.min(cells.len()) {
        let j = rng.int(i, cells.len() - 1);
        cells.swap(i, j);
    }
    cells
        .iter()
        .take(n)
        .map(|&c| {
            let (cx, cz) = ((c % m) as f32, (c / m) as f32);
            let x = ((cx + rng.unit()) / m as f32 - 0.5) * side;
            let z = ((cz + rng.unit()) / m as f32 - 0.5) * side;
            let tilt = Vec3::new(rng.range(-0.15, 0.15), 0.0, rng.range(-0.15, 0.15));
            Root {
                pos: Vec3::new(x, 0.0, z),
                dir: (Vec3::Y + tilt).normalize(),
            }
        })
        .collect()
}

/// A patch of `n` strands of `length` on a square of side `side`, growing up +Y (no clumping), moved by
/// `offset`.
fn patch_block(
    p: &GenParams,
    n: usize,
    side: f32,
    length: f32,
    offset: Vec3,
    rng: &mut Rng,
    progress: &mut dyn Progress,
) -> Strands {
    let q = GenParams {
        length,
        clumps: 0,
        ..p.clone()
    };
    let mut s = grow_all(&q, 0.0, &patch_roots(n, side, rng), None, progress);
    for x in &mut s.points {
        *x += offset;
    }
    s
}

fn stray_strand(p: &GenParams, n: usize, rng: &mut Rng, progress: &mut dyn Progress) -> Strands {
    let side = p.length * 0.4;
    let mut s = patch_block(p, n, side, p.length, Vec3::ZERO, rng, progress);
    let stray = GenParams {
        style: HairStyle::Straight,
        ..p.clone()
    };
    let count = p.clumps.max(1);
    for k in 0..count {
        // Spread across the clump's width (towards the viewer), a clump width in front of it towards +X.
        let z = if count == 1 {
            0.0
        } else {
            (k as f32 / (count - 1) as f32 - 0.5) * side
        };
        s.append(&patch_block(
            &stray,
            1,
            0.0,
            p.length,
            Vec3::new(p.length * 0.6, 0.0, z),
            rng,
            progress,
        ));
    }
    s
}

fn mixed_sizes(p: &GenParams, n: usize, rng: &mut Rng, progress: &mut dyn Progress) -> Strands {
    let half = n.div_ceil(2);
    let l = p.length;
    let at = Vec3::new(-l * 0.3, 0.0, 0.0);
    let mut s = patch_block(p, half, l * 0.4, l * 0.1, at, rng, progress);
    s.append(&patch_block(
        p,
        (n - half).max(1),
        l * 0.15,
        l,
        Vec3::new(l * 0.2, 0.0, 0.0),
        rng,
        progress,
    ));
    s
}

fn many_clumps(p: &GenParams, n: usize, rng: &mut Rng, progress: &mut dyn Progress) -> Strands {
    let q = p.clumps.max(1) as usize;
    let gap = p.length * 0.3;
    let mut out = Strands::default();
    for k in 0..q {
        // A patch grown along +Y, laid down along +X and squashed into a thin sheet at height k * gap.
        let mut sheet = patch_block(p, (n / q).max(1), p.length, p.length, Vec3::ZERO, rng, progress);
        for x in &mut sheet.points {
            *x = Vec3::new(x.y - p.length * 0.5, k as f32 * gap + x.x * 0.03, x.z);
        }
        out.append(&sheet);
    }
    out
}

/// Grows one strand per root (drooping with `gravity`, kept out of the ellipsoid `head`), applies clumping,
/// and colours the strands when `p.strand_colors` is set. Tells `progress` the share grown every [`BATCH`]
/// strands and stops growing once it answers `false`.
fn grow_all(
    p: &GenParams,
    gravity: f32,
    roots: &[Root],
    head: Option<Vec3>,
    progress: &mut dyn Progress,
) -> Strands {
    let per = p.segments as usize + 1;
    let mut points = Vec::with_capacity(roots.len() * per);
    let mut color = Vec::with_capacity(if p.strand_colors { roots.len() * per } else { 0 });
    let mut grown = 0;
    for (i, root) in roots.iter().enumerate() {
        if i % BATCH == 0 && !progress.step("growing the strands", share(i, roots.len())) {
            break;
        }
        grown = i + 1;
        let mut rng = Rng::stream(p.seed, i as u64 + 1);
        grow_strand(p, gravity, root, head, &mut rng, &mut points);
        if p.strand_colors {
            let tint = Vec3::new(rng.range(0.9, 1.1), rng.range(0.9, 1.1), rng.range(0.9, 1.1))
                * rng.range(0.75, 1.25);
            color.extend(std::iter::repeat_n((BROWN * tint).min(Vec3::ONE), per));
        }
    }
    // A stopped build keeps the strands grown so far.
    let roots = &roots[..grown];
    clump(p, roots, head, &mut points);
    Strands {
        points,
        counts: vec![per as u32; roots.len()],
        thickness: None,
        alpha: None,
        color: p.strand_colors.then_some(color),
    }
}

/// Removes the component of `d` that would take a step of length `h` from `p` into the head shell; by
/// convexity the step then never gets closer to the head.
fn slide_on_head(p: Vec3, d: Vec3, h: f32, radii: Option<Vec3>) -> Vec3 {
    let Some(r) = radii else { return d };
    if ((p + d * h) / (r * HEAD_SHELL)).length_squared() >= 1.0 {
        return d;
    }
    let Some(g) = (p / (r * r)).try_normalize() else {
        return d;
    };
    let inward = d.dot(g);
    if inward >= 0.0 {
        return d;
    }
    (d - g * inward)
        .try_normalize()
        .unwrap_or_else(|| g.any_orthonormal_vector())
}

/// Turns the unit direction `t` towards −Y by `angle` radians, stopping at −Y. A direction pointing straight
/// up has no preferred way down and stays.
fn droop(t: Vec3, angle: f32) -> Vec3 {
    let Some(side) = Vec3::NEG_Y.reject_from_normalized(t).try_normalize() else {
        return t;
    };
    let a = angle.min(t.dot(Vec3::NEG_Y).clamp(-1.0, 1.0).acos());
    (t * a.cos() + side * a.sin()).normalize_or(t)
}

/// Traces one strand of `p.segments` steps of exactly `p.length / p.segments` and appends its points.
fn grow_strand(
    p: &GenParams,
    gravity: f32,
    root: &Root,
    head: Option<Vec3>,
    rng: &mut Rng,
    out: &mut Vec<Vec3>,
) {
    let len = p.length;
    let h = len / p.segments as f32;
    let mut t = root.dir;
    let mut u = Quat::from_axis_angle(t, rng.angle()) * t.any_orthonormal_vector();
    let phase = rng.angle();
    let turn = gravity * GRAVITY_TURN / len;
    let (wave_w, curl_w) = (
        std::f32::consts::TAU * p.wave_frequency / len,
        std::f32::consts::TAU * p.curl_turns / len,
    );
    let mut pos = root.pos;
    out.push(pos);
    for i in 0..p.segments {
        let s = (i as f32 + 0.5) * h;
        let v = t.cross(u);
        let d = match p.style {
            HairStyle::Straight => t,
            HairStyle::Wavy => {
                // Lateral speed k integrates to a sine of amplitude wave_amplitude.
                let k = (p.wave_amplitude * wave_w * (wave_w * s + phase).cos()).clamp(-MAX_TILT, MAX_TILT);
                t * (1.0 - k * k).sqrt() + u * k
            }
            HairStyle::Curly => {
                // Constant lateral speed k rotating at curl_w traces a helix of radius k / curl_w =
                // curl_radius.
                let k = (p.curl_radius * curl_w).min(MAX_TILT);
                let a = curl_w * s + phase;
                t * (1.0 - k * k).sqrt() + (v * a.cos() - u * a.sin()) * k
            }
        };
        pos += slide_on_head(pos, d, h, head) * h;
        out.push(pos);
        let bent = droop(t, turn * h);
        let next = slide_on_head(pos, bent, h, head);
        u = (Quat::from_rotation_arc(t, next) * u)
            .reject_from_normalized(next)
            .normalize_or(u);
        t = next;
    }
}

/// Makes each strand follow its nearest clump centre (the first `clumps` strands, whose roots are random):
/// point j becomes centre_j + (root − centre_root) · (1 − clump_strength · j / segments). On the head, points
/// the offset pushed inside are moved back out onto the head's surface.
fn clump(p: &GenParams, roots: &[Root], head: Option<Vec3>, points: &mut [Vec3]) {
    let k = (p.clumps as usize).min(roots.len());
    if k == 0 {
        return;
    }
    let per = p.segments as usize + 1;
    let centres: Vec<Vec<Vec3>> = points.chunks_exact(per).take(k).map(<[Vec3]>::to_vec).collect();
    for (strand, root) in points.chunks_exact_mut(per).zip(roots).skip(k) {
        let (nearest, _) = centres
            .iter()
            .enumerate()
            .fold((0, f32::INFINITY), |best, (c, centre)| {
                let d = centre
                    .first()
                    .map_or(f32::INFINITY, |q| q.distance_squared(root.pos));
                if d < best.1 { (c, d) } else { best }
            });
        let Some(centre) = centres.get(nearest) else {
            continue;
        };
        let Some(&centre_root) = centre.first() else {
            continue;
        };
        let offset = root.pos - centre_root;
        for (j, (q, cq)) in strand.iter_mut().zip(centre).enumerate() {
            let shrink = 1.0 - p.clump_strength * j as f32 / p.segments as f32;
            *q = *cq + offset * shrink;
            if let Some(r) = head
                && j > 0
            {
                let f = (*q / r).length();
                if f < 1.0 && f > 0.0 {
                    *q /= f;
                }
            }
        }
    }
}

/// Guard hairs (Andersen et al. 2016 §3.1) of `p` (count, length, segments, gravity, style, clumps, seed, taper, tip transparency) grown on
/// every triangle of `mesh`.
pub fn guard_hairs(p: &GenParams, mesh: &Mesh) -> Result<Strands, GenError> {
    let mut strands = grow_on_mesh(p, mesh, &mut Quiet)?;
    style::style(&mut strands, p.taper, p.tip_transparency);
    Ok(strands)
}
