//! Sub-element indexing, Andersen et al. 2016 eqs. (1)–(3) (spec B.3 #1–2).
//!
//! A layer of a prism is a triangle subdivided `d` times by joining edge centres: `4^d` sub-triangles. With
//! `n = 2^d` and `λ_x` the barycentric coordinate of corner `x` (`dist⊥(p, e_x)/dist⊥(p_x, e_x)` in the paper),
//! eq. (1) is read as a product: `i_x = min(⌊(1 − λ_x)·n⌋, n − 1)` (printed as a power it makes every index 0),
//! and eq. (2) `i = i_0(1 + i_0) + (i_1 − i_2)` numbers the sub-triangles row by row from corner 0: row `i_0`
//! holds indices `i_0² ..= i_0² + 2 i_0`. The inverse uses the lattice cell `a_x = n − 1 − i_x`: an upward
//! sub-triangle (corners `a + e_x`) has `Σa = n − 1`, a downward one (corners `a + 1 − e_x`) `Σa = n − 2`.
//!
//! Eq. (3) `i_g = (i_v n_l + i_l)·4^d + i` assumes one `d`. Under dynamic resolution each face `v` has its own
//! `d_v`, so the decision here is `i_g = offset_v + i_l·4^{d_v} + i` with `offset_v = Σ_{u<v} n_l·4^{d_u}`: the
//! same formula when every `d_v` is equal, and still a bijection onto `[0, Σ n_l 4^{d_v})` when they differ.
//!
//! Sub-edge `x` of a sub-triangle is the side opposite its corner `x`. Across it lies, inside the face, the
//! sub-triangle of the other orientation sharing that side (also as its side `x`); an upward sub-triangle with
//! `a_x = 0` sits on the face's edge `x`, and its neighbours are the sub-triangles of the neighbouring face
//! along that edge: one when that face's level is lower or equal, `2^{d' − d}` when it is finer.

use super::mesh::{FurMesh, NONE, edge_of};

/// The deepest subdivision level (`4^10` = 1 048 576 sub-triangles per layer; spec FR-LIM).
pub const MAX_LEVEL: u32 = 10;

/// Eq. (1): the three sub-indices of barycentric point `lambda` at level `d`, clamped into `[0, 2^d)` so that
/// points on an edge or corner (and rounding just outside) stay in range.
pub fn sub_indices(lambda: [f32; 3], d: u32) -> [u32; 3] {
    let n = (1u32 << d) as f32;
    lambda.map(|l| (((1.0 - l) * n).floor().max(0.0) as u32).min((1 << d) - 1))
}

/// Eq. (2): the local index of sub-indices `i`.
pub fn local_index(i: [u32; 3]) -> u32 {
    let [i0, i1, i2] = i.map(i64::from);
    (i0 * (1 + i0) + i1 - i2) as u32
}

/// Eqs. (1)–(2): the local index of the sub-triangle holding barycentric point `lambda` at level `d`.
pub fn locate(lambda: [f32; 3], d: u32) -> u32 {
    local_index(sub_indices(lambda, d))
}

/// The layer of shell height `w ∈ [0, 1]` among `layers` (layer 0 at the base; `w = 1` in the top layer).
pub fn layer_of(w: f32, layers: u32) -> u32 {
    ((w * layers as f32).floor().max(0.0) as u32).min(layers - 1)
}

/// Eq. (3) under dynamic resolution: the global index of local index `i` in layer `layer` of the face whose
/// sub-elements start at `offset` and whose level is `d`.
pub fn global_index(offset: u64, layer: u32, d: u32, i: u32) -> u64 {
    offset + u64::from(layer) * (1u64 << (2 * d)) + u64::from(i)
}

/// One sub-triangle of a layer at level `d`, by its lattice cell and orientation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubTriangle {
    /// `a_x = 2^d − 1 − i_x`.
    pub cell: [u32; 3],
    /// Upward (corners `a + e_x`, touching the face's edges where some `a_x = 0`) or downward (`a + 1 − e_x`).
    pub up: bool,
}

