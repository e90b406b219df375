//! Base mesh → welded, oriented, neighboured mesh (spec FR-MESH-1..5, Andersen et al. 2016 §3.2).
//!
//! Order of work: positions checked finite and indices in range; vertices welded by position (tolerance
//! [`WELD_TOLERANCE`] × bounding-box diagonal; the generated head and glTF files split vertices at seams and
//! poles); zero-area triangles dropped (their edges become boundary); edges used by more than two faces cut
//! (non-manifold); faces re-oriented by a breadth-first walk so that every shared edge is traversed in
//! opposite directions (what cannot be made consistent — a Möbius band — is cut too); a closed component is
//! turned outward (positive signed volume), an open one faces where its input vertex normals point (a glTF
//! scalp wound inward but with outward normals grows its shell outside), or keeps the winding of most of its
//! input faces when the normals say nothing.
//! Neighbours are then found as the paper does: a map from 64-bit directed-edge keys `(a << 32) | b` to the
//! face, looked up with the reversed key. Normals are area-weighted over the welded vertices. Every fix is
//! counted in [`MeshReport`]; nothing is dropped silently.

use std::collections::{HashMap, VecDeque};

use glam::{DVec3, Vec3};
use thiserror::Error;

use crate::scene::Mesh;

/// No neighbour across an edge (mesh boundary, or an edge cut as non-manifold or inconsistently wound).
pub const NONE: u32 = u32::MAX;
/// Weld tolerance as a fraction of the bounding-box diagonal.
pub const WELD_TOLERANCE: f32 = 1e-6;

/// A base mesh the shell cannot be built on. Each message names the mesh, the face or vertex, and the problem.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("fur base mesh '{mesh}': no triangles")]
    Empty { mesh: String },
    #[error("fur base mesh '{mesh}': {len} indices is not a multiple of 3")]
    IndexCount { mesh: String, len: usize },
    #[error("fur base mesh '{mesh}': face {face} uses vertex {index}, but there are {vertices} vertices")]
    IndexOutOfRange {
        mesh: String,
        face: usize,
        index: u32,
        vertices: usize,
    },
    #[error("fur base mesh '{mesh}': vertex {vertex} has a non-finite position {position:?}")]
    NonFinite {
        mesh: String,
        vertex: usize,
        position: Vec3,
    },
    #[error("fur base mesh '{mesh}': all {faces} faces have zero area after welding")]
    AllDegenerate { mesh: String, faces: usize },
}

/// What welding and orientation changed, and what is left as boundary.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshReport {
    pub input_vertices: usize,
    pub input_faces: usize,
    /// Vertices after welding.
    pub welded_vertices: usize,
    /// Faces dropped for zero area (after welding).
    pub degenerate_faces: usize,
    /// Faces whose winding was reversed to agree with their neighbours (or to face out of a closed component).
    pub flipped_faces: usize,
    /// Undirected edges used by more than two faces; each is treated as boundary on every face using it.
    pub non_manifold_edges: usize,
    /// Edges two faces share but that no re-orientation makes consistent (non-orientable surfaces); boundary.
    pub inconsistent_edges: usize,
    /// Face edges with no neighbour, the cut ones included.
    pub boundary_edges: usize,
    /// Vertices whose area-weighted normal summed to zero and took the normal of their first face instead.
    pub normal_fallbacks: usize,
}

impl MeshReport {
    /// One line for logs and the UI; `None` when nothing needed fixing.
    pub fn warning(&self, mesh: &str) -> Option<String> {
        let cut = self.non_manifold_edges + self.inconsistent_edges;
        let mut parts = Vec::new();
        if self.degenerate_faces > 0 {
            parts.push(format!("{} zero-area faces dropped", self.degenerate_faces));
        }
        if self.flipped_faces > 0 {
            parts.push(format!("{} faces re-oriented", self.flipped_faces));
        }
        if cut > 0 {
            parts.push(format!(
                "{cut} edges are non-manifold or inconsistently wound and treated as boundary"
            ));
        }
        if self.normal_fallbacks > 0 {
            parts.push(format!("{} vertices took a face normal", self.normal_fallbacks));
        }
        (!parts.is_empty()).then(|| format!("fur base mesh '{mesh}': {}", parts.join(", ")))
    }
}

