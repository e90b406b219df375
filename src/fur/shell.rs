//! The prismatic shell (spec FR-SHELL, B.3 #2–5): every face of a [`FurMesh`] extruded along its smoothed
//! vertex normals into a triangular prism with base corners `P_k` and top corners `T_k = P_k + h_k N_k`,
//! sliced into `n_l` layers and subdivided `d_v` times per layer (dynamic resolution: `d_v` is the smallest
//! level whose sub-triangles are no larger than an equilateral triangle of edge `ℓ_cell`, from the face's
//! area).
//!
//! A prism is valid when, for every height `w ∈ [0, 1]`, its cross-section `q_k(w) = P_k + w (T_k − P_k)`
//! faces the way the base does and the shell map `(λ, w) ↦ Σ λ_k q_k(w)` keeps a positive Jacobian (its three
//! lateral edges `D_k = T_k − P_k` stay on the front of `q(w)`, `D_k · n(w) > 0`). Both are quadratics in `w`,
//! checked exactly. An invalid prism has the heights at its corners shrunk (×0.8 a pass, down to 10 % of
//! `h_0`), counted in [`ShellReport`]; one that no shrinking fixes is an error naming the face.
//!
//! Point location (mode B of B.3 #4): the height `w` at which `p` lies in the plane of `q(w)` (a cubic, by
//! Newton from the paper's perpendicular-distance estimate), then barycentrics in `q(w)`. `w` is continuous
//! across prisms sharing a lateral face. [`Shell::walk`] is the paper's neighbour walk; [`Shell::locate_brute`]
//! tests every prism and is the reference it is checked against (FC-5).

use glam::{DVec3, Vec3};
use thiserror::Error;

use super::index::{self, MAX_LEVEL};
use super::mesh::{FurMesh, NONE};

/// Most layers per prism (spec FR-LIM).
pub const MAX_LAYERS: u32 = 256;
/// Heights are never shrunk below this fraction of `h_0`.
pub const MIN_HEIGHT_FRACTION: f32 = 0.1;
/// Factor a shrinking pass applies to the heights at an invalid prism's corners.
const SHRINK: f32 = 0.8;
/// Most shrinking passes (0.8^11 < 0.1, so eleven reach the floor; the rest absorb knock-on effects).
const MAX_SHRINK_PASSES: usize = 64;
/// A quadratic counts as positive on `[0, 1]` when its minimum exceeds this fraction of its scale.
const VALID_MARGIN: f64 = 1e-3;
/// The spec's hop cap per step (B.3 #5); [`Shell::hop_cap`] raises it at high-valence vertices.
pub const MIN_HOPS: u32 = 4;
/// Newton iterations for the shell height of a point.
const NEWTON_STEPS: usize = 8;

/// How each face's subdivision level is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Levels {
    /// From the face's area (dynamic resolution), at most `max`.
    Dynamic { max: u32 },
    /// One level for every face: eq. (3) literally.
    Uniform(u32),
}

/// Shell parameters (the paper gives none of them; B.1 "not given").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellParams {
    /// Shell height `h_0` in world units.
    pub height: f32,
    /// Layers per prism, `n_l`.
    pub layers: u32,
    /// Target sub-element edge `ℓ_cell`; `None` = `height / layers` (roughly cubic sub-elements).
    pub cell: Option<f32>,
    pub levels: Levels,
}

impl Default for ShellParams {
    /// 1 cm of undercoat (mink's is about that long) in 16 layers, dynamic levels up to 8.
    fn default() -> Self {
        ShellParams {
            height: 0.01,
            layers: 16,
            cell: None,
            levels: Levels::Dynamic { max: 8 },
        }
    }
}