impl SubTriangle {
    /// The sub-triangle of local index `i < 4^d` (the inverse of eq. 2).
    pub fn from_index(i: u32, d: u32) -> SubTriangle {
        let n = 1i64 << d;
        let i0 = i64::from(i.isqrt());
        let r = i64::from(i) - i0 * i0 - i0; // i_1 − i_2 ∈ [−i_0, i_0]
        let up = (r + i0) % 2 == 0;
        let sum = if up { 2 * n - 2 - i0 } else { 2 * n - 1 - i0 }; // i_1 + i_2
        let (i1, i2) = ((sum + r) / 2, (sum - r) / 2);
        SubTriangle {
            cell: [i0, i1, i2].map(|ix| (n - 1 - ix) as u32),
            up,
        }
    }

    /// Its local index at level `d` (eq. 2 of its sub-indices).
    pub fn index(&self, d: u32) -> u32 {
        local_index(self.cell.map(|a| (1 << d) - 1 - a))
    }

    /// Barycentric coordinates of its centroid at level `d`.
    pub fn centroid(&self, d: u32) -> [f32; 3] {
        let n = (1u32 << d) as f32;
        let off = if self.up { 1.0 / 3.0 } else { 2.0 / 3.0 };
        self.cell.map(|a| (a as f32 + off) / n)
    }

    /// Its corners as lattice points (barycentrics × `2^d`, each summing to `2^d`), corner `x` opposite sub-edge `x`.
    pub fn corners(&self) -> [[u32; 3]; 3] {
        std::array::from_fn(|x| {
            std::array::from_fn(|y| self.cell[y] + u32::from(if self.up { x == y } else { x != y }))
        })
    }

    /// The sub-triangle across sub-edge `x` inside the same layer, or `None` when that side lies on the face's
    /// edge `x`.
    pub fn inside_neighbour(&self, x: usize) -> Option<SubTriangle> {
        let mut cell = self.cell;
        if self.up {
            cell[x] = cell[x].checked_sub(1)?;
        } else {
            cell[x] += 1;
        }
        Some(SubTriangle { cell, up: !self.up })
    }
}

/// What lies across one sub-edge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SubNeighbour {
    /// The sub-triangle of this local index in the same face.
    Inside(u32),
    /// The sub-triangles (local indices at that face's level, in order along the edge) of `face` touching the
    /// sub-edge, which lies on that face's edge `edge`.
    Across { face: u32, edge: usize, subs: Vec<u32> },
    /// The face's edge has no neighbour (mesh boundary or a cut edge).
    Boundary,
}