/// A welded, consistently oriented triangle mesh with its face neighbours and smoothed normals.
#[derive(Clone, Debug, PartialEq)]
pub struct FurMesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Area-weighted smoothed vertex normals (unit), per welded vertex.
    pub normals: Vec<Vec3>,
    pub faces: Vec<[u32; 3]>,
    /// `neighbours[f][e]`: the face across edge `e` of `f`, the edge opposite corner `e` (from corner `e + 1` to
    /// corner `e + 2`), or [`NONE`].
    pub neighbours: Vec<[u32; 3]>,
    /// The index of each face in the input mesh's triangle list.
    pub source_faces: Vec<u32>,
    pub report: MeshReport,
}

/// The 64-bit directed-edge key of the paper's Fig. 7: `a` shifted into the high word, `b` in the low word.
pub fn edge_key(a: u32, b: u32) -> u64 {
    (u64::from(a) << 32) | u64::from(b)
}

/// Corners `(e + 1, e + 2)` of a face: the directed edge opposite corner `e`.
pub fn edge_of(face: [u32; 3], e: usize) -> (u32, u32) {
    (face[(e + 1) % 3], face[(e + 2) % 3])
}

impl FurMesh {
    /// Welds, cleans, orients and neighbours `mesh` (named `name` in messages).
    pub fn build(name: &str, mesh: &Mesh) -> Result<FurMesh, MeshError> {
        let err_name = || name.to_string();
        if !mesh.indices.len().is_multiple_of(3) {
            return Err(MeshError::IndexCount {
                mesh: err_name(),
                len: mesh.indices.len(),
            });
        }
        if mesh.indices.is_empty() {
            return Err(MeshError::Empty { mesh: err_name() });
        }
        if let Some((vertex, &position)) = mesh.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(MeshError::NonFinite {
                mesh: err_name(),
                vertex,
                position,
            });
        }
        let nv = mesh.positions.len();
        if let Some(k) = mesh.indices.iter().position(|&i| i as usize >= nv) {
            return Err(MeshError::IndexOutOfRange {
                mesh: err_name(),
                face: k / 3,
                index: mesh.indices[k],
                vertices: nv,
            });
        }
        let mut report = MeshReport {
            input_vertices: nv,
            input_faces: mesh.indices.len() / 3,
            ..MeshReport::default()
        };
        let (positions, remap, diagonal) = weld(&mesh.positions);
        report.welded_vertices = positions.len();
        let min_double_area = (WELD_TOLERANCE * diagonal).powi(2);
        let mut faces = Vec::new();
        let mut source_faces = Vec::new();
        // Per kept face, the input's vertex normals summed: which side an open surface's outside is.
        let mut hints = Vec::new();
        let has_normals = mesh.normals.len() == nv;
        for (f, t) in mesh.indices.chunks_exact(3).enumerate() {
            let face = [remap[t[0] as usize], remap[t[1] as usize], remap[t[2] as usize]];
            let [a, b, c] = face.map(|v| positions[v as usize]);
            let double_area = (b - a).cross(c - a).length();
            if face[0] == face[1]
                || face[1] == face[2]
                || face[0] == face[2]
                || double_area <= min_double_area
            {
                report.degenerate_faces += 1;
            } else {
                faces.push(face);
                source_faces.push(f as u32);
                hints.push(if has_normals {
                    t.iter().map(|&i| mesh.normals[i as usize]).sum()
                } else {
                    Vec3::ZERO
                });
            }
        }
        if faces.is_empty() {
            return Err(MeshError::AllDegenerate {
                mesh: err_name(),
                faces: report.input_faces,
            });
        }
        let cut = orient(&positions, &mut faces, &hints, &mut report);
        let neighbours = neighbours(&faces, &cut);
        report.boundary_edges = neighbours.iter().flatten().filter(|&&n| n == NONE).count();
        let normals = smoothed_normals(&positions, &faces, &mut report);
        Ok(FurMesh {
            name: name.to_string(),
            positions,
            normals,
            faces,
            neighbours,
            source_faces,
            report,
        })
    }

    /// Distinct undirected edges.
    pub fn edge_count(&self) -> usize {
        let interior = self.neighbours.iter().flatten().filter(|&&n| n != NONE).count();
        interior / 2 + self.report.boundary_edges
    }

    /// V − E + F over the vertices used by faces (2 for a closed sphere-like surface, 0 for an open cylinder).
    pub fn euler_characteristic(&self) -> i64 {
        let mut used = vec![false; self.positions.len()];
        for &v in self.faces.iter().flatten() {
            used[v as usize] = true;
        }
        let v = used.iter().filter(|&&u| u).count() as i64;
        v - self.edge_count() as i64 + self.faces.len() as i64
    }

    /// The most faces around one vertex.
    pub fn max_valence(&self) -> u32 {
        let mut n = vec![0u32; self.positions.len()];
        for &v in self.faces.iter().flatten() {
            n[v as usize] += 1;
        }
        n.into_iter().max().unwrap_or(0)
    }

    /// The unit normal of face `f` (its winding's right-hand normal).
    pub fn face_normal(&self, f: usize) -> Vec3 {
        let [a, b, c] = self.faces[f].map(|v| self.positions[v as usize]);
        (b - a).cross(c - a).normalize()
    }

    /// The area of face `f`.
    pub fn face_area(&self, f: usize) -> f32 {
        let [a, b, c] = self.faces[f].map(|v| self.positions[v as usize]);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Which edge of face `g` joins vertices `a` and `b` (either direction).
    pub fn edge_index(&self, g: usize, a: u32, b: u32) -> Option<usize> {
        (0..3).find(|&e| {
            let (p, q) = edge_of(self.faces[g], e);
            (p, q) == (a, b) || (p, q) == (b, a)
        })
    }
}