/// A shell that cannot be built. Each message names the mesh, the key or face, and the problem.
#[derive(Debug, Error, PartialEq)]
pub enum ShellError {
    #[error("fur shell on '{mesh}': invalid {key} = {value}: {rule}")]
    Param {
        mesh: String,
        key: &'static str,
        value: String,
        rule: &'static str,
    },
    #[error(
        "fur shell on '{mesh}': face {face}: the smoothed normal at vertex {vertex} points behind the face, \
         so no shell height gives a valid prism"
    )]
    NormalBehindFace { mesh: String, face: usize, vertex: u32 },
    #[error(
        "fur shell on '{mesh}': face {face}: the prism still inverts with its heights at {ratio:.2} × h_0 \
         (the shell is thicker than the surface's local radius of curvature); lower fur.shell_height"
    )]
    Inverted { mesh: String, face: usize, ratio: f32 },
    #[error(
        "fur shell on '{mesh}': {total} sub-elements do not fit 32-bit indices (at most {limit}); \
         raise fur.cell_size or lower fur.max_level or fur.layers"
    )]
    TooManySubElements { mesh: String, total: u64, limit: u64 },
}

/// What building the shell fixed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShellReport {
    /// Prisms invalid at the full height `h_0`.
    pub inverted_prisms: usize,
    /// Vertices whose height was shrunk to make them valid.
    pub shrunk_vertices: usize,
    /// The smallest height as a fraction of `h_0` (1 when nothing shrank).
    pub min_height_ratio: f32,
    /// Shrinking passes run.
    pub shrink_passes: usize,
}

impl ShellReport {
    /// One line for logs and the UI; `None` when nothing was shrunk.
    pub fn warning(&self, mesh: &str) -> Option<String> {
        (self.shrunk_vertices > 0).then(|| {
            format!(
                "fur shell on '{mesh}': {} prisms inverted at full height; {} vertices shrunk (down to {:.2} × h_0)",
                self.inverted_prisms, self.shrunk_vertices, self.min_height_ratio
            )
        })
    }
}

/// Where a point lies relative to one prism (extended beyond its sides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    /// Shell height: 0 on the base, 1 on the top.
    pub w: f32,
    /// Barycentric coordinates in the cross-section `q(w)` (negative outside the prism's sides).
    pub lambda: [f32; 3],
}

impl Location {
    /// The most negative barycentric and its corner (the exit edge when negative).
    pub fn min_lambda(&self) -> (usize, f32) {
        (0..3).fold((0, self.lambda[0]), |(k, m), x| {
            if self.lambda[x] < m {
                (x, self.lambda[x])
            } else {
                (k, m)
            }
        })
    }

    /// Inside the prism: inside its sides and between base and top.
    pub fn inside(&self) -> bool {
        self.min_lambda().1 >= 0.0 && (0.0..=1.0).contains(&self.w)
    }
}

/// The outcome of the neighbour walk for one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Walk {
    /// Inside prism `face` after `hops` hops.
    Inside { face: u32, at: Location, hops: u32 },
    /// Above the top of the shell (left it; a re-entry is another shell fragment).
    Top { face: u32 },
    /// Below the base (inside the base mesh: opaque).
    Base { face: u32 },
    /// Out across a boundary edge.
    Boundary { face: u32, edge: usize },
    /// Still outside after the hop cap.
    Lost { face: u32 },
}

/// The shell: the mesh, the heights and tops per vertex, and each face's level and sub-element offset.
#[derive(Clone, Debug, PartialEq)]
pub struct Shell {
    pub mesh: FurMesh,
    pub height: f32,
    /// Per vertex `h_v` (`h_0` unless shrunk).
    pub heights: Vec<f32>,
    /// Per vertex `T_v = P_v + h_v N_v`.
    pub tops: Vec<Vec3>,
    pub layers: u32,
    /// Per face subdivision level `d_v`.
    pub levels: Vec<u32>,
    /// Per face first global sub-element index, `Σ_{u<v} n_l 4^{d_u}` (eq. 3 decision).
    pub offsets: Vec<u64>,
    /// Sub-elements in all: `Σ n_l 4^{d_v}`.
    pub sub_elements: u64,
    pub report: ShellReport,
}