/// The neighbour across sub-edge `x` of sub-triangle `i` of face `f`, with `levels[g]` the level of face `g`.
pub fn sub_neighbour(mesh: &FurMesh, levels: &[u32], f: usize, i: u32, x: usize) -> SubNeighbour {
    let d = levels[f];
    let t = SubTriangle::from_index(i, d);
    if let Some(n) = t.inside_neighbour(x) {
        return SubNeighbour::Inside(n.index(d));
    }
    let g = mesh.neighbours[f][x];
    if g == NONE {
        return SubNeighbour::Boundary;
    }
    let z = (x + 2) % 3;
    let (va, vb) = edge_of(mesh.faces[f], x);
    let g = g as usize;
    let Some(xg) = mesh.edge_index(g, va, vb) else {
        return SubNeighbour::Boundary;
    };
    // In g the edge runs the other way: g's corner (xg + 1) is f's corner z, so λ'_{xg+1} = λ_z along the edge.
    let (yg, zg) = ((xg + 1) % 3, (xg + 2) % 3);
    debug_assert_eq!(mesh.faces[g][yg], mesh.faces[f][z]);
    let dg = levels[g];
    let k = t.cell[z]; // the sub-edge covers λ_z ∈ [k, k + 1] / 2^d
    let (lo, hi) = if dg >= d {
        let s = 1 << (dg - d);
        (k * s, (k + 1) * s)
    } else {
        let s = k >> (d - dg);
        (s, s + 1)
    };
    let ng = 1u32 << dg;
    let subs = (lo..hi)
        .map(|kg| {
            let mut cell = [0; 3];
            cell[yg] = kg;
            cell[zg] = ng - 1 - kg;
            SubTriangle { cell, up: true }.index(dg)
        })
        .collect();
    SubNeighbour::Across {
        face: g as u32,
        edge: xg,
        subs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_one_indices_by_hand() {
        // Corner 0's sub-triangle is row 0; row 1 runs corner 1 (i_1 = 0, i_2 = 1 → 2 − 1 = 1), the centre
        // (i_1 = i_2 = 1 → 2), corner 2 (i_1 = 1, i_2 = 0 → 3).
        assert_eq!(locate([0.8, 0.1, 0.1], 1), 0);
        assert_eq!(locate([0.1, 0.8, 0.1], 1), 1);
        assert_eq!(locate([1.0 / 3.0; 3], 1), 2);
        assert_eq!(locate([0.1, 0.1, 0.8], 1), 3);
        assert_eq!(sub_indices([0.1, 0.8, 0.1], 1), [1, 0, 1]);
        // Level 0: one sub-triangle whatever the point.
        assert_eq!(locate([0.2, 0.3, 0.5], 0), 0);
    }

    #[test]
    fn corners_and_edges_stay_in_range() {
        for d in 0..=MAX_LEVEL {
            let n4 = 1u32 << (2 * d);
            for l in [
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.5, 0.5, 0.0],
                [0.0, 0.5, 0.5],
            ] {
                assert!(locate(l, d) < n4, "d = {d}, {l:?}");
            }
            // Rounding just outside the triangle clamps instead of wrapping.
            assert!(locate([1.0 + 1e-6, -1e-6, 0.0], d) < n4);
        }
        assert_eq!(locate([0.0, 0.0, 1.0], 3), 63); // corner 2 is the last index of the last row
    }

    #[test]
    fn the_power_reading_of_eq_1_collides() {
        // ⌊(1 − λ)^(2^d)⌋ is 0 for every interior point, so all 16 level-2 centroids share index 0.
        let power = |l: [f32; 3], d: u32| local_index(l.map(|x| (1.0 - x).powi(1 << d).floor() as u32));
        let distinct: std::collections::BTreeSet<u32> = (0..16)
            .map(|i| power(SubTriangle::from_index(i, 2).centroid(2), 2))
            .collect();
        assert_eq!(distinct.len(), 1);
    }

    #[test]
    fn centroids_round_trip_and_corners_sum_to_the_lattice_size() {
        for d in 0..=6 {
            for i in 0..1u32 << (2 * d) {
                let t = SubTriangle::from_index(i, d);
                assert_eq!(t.index(d), i);
                assert_eq!(locate(t.centroid(d), d), i, "d = {d}");
                for c in t.corners() {
                    assert_eq!(c.iter().sum::<u32>(), 1 << d);
                }
            }
        }
    }

    #[test]
    fn inside_neighbours_share_a_side_and_are_mutual() {
        for d in 1..=5 {
            for i in 0..1u32 << (2 * d) {
                let t = SubTriangle::from_index(i, d);
                for x in 0..3 {
                    let Some(n) = t.inside_neighbour(x) else {
                        assert!(t.up && t.cell[x] == 0);
                        continue;
                    };
                    assert_eq!(n.inside_neighbour(x), Some(t));
                    let (a, b) = (t.corners(), n.corners());
                    for y in (0..3).filter(|&y| y != x) {
                        assert!(b.contains(&a[y]), "d {d} i {i} x {x}");
                    }
                    assert!(!b.contains(&a[x]));
                }
            }
        }
        // Level 1: the centre's neighbours are the three corner sub-triangles.
        let centre = SubTriangle::from_index(2, 1);
        let across: Vec<u32> = (0..3)
            .map(|x| centre.inside_neighbour(x).unwrap().index(1))
            .collect();
        assert_eq!(across, vec![0, 1, 3]);
    }

    #[test]
    fn global_indices_follow_offsets() {
        assert_eq!(global_index(0, 0, 2, 5), 5);
        assert_eq!(global_index(100, 3, 2, 5), 100 + 3 * 16 + 5);
        assert_eq!(layer_of(0.0, 8), 0);
        assert_eq!(layer_of(1.0, 8), 7);
        assert_eq!(layer_of(0.49, 2), 0);
        assert_eq!(layer_of(0.51, 2), 1);
    }
}