/// Welds `positions` within the tolerance of the first vertex seen in each cluster (input order, so the
/// result is deterministic); returns the welded positions, the old → new map and the bounding-box diagonal.
fn weld(positions: &[Vec3]) -> (Vec<Vec3>, Vec<u32>, f32) {
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let diagonal = if positions.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    };
    let tol = (WELD_TOLERANCE * diagonal).max(f32::MIN_POSITIVE);
    let cell = |p: Vec3| ((p - lo) / tol).floor().as_ivec3();
    let mut grid: HashMap<glam::IVec3, Vec<u32>> = HashMap::new();
    let mut out: Vec<Vec3> = Vec::new();
    let mut remap = Vec::with_capacity(positions.len());
    for &p in positions {
        let c = cell(p);
        let mut found = None;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(list) = grid.get(&(c + glam::IVec3::new(dx, dy, dz)))
                        && let Some(&w) = list.iter().find(|&&w| out[w as usize].distance(p) <= tol)
                    {
                        found = Some(w);
                        break 'search;
                    }
                }
            }
        }
        let w = found.unwrap_or_else(|| {
            let w = out.len() as u32;
            out.push(p);
            grid.entry(c).or_default().push(w);
            w
        });
        remap.push(w);
    }
    (out, remap, diagonal)
}