impl Shell {
    /// Extrudes `mesh` by `p`.
    pub fn build(mesh: FurMesh, p: &ShellParams) -> Result<Shell, ShellError> {
        let cell = validate(&mesh.name, p)?;
        let (heights, report) = fit_heights(&mesh, p.height)?;
        let tops = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .zip(&heights)
            .map(|((&pv, &nv), &h)| pv + h * nv)
            .collect();
        let cell_area = f64::from(cell).powi(2) * 3f64.sqrt() / 4.0;
        let levels: Vec<u32> = (0..mesh.faces.len())
            .map(|f| match p.levels {
                Levels::Uniform(d) => d,
                Levels::Dynamic { max } => level_for_area(f64::from(mesh.face_area(f)), cell_area, max),
            })
            .collect();
        let mut offsets = Vec::with_capacity(levels.len());
        let mut total = 0u64;
        for &d in &levels {
            offsets.push(total);
            total += u64::from(p.layers) << (2 * d);
        }
        let limit = u64::from(u32::MAX);
        if total > limit {
            return Err(ShellError::TooManySubElements {
                mesh: mesh.name.clone(),
                total,
                limit,
            });
        }
        Ok(Shell {
            mesh,
            height: p.height,
            heights,
            tops,
            layers: p.layers,
            levels,
            offsets,
            sub_elements: total,
            report,
        })
    }

    /// Base and top corners of prism `f`.
    pub fn prism(&self, f: usize) -> ([Vec3; 3], [Vec3; 3]) {
        let face = self.mesh.faces[f];
        (
            face.map(|v| self.mesh.positions[v as usize]),
            face.map(|v| self.tops[v as usize]),
        )
    }

    /// The point of prism `f` at barycentrics `lambda` and height `w` (the shell map).
    pub fn point(&self, f: usize, lambda: [f32; 3], w: f32) -> Vec3 {
        let (b, t) = self.prism(f);
        (0..3).map(|k| lambda[k] * b[k].lerp(t[k], w)).sum()
    }

    /// Shell height and cross-section barycentrics of `p` relative to prism `f` (B.3 #4, mode B).
    pub fn locate(&self, p: Vec3, f: usize) -> Location {
        let (b, t) = self.prism(f);
        let d = [t[0] - b[0], t[1] - b[1], t[2] - b[2]];
        let (e1, e2) = (b[1] - b[0], b[2] - b[0]);
        let (f1, f2) = (d[1] - d[0], d[2] - d[0]);
        let r = p - b[0];
        let n0 = e1.cross(e2);
        let n1 = e1.cross(f2) + f1.cross(e2);
        let n2 = f1.cross(f2);
        // g(w) = (r − w D_0) · (n0 + w n1 + w² n2): zero where p lies in the plane of q(w).
        let c = [
            r.dot(n0),
            r.dot(n1) - d[0].dot(n0),
            r.dot(n2) - d[0].dot(n1),
            -d[0].dot(n2),
        ];
        let top_n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        let centre = (b[0] + b[1] + b[2]) / 3.0;
        let thickness = (t[0] - centre).dot(top_n);
        let mut w = if thickness > 0.0 {
            1.0 - (t[0] - p).dot(top_n) / thickness
        } else {
            0.5
        };
        for _ in 0..NEWTON_STEPS {
            let g = ((c[3] * w + c[2]) * w + c[1]) * w + c[0];
            let dg = (3.0 * c[3] * w + 2.0 * c[2]) * w + c[1];
            if dg == 0.0 {
                break;
            }
            let step = g / dg;
            w -= step;
            if step.abs() < 1e-7 {
                break;
            }
        }
        let q = [b[0].lerp(t[0], w), b[1].lerp(t[1], w), b[2].lerp(t[2], w)];
        let n = n0 + w * n1 + w * w * n2;
        let nn = n.length_squared();
        let lambda = std::array::from_fn(|x| {
            let (u, v) = (q[(x + 1) % 3] - p, q[(x + 2) % 3] - p);
            u.cross(v).dot(n) / nn
        });
        Location { w, lambda }
    }

    /// The paper's neighbour walk: locate `p` in `face`, hop across the exit edge (the side opposite the most
    /// negative barycentric) at most `max_hops` times.
    pub fn walk(&self, p: Vec3, face: u32, max_hops: u32) -> Walk {
        let mut f = face;
        for hops in 0..=max_hops {
            let at = self.locate(p, f as usize);
            let (edge, m) = at.min_lambda();
            if m < 0.0 {
                if hops == max_hops {
                    break;
                }
                match self.mesh.neighbours[f as usize][edge] {
                    NONE => return Walk::Boundary { face: f, edge },
                    g => f = g,
                }
                continue;
            }
            return if at.w < 0.0 {
                Walk::Base { face: f }
            } else if at.w > 1.0 {
                Walk::Top { face: f }
            } else {
                Walk::Inside { face: f, at, hops }
            };
        }
        Walk::Lost { face: f }
    }

    /// The hop cap for [`Shell::walk`]: at least [`MIN_HOPS`], and half the largest vertex valence, so that a
    /// step passing a high-valence vertex (the generated head's poles join 40 faces) can go half way round it.
    pub fn hop_cap(&self) -> u32 {
        MIN_HOPS.max(self.mesh.max_valence().div_ceil(2))
    }

    /// Brute-force point location: the first prism (by face index) holding `p`, testing every prism whose
    /// corner bounding box holds it.
    pub fn locate_brute(&self, p: Vec3) -> Option<(u32, Location)> {
        (0..self.mesh.faces.len()).find_map(|f| {
            let (b, t) = self.prism(f);
            let lo = b.iter().chain(&t).fold(Vec3::INFINITY, |a, &c| a.min(c));
            let hi = b.iter().chain(&t).fold(Vec3::NEG_INFINITY, |a, &c| a.max(c));
            if p.cmplt(lo).any() || p.cmpgt(hi).any() {
                return None;
            }
            let at = self.locate(p, f);
            at.inside().then_some((f as u32, at))
        })
    }

    /// Layer, local index (eqs. 1–2) and global index (eq. 3 decision) of location `at` in prism `f`.
    pub fn sub_element(&self, f: usize, at: &Location) -> (u32, u32, u64) {
        let d = self.levels[f];
        let layer = index::layer_of(at.w, self.layers);
        let local = index::locate(at.lambda, d);
        (
            layer,
            local,
            index::global_index(self.offsets[f], layer, d, local),
        )
    }

    /// The face, layer and local index of global index `g < sub_elements` (the inverse of eq. 3).
    pub fn split_global(&self, g: u64) -> (usize, u32, u32) {
        let f = self.offsets.partition_point(|&o| o <= g) - 1;
        let r = g - self.offsets[f];
        let per_layer = 1u64 << (2 * self.levels[f]);
        (f, (r / per_layer) as u32, (r % per_layer) as u32)
    }
}

fn validate(mesh: &str, p: &ShellParams) -> Result<f32, ShellError> {
    let bad = |key, value: String, rule| ShellError::Param {
        mesh: mesh.to_string(),
        key,
        value,
        rule,
    };
    if !(p.height.is_finite() && p.height > 0.0) {
        return Err(bad(
            "fur.shell_height",
            p.height.to_string(),
            "must be finite and > 0",
        ));
    }
    if !(1..=MAX_LAYERS).contains(&p.layers) {
        return Err(bad("fur.layers", p.layers.to_string(), "must be in 1..=256"));
    }
    let level = match p.levels {
        Levels::Dynamic { max } => ("fur.max_level", max),
        Levels::Uniform(d) => ("fur.level", d),
    };
    if level.1 > MAX_LEVEL {
        return Err(bad(level.0, level.1.to_string(), "must be at most 10"));
    }
    let cell = p.cell.unwrap_or(p.height / p.layers as f32);
    if !(cell.is_finite() && cell > 0.0) {
        return Err(bad("fur.cell_size", cell.to_string(), "must be finite and > 0"));
    }
    Ok(cell)
}