/// Re-orients `faces` in place; returns the set of cut edges as undirected keys (min, max). A closed
/// component faces outward; an open one faces the side its input normals (`hints`, per face) point to, or keeps
/// the winding most of its faces had when the input has no normals.
fn orient(positions: &[Vec3], faces: &mut [[u32; 3]], hints: &[Vec3], report: &mut MeshReport) -> Vec<u64> {
    let undirected = |a: u32, b: u32| edge_key(a.min(b), a.max(b));
    let mut uses: HashMap<u64, Vec<(u32, u8)>> = HashMap::new();
    for (f, &face) in faces.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = edge_of(face, e);
            uses.entry(undirected(a, b))
                .or_default()
                .push((f as u32, e as u8));
        }
    }
    let mut cut: Vec<u64> = uses
        .iter()
        .filter(|(_, u)| u.len() > 2)
        .map(|(&k, _)| k)
        .collect();
    report.non_manifold_edges = cut.len();
    // links[f][e] = the face sharing edge e of f through a two-face edge, and whether the input windings agree.
    let mut links = vec![[None::<(u32, bool)>; 3]; faces.len()];
    for u in uses.values().filter(|u| u.len() == 2) {
        let ((f, e), (g, h)) = (u[0], u[1]);
        let same_direction = edge_of(faces[f as usize], e as usize) == edge_of(faces[g as usize], h as usize);
        // Consistent windings traverse the shared edge in opposite directions.
        links[f as usize][e as usize] = Some((g, !same_direction));
        links[g as usize][h as usize] = Some((f, !same_direction));
    }
    let mut flip: Vec<Option<bool>> = vec![None; faces.len()];
    let mut inconsistent = Vec::new();
    for seed in 0..faces.len() {
        if flip[seed].is_some() {
            continue;
        }
        let conflicts_before = inconsistent.len();
        let mut component = vec![seed];
        flip[seed] = Some(false);
        let mut queue = VecDeque::from([seed]);
        while let Some(f) = queue.pop_front() {
            let flip_f = flip[f].unwrap_or(false);
            for (e, link) in links[f].iter().enumerate() {
                let Some((g, agree)) = *link else { continue };
                let want = if agree { flip_f } else { !flip_f };
                match flip[g as usize] {
                    None => {
                        flip[g as usize] = Some(want);
                        component.push(g as usize);
                        queue.push_back(g as usize);
                    }
                    Some(have) if have != want => {
                        let (a, b) = edge_of(faces[f], e);
                        inconsistent.push(undirected(a, b));
                    }
                    Some(_) => {}
                }
            }
        }
        // Closed and consistent: face outward. Otherwise face the input normals, or keep the majority winding.
        let closed = component.iter().all(|&f| links[f].iter().all(|l| l.is_some()));
        let flipped = component.iter().filter(|&&f| flip[f] == Some(true)).count();
        let invert = if closed && inconsistent.len() == conflicts_before {
            let volume: f64 = component
                .iter()
                .map(|&f| {
                    let [a, b, c] = faces[f].map(|v| positions[v as usize].as_dvec3());
                    let v = a.dot(b.cross(c));
                    if flip[f] == Some(true) { -v } else { v }
                })
                .sum();
            volume < 0.0
        } else {
            // Area-weighted agreement of the oriented faces with the input normals.
            let agreement: f64 = component
                .iter()
                .map(|&f| {
                    let [a, b, c] = faces[f].map(|v| positions[v as usize].as_dvec3());
                    let n = (b - a).cross(c - a).dot(hints[f].as_dvec3());
                    if flip[f] == Some(true) { -n } else { n }
                })
                .sum();
            if agreement != 0.0 {
                agreement < 0.0
            } else {
                2 * flipped > component.len()
            }
        };
        if invert {
            for &f in &component {
                flip[f] = flip[f].map(|x| !x);
            }
        }
    }
    inconsistent.sort_unstable();
    inconsistent.dedup();
    report.inconsistent_edges = inconsistent.len();
    cut.extend(inconsistent);
    cut.sort_unstable();
    for (face, fl) in faces.iter_mut().zip(&flip) {
        if *fl == Some(true) {
            face.swap(1, 2);
            report.flipped_faces += 1;
        }
    }
    cut
}

/// The paper's neighbour table: directed keys → face, looked up reversed; cut edges get [`NONE`].
fn neighbours(faces: &[[u32; 3]], cut: &[u64]) -> Vec<[u32; 3]> {
    let is_cut = |a: u32, b: u32| cut.binary_search(&edge_key(a.min(b), a.max(b))).is_ok();
    let mut by_key: HashMap<u64, u32> = HashMap::with_capacity(faces.len() * 3);
    for (f, &face) in faces.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = edge_of(face, e);
            if !is_cut(a, b) {
                by_key.insert(edge_key(a, b), f as u32);
            }
        }
    }
    faces
        .iter()
        .map(|&face| {
            std::array::from_fn(|e| {
                let (a, b) = edge_of(face, e);
                if is_cut(a, b) {
                    NONE
                } else {
                    by_key.get(&edge_key(b, a)).copied().unwrap_or(NONE)
                }
            })
        })
        .collect()
}