/// The smallest level `d ≤ max` with `area / 4^d ≤ cell_area`.
pub fn level_for_area(area: f64, cell_area: f64, max: u32) -> u32 {
    (0..max)
        .find(|&d| area / 4f64.powi(d as i32) <= cell_area)
        .unwrap_or(max)
}

/// Minimum of `c0 + c1 w + c2 w²` over `w ∈ [0, 1]`.
fn min_quadratic(c: [f64; 3]) -> f64 {
    let at = |w: f64| c[0] + w * (c[1] + w * c[2]);
    let mut m = at(0.0).min(at(1.0));
    if c[2] > 0.0 {
        let w = -c[1] / (2.0 * c[2]);
        if w > 0.0 && w < 1.0 {
            m = m.min(at(w));
        }
    }
    m
}

/// Whether the prism on base `b` with lateral edges `d` is valid (module docs).
fn prism_valid(b: [DVec3; 3], d: [DVec3; 3]) -> bool {
    let (e1, e2) = (b[1] - b[0], b[2] - b[0]);
    let (f1, f2) = (d[1] - d[0], d[2] - d[0]);
    let n = [e1.cross(e2), e1.cross(f2) + f1.cross(e2), f1.cross(f2)];
    let base = n[0].normalize();
    let scale = n[0].length();
    let facing = min_quadratic(n.map(|v| v.dot(base)));
    facing > VALID_MARGIN * scale
        && d.iter().all(|dk| {
            let jac = min_quadratic(n.map(|v| v.dot(*dk)));
            jac > VALID_MARGIN * scale * dk.length()
        })
}

/// Per-vertex heights: `h_0`, shrunk where prisms are invalid.
fn fit_heights(mesh: &FurMesh, h0: f32) -> Result<(Vec<f32>, ShellReport), ShellError> {
    let mut heights = vec![h0; mesh.positions.len()];
    let floor = MIN_HEIGHT_FRACTION * h0;
    let valid = |f: usize, heights: &[f32]| {
        let face = mesh.faces[f];
        let b = face.map(|v| mesh.positions[v as usize].as_dvec3());
        let d = face.map(|v| (mesh.normals[v as usize] * heights[v as usize]).as_dvec3());
        prism_valid(b, d)
    };
    let mut report = ShellReport {
        min_height_ratio: 1.0,
        ..ShellReport::default()
    };
    let mut shrunk = vec![false; heights.len()];
    for pass in 0..=MAX_SHRINK_PASSES {
        let bad: Vec<usize> = (0..mesh.faces.len()).filter(|&f| !valid(f, &heights)).collect();
        if pass == 0 {
            report.inverted_prisms = bad.len();
        }
        let Some(&first) = bad.first() else {
            report.shrink_passes = pass;
            report.shrunk_vertices = shrunk.iter().filter(|&&s| s).count();
            report.min_height_ratio = heights.iter().fold(1.0f32, |m, &h| m.min(h / h0));
            return Ok((heights, report));
        };
        let mut moved = vec![false; heights.len()];
        for &f in &bad {
            let n = mesh.face_normal(f);
            if let Some(&v) = mesh.faces[f]
                .iter()
                .find(|&&v| mesh.normals[v as usize].dot(n) <= 0.0)
            {
                return Err(ShellError::NormalBehindFace {
                    mesh: mesh.name.clone(),
                    face: f,
                    vertex: v,
                });
            }
            for &v in &mesh.faces[f] {
                let v = v as usize;
                if !moved[v] && heights[v] > floor {
                    heights[v] = (heights[v] * SHRINK).max(floor);
                    moved[v] = true;
                    shrunk[v] = true;
                }
            }
        }
        if !moved.iter().any(|&m| m) || pass == MAX_SHRINK_PASSES {
            let ratio = mesh.faces[first]
                .iter()
                .fold(1.0f32, |m, &v| m.min(heights[v as usize] / h0));
            return Err(ShellError::Inverted {
                mesh: mesh.name.clone(),
                face: first,
                ratio,
            });
        }
    }
    unreachable!("the pass loop returns on its last pass")
}

#[cfg(test)]
mod tests;