/// Area-weighted face normals summed per vertex (in f64), normalised.
fn smoothed_normals(positions: &[Vec3], faces: &[[u32; 3]], report: &mut MeshReport) -> Vec<Vec3> {
    let mut sum = vec![DVec3::ZERO; positions.len()];
    let mut first = vec![None::<Vec3>; positions.len()];
    for face in faces {
        let [a, b, c] = face.map(|v| positions[v as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &v in face {
            sum[v as usize] += n;
            first[v as usize].get_or_insert(n.normalize().as_vec3());
        }
    }
    sum.iter()
        .zip(&first)
        .map(|(s, f)| match (s.try_normalize(), f) {
            (Some(n), _) => n.as_vec3(),
            (None, Some(f)) => {
                report.normal_fallbacks += 1;
                *f
            }
            (None, None) => Vec3::ZERO,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_open_mesh_wound_inward_faces_where_its_normals_point() {
        // The cylinder's windings reversed, its radial (outward) normals kept, as a glTF scalp can come.
        let mut m = crate::scene::fur_shapes::cylinder(0.04, 0.1, 16, 4);
        for t in m.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
        let f = FurMesh::build("inward", &m).unwrap();
        assert_eq!(f.report.flipped_faces, f.faces.len());
        for face in 0..f.faces.len() {
            let [a, b, c] = f.faces[face].map(|v| f.positions[v as usize]);
            let radial = ((a + b + c) / 3.0) * Vec3::new(1.0, 0.0, 1.0);
            assert!(f.face_normal(face).dot(radial) > 0.0, "face {face} faces inward");
        }
        // Without normals the majority winding stays.
        m.normals.clear();
        assert_eq!(FurMesh::build("inward", &m).unwrap().report.flipped_faces, 0);
    }

    fn mesh(positions: &[[f32; 3]], indices: &[u32]) -> Mesh {
        Mesh {
            positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
            normals: vec![Vec3::Y; positions.len()],
            indices: indices.to_vec(),
            color: Vec3::ONE,
        }
    }

    const TET: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// Outward-wound tetrahedron faces.
    const TET_FACES: [u32; 12] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];

    #[test]
    fn tetrahedron_is_closed_with_symmetric_neighbours() {
        let m = FurMesh::build("tet", &mesh(&TET, &TET_FACES)).unwrap();
        assert_eq!(m.euler_characteristic(), 2);
        assert_eq!(m.edge_count(), 6);
        assert_eq!(m.report.boundary_edges, 0);
        assert_eq!(m.report.flipped_faces, 0);
        for (f, nb) in m.neighbours.iter().enumerate() {
            for (e, &g) in nb.iter().enumerate() {
                let (a, b) = edge_of(m.faces[f], e);
                let h = m.edge_index(g as usize, a, b).unwrap();
                assert_eq!(m.neighbours[g as usize][h], f as u32);
                // Consistent winding: the neighbour traverses the edge the other way.
                assert_eq!(edge_of(m.faces[g as usize], h), (b, a));
            }
        }
        // Face 0 = (0, 2, 1): edge 0 is 2 → 1, shared with face 3 = (1, 2, 3) as 1 → 2.
        assert_eq!(m.neighbours[0][0], 3);
        // The normal at vertex 0 averages three unit right triangles' normals: −(1, 1, 1)/√3.
        let expect = -Vec3::ONE / 3f32.sqrt();
        assert!(m.normals[0].distance(expect) < 1e-6, "{:?}", m.normals[0]);
    }

    #[test]
    fn one_inverted_face_is_flipped_and_counted() {
        let mut faces = TET_FACES;
        faces.swap(4, 5); // face 1 wound inward
        let m = FurMesh::build("tet", &mesh(&TET, &faces)).unwrap();
        assert_eq!(m.report.flipped_faces, 1);
        assert_eq!(m.report.boundary_edges, 0);
        assert!(m.report.warning("tet").unwrap().contains("1 faces re-oriented"));
        let outward = FurMesh::build("tet", &mesh(&TET, &TET_FACES)).unwrap();
        assert_eq!(m.faces[0], outward.faces[0]);
        assert!(m.face_normal(1).dot(outward.face_normal(1)) > 0.999);
    }

    #[test]
    fn an_all_inward_closed_mesh_is_turned_outward() {
        let inward: Vec<u32> = TET_FACES.chunks(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
        let m = FurMesh::build("tet", &mesh(&TET, &inward)).unwrap();
        assert_eq!(m.report.flipped_faces, 4);
        // Face 0 lies in z = 0 with the solid above it: outward is −Z.
        assert!(m.face_normal(0).distance(-Vec3::Z) < 1e-6);
    }

    #[test]
    fn split_vertices_are_welded() {
        // Two triangles of a unit square whose shared diagonal has its vertices duplicated (a seam).
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
        ];
        let m = FurMesh::build("square", &mesh(&p, &[0, 1, 2, 5, 3, 4])).unwrap();
        assert_eq!(m.report.welded_vertices, 4);
        assert_eq!(m.neighbours[0][1], 1);
        assert_eq!(m.report.boundary_edges, 4);
        assert_eq!(m.euler_characteristic(), 1);
        assert!(m.normals.iter().all(|n| n.distance(Vec3::Z) < 1e-6));
    }

    #[test]
    fn three_faces_on_one_edge_are_cut_and_reported() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ];
        let m = FurMesh::build("fin", &mesh(&p, &[0, 1, 2, 1, 0, 3, 0, 1, 4])).unwrap();
        assert_eq!(m.report.non_manifold_edges, 1);
        assert!(m.neighbours.iter().flatten().all(|&n| n == NONE));
        assert_eq!(m.report.boundary_edges, 9);
        let w = m.report.warning("fin").unwrap();
        assert!(
            w.contains("'fin'") && w.contains("1 edges are non-manifold"),
            "{w}"
        );
    }

    #[test]
    fn a_moebius_band_keeps_one_inconsistent_edge() {
        // Three quads of a strip whose last quad joins the first with a half twist.
        let p = [
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.3],
            [1.0, 1.0, 0.3],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
        ];
        let idx = [0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5, 4, 1, 0, 4, 0, 5];
        let m = FurMesh::build("band", &mesh(&p, &idx)).unwrap();
        assert_eq!(m.report.inconsistent_edges, 1);
        assert_eq!(m.report.non_manifold_edges, 0);
    }

    #[test]
    fn zero_area_faces_are_dropped_and_counted() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]];
        let m = FurMesh::build("sliver", &mesh(&p, &[0, 1, 2, 0, 1, 3])).unwrap();
        assert_eq!(m.faces.len(), 1);
        assert_eq!(m.source_faces, vec![0]);
        assert_eq!(m.report.degenerate_faces, 1);
    }

    #[test]
    fn bad_meshes_are_typed_errors_naming_mesh_and_face() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let e = FurMesh::build("m", &mesh(&p, &[])).unwrap_err();
        assert_eq!(e, MeshError::Empty { mesh: "m".into() });
        let e = FurMesh::build("m", &mesh(&p, &[0, 1])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "fur base mesh 'm': 2 indices is not a multiple of 3"
        );
        let e = FurMesh::build("m", &mesh(&p, &[0, 1, 2, 0, 1, 7])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "fur base mesh 'm': face 1 uses vertex 7, but there are 3 vertices"
        );
        let q = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let e = FurMesh::build("m", &mesh(&q, &[0, 1, 2])).unwrap_err();
        assert!(matches!(e, MeshError::NonFinite { vertex: 1, .. }), "{e}");
        let e = FurMesh::build("m", &mesh(&p, &[0, 0, 1])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "fur base mesh 'm': all 1 faces have zero area after welding"
        );
    }

    #[test]
    fn edge_keys_put_the_first_vertex_in_the_high_word() {
        assert_eq!(edge_key(1, 2), 0x0000_0001_0000_0002);
        assert_eq!(edge_key(u32::MAX, 0), 0xFFFF_FFFF_0000_0000);
        assert_ne!(edge_key(3, 5), edge_key(5, 3));
    }
}
