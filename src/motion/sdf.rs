//! Mesh colliders as a signed distance grid, the collider shape engines ship for strands (AMD TressFX 4 and
//! Unreal's groom collide hair with signed distance fields); own code.
//!
//! [`SdfGrid::build`] samples, on the CPU and deterministically, the signed distance to a set of triangle meshes
//! at the nodes of a regular grid in the root frame's rest space:
//! - **Grid**: the meshes' bounds padded by `margin + 2` cells on every side; the cell is the longest axis of
//!   the bounds over `resolution`.
//! - **Distance**: exact point–triangle distances in a band of [`BAND`] cells around each triangle, then
//!   propagated to every node by fast sweeping over the closest triangle (Bridson's `makelevelset3` scheme: two
//!   rounds of the eight sweep orders, each node trying its already-swept neighbours' closest triangles).
//! - **Sign**: six axis half-rays per node vote (a half-ray that crosses the surface an odd number of times says
//!   inside); four votes of six make a node inside. Crossings are counted with a symbolic perturbation of the
//!   ray (each edge function computed once per shared edge, in a canonical direction), so a ray through an
//!   edge or a vertex crosses exactly one of the triangles that meet there. A mesh with a small opening (a neck)
//!   is outvoted by the rays that do not pass through it.
//!
//! [`SdfGrid::distance`] interpolates trilinearly (clamped to the grid, whose border lies `margin + 2` cells
//! outside every mesh, so a point outside the grid never collides); [`SdfGrid::gradient`] is the central
//! difference of that interpolation one cell either side. [`SdfGrid::push_out`] moves a point whose distance
//! is below the margin along the normalised gradient by `margin − d`. `shaders/motion/collide.wgsl` evaluates
//! the same expressions on the GPU.

use crate::scene::{Aabb, Mesh};
use anyhow::{Result, bail};
use glam::{DVec2, Vec3};

/// Cells around each triangle where distances are computed exactly before the sweeps.
pub const BAND: i64 = 2;
/// Largest `motion.collider_resolution`: 256 cells on the longest axis (≈ 70 MB of distances for a cube).
pub const MAX_RESOLUTION: u32 = 256;
/// Smallest `motion.collider_resolution`.
pub const MIN_RESOLUTION: u32 = 4;

/// A signed distance grid: `values[i + nx·(j + ny·k)]` is the signed distance (negative inside) at node
/// `origin + cell · (i, j, k)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SdfGrid {
    pub origin: Vec3,
    pub cell: f32,
    /// Nodes per axis.
    pub dims: [u32; 3],
    pub values: Vec<f32>,
    /// A point closer than this to the surface (or inside) is pushed out to it.
    pub margin: f32,
    /// The meshes' bounds (rest space).
    pub bounds: Aabb,
}

/// Ericson's closest point on triangle `(a, b, c)` to `p` ("Real-Time Collision Detection", § 5.1.5).
fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Sign of edge `a → b` seen from `q` in the plane, under the perturbation `q + (ε, ε²)`: never 0 for a
/// non-degenerate edge. Computed for the canonical direction (smaller endpoint first), so the two triangles
/// sharing an edge see exactly opposite signs.
fn edge_sign(a: DVec2, b: DVec2, q: DVec2) -> f64 {
    let flip = (b.x, b.y) < (a.x, a.y);
    let (a, b) = if flip { (b, a) } else { (a, b) };
    let e = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
    let s = if e != 0.0 {
        e.signum()
    } else if b.y != a.y {
        (a.y - b.y).signum()
    } else {
        (b.x - a.x).signum()
    };
    let w = e.abs();
    // The weight (|e|) rides in the magnitude: barycentric weights for the crossing point.
    if flip {
        -s * w.max(f64::MIN_POSITIVE)
    } else {
        s * w.max(f64::MIN_POSITIVE)
    }
}

impl SdfGrid {
    /// The signed distance grid of `meshes` at `resolution` cells on the longest axis, for a collision margin
    /// `margin` (see the module docs). Errors name `motion.colliders` when the meshes have no triangle.
    pub fn build(meshes: &[&Mesh], resolution: u32, margin: f32) -> Result<SdfGrid> {
        if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&resolution) {
            bail!(
                "motion.collider_resolution must be in {MIN_RESOLUTION}..={MAX_RESOLUTION} (got {resolution})"
            );
        }
        if !(margin.is_finite() && margin >= 0.0) {
            bail!("motion.collider_margin must be a finite number ≥ 0 (got {margin:?})");
        }
        let mut tris: Vec<[Vec3; 3]> = Vec::new();
        for m in meshes {
            for t in m.indices.chunks_exact(3) {
                let get = |i: u32| m.positions.get(i as usize).copied();
                if let (Some(a), Some(b), Some(c)) = (get(t[0]), get(t[1]), get(t[2]))
                    && (b - a).cross(c - a).length_squared() > 0.0
                    && a.is_finite()
                    && b.is_finite()
                    && c.is_finite()
                {
                    tris.push([a, b, c]);
                }
            }
        }
        if tris.is_empty() {
            bail!(
                "motion.colliders: the collider meshes have no triangle with area (an empty mesh cannot collide)"
            );
        }
        let bounds = tris
            .iter()
            .fold(Aabb::EMPTY, |b, t| b.union(Aabb::from_points(t)));
        let extent = bounds.max - bounds.min;
        let cell = extent.max_element() / resolution as f32;
        let pad = ((margin / cell).ceil() as u32).saturating_add(2);
        if !(cell.is_finite() && cell > 0.0) || pad > MAX_RESOLUTION {
            bail!(
                "motion.collider_margin {margin} is too wide for collider meshes {:.3} across at {resolution} cells",
                extent.max_element()
            );
        }
        let origin = bounds.min - Vec3::splat(cell * pad as f32);
        let dims = [0, 1, 2].map(|a| (extent[a] / cell).ceil() as u32 + 2 * pad + 1);
        let mut grid = SdfGrid {
            origin,
            cell,
            dims,
            values: Vec::new(),
            margin,
            bounds,
        };
        let (dist, _) = grid.unsigned(&tris);
        let inside = grid.inside(&tris);
        grid.values = dist
            .iter()
            .zip(&inside)
            .map(|(&d, &i)| if i { -d } else { d })
            .collect();
        Ok(grid)
    }

    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] as usize * (j + self.dims[1] as usize * k)
    }

    /// The position of node `(i, j, k)`.
    pub fn node(&self, i: u32, j: u32, k: u32) -> Vec3 {
        self.origin + Vec3::new(i as f32, j as f32, k as f32) * self.cell
    }

    /// Bytes the distances take (as uploaded to the GPU).
    pub fn bytes(&self) -> u64 {
        self.values.len() as u64 * 4
    }

    /// Unsigned distance and closest triangle per node: exact in a band, then swept.
    fn unsigned(&self, tris: &[[Vec3; 3]]) -> (Vec<f32>, Vec<u32>) {
        let [nx, ny, nz] = self.dims.map(|d| d as usize);
        let mut dist = vec![f32::INFINITY; nx * ny * nz];
        let mut near = vec![u32::MAX; nx * ny * nz];
        let dmax = [nx, ny, nz].map(|d| d as i64 - 1);
        for (t, tri) in tris.iter().enumerate() {
            let b = Aabb::from_points(tri);
            let lo = ((b.min - self.origin) / self.cell).floor();
            let hi = ((b.max - self.origin) / self.cell).ceil();
            let range = |a: usize| {
                (lo[a] as i64 - BAND).clamp(0, dmax[a]) as usize
                    ..=(hi[a] as i64 + BAND).clamp(0, dmax[a]) as usize
            };
            for k in range(2) {
                for j in range(1) {
                    for i in range(0) {
                        let p = self.node(i as u32, j as u32, k as u32);
                        let d = (closest_on_triangle(p, tri[0], tri[1], tri[2]) - p).length();
                        let n = self.index(i, j, k);
                        if d < dist[n] {
                            dist[n] = d;
                            near[n] = t as u32;
                        }
                    }
                }
            }
        }
        for _ in 0..2 {
            for dir in 0..8 {
                let step = [dir & 1, (dir >> 1) & 1, (dir >> 2) & 1].map(|b| if b == 0 { 1i64 } else { -1 });
                let order = |a: usize, len: usize| -> Vec<usize> {
                    if step[a] > 0 {
                        (0..len).collect()
                    } else {
                        (0..len).rev().collect()
                    }
                };
                let (is, js, ks) = (order(0, nx), order(1, ny), order(2, nz));
                for &k in &ks {
                    for &j in &js {
                        for &i in &is {
                            let n = self.index(i, j, k);
                            let p = self.node(i as u32, j as u32, k as u32);
                            for nb in 1..8usize {
                                let (di, dj, dk) = (nb & 1, (nb >> 1) & 1, (nb >> 2) & 1);
                                let (ii, jj, kk) = (
                                    i as i64 - step[0] * di as i64,
                                    j as i64 - step[1] * dj as i64,
                                    k as i64 - step[2] * dk as i64,
                                );
                                if ii < 0 || jj < 0 || kk < 0 || ii > dmax[0] || jj > dmax[1] || kk > dmax[2]
                                {
                                    continue;
                                }
                                let t = near[self.index(ii as usize, jj as usize, kk as usize)];
                                if t == u32::MAX || t == near[n] {
                                    continue;
                                }
                                let tri = &tris[t as usize];
                                let d = (closest_on_triangle(p, tri[0], tri[1], tri[2]) - p).length();
                                if d < dist[n] {
                                    dist[n] = d;
                                    near[n] = t;
                                }
                            }
                        }
                    }
                }
            }
        }
        (dist, near)
    }

    /// Per node, whether at least four of its six axis half-rays cross the surface an odd number of times.
    fn inside(&self, tris: &[[Vec3; 3]]) -> Vec<bool> {
        let dims = self.dims.map(|d| d as usize);
        let mut votes = vec![0u8; dims[0] * dims[1] * dims[2]];
        let grid = |p: Vec3, a: usize| (f64::from(p[a]) - f64::from(self.origin[a])) / f64::from(self.cell);
        for a in 0..3 {
            let (u, v) = ((a + 1) % 3, (a + 2) % 3);
            let mut columns: Vec<Vec<f64>> = vec![Vec::new(); dims[u] * dims[v]];
            for tri in tris {
                let q = tri.map(|p| DVec2::new(grid(p, u), grid(p, v)));
                let h = tri.map(|p| grid(p, a));
                let (lo, hi) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
                let (u0, u1) = (
                    lo.x.ceil().max(0.0) as usize,
                    (hi.x.floor()).min(dims[u] as f64 - 1.0),
                );
                let (v0, v1) = (
                    lo.y.ceil().max(0.0) as usize,
                    (hi.y.floor()).min(dims[v] as f64 - 1.0),
                );
                if u1 < 0.0 || v1 < 0.0 {
                    continue;
                }
                for iv in v0..=v1 as usize {
                    for iu in u0..=u1 as usize {
                        let c = DVec2::new(iu as f64, iv as f64);
                        let w = [
                            edge_sign(q[1], q[2], c),
                            edge_sign(q[2], q[0], c),
                            edge_sign(q[0], q[1], c),
                        ];
                        let all = |pos: bool| w.iter().all(|x| (*x > 0.0) == pos);
                        if all(true) || all(false) {
                            let sum = w[0] + w[1] + w[2];
                            columns[iu + dims[u] * iv].push((w[0] * h[0] + w[1] * h[1] + w[2] * h[2]) / sum);
                        }
                    }
                }
            }
            for iv in 0..dims[v] {
                for iu in 0..dims[u] {
                    let col = &mut columns[iu + dims[u] * iv];
                    col.sort_by(f64::total_cmp);
                    for ia in 0..dims[a] {
                        let below = col.partition_point(|&z| z < ia as f64);
                        let above = col.len() - below;
                        let mut ijk = [0usize; 3];
                        (ijk[a], ijk[u], ijk[v]) = (ia, iu, iv);
                        let n = self.index(ijk[0], ijk[1], ijk[2]);
                        votes[n] += (below % 2) as u8 + (above % 2) as u8;
                    }
                }
            }
        }
        votes.iter().map(|&v| v >= 4).collect()
    }

    /// Trilinear interpolation of the distances at `p`, clamped to the grid.
    pub fn distance(&self, p: Vec3) -> f32 {
        let max = Vec3::new(
            (self.dims[0] - 1) as f32,
            (self.dims[1] - 1) as f32,
            (self.dims[2] - 1) as f32,
        );
        let g = ((p - self.origin) / self.cell).clamp(Vec3::ZERO, max);
        let c = g.floor().min(max - Vec3::ONE);
        let t = g - c;
        let (i, j, k) = (c.x as usize, c.y as usize, c.z as usize);
        let v = |di: usize, dj: usize, dk: usize| self.values[self.index(i + di, j + dj, k + dk)];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let x00 = lerp(v(0, 0, 0), v(1, 0, 0), t.x);
        let x10 = lerp(v(0, 1, 0), v(1, 1, 0), t.x);
        let x01 = lerp(v(0, 0, 1), v(1, 0, 1), t.x);
        let x11 = lerp(v(0, 1, 1), v(1, 1, 1), t.x);
        lerp(lerp(x00, x10, t.y), lerp(x01, x11, t.y), t.z)
    }

    /// Central differences of [`SdfGrid::distance`] one cell either side of `p` (not normalised).
    pub fn gradient(&self, p: Vec3) -> Vec3 {
        let h = self.cell;
        let d = |e: Vec3| self.distance(p + e * h) - self.distance(p - e * h);
        Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z)) * (0.5 / h)
    }

    /// `p` moved out to the margin along the gradient when its distance is below the margin; `None` when it
    /// is not (or the gradient vanishes).
    pub fn push_out(&self, p: Vec3) -> Option<Vec3> {
        let d = self.distance(p);
        if d >= self.margin {
            return None;
        }
        let g = self.gradient(p);
        let l = g.length();
        (l > 0.0).then(|| p + g * ((self.margin - d) / l))
    }

    /// How far inside the surface `p` is (0 outside).
    pub fn depth(&self, p: Vec3) -> f32 {
        (-self.distance(p)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius `r` about the origin: `lat × lon` quads, poles shared, seam shared (closed).
    fn sphere(r: f32, lat: u32, lon: u32) -> Mesh {
        let mut positions = vec![Vec3::new(0.0, r, 0.0)];
        for i in 1..lat {
            let th = std::f32::consts::PI * i as f32 / lat as f32;
            for j in 0..lon {
                let ph = std::f32::consts::TAU * j as f32 / lon as f32;
                positions.push(Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()) * r);
            }
        }
        positions.push(Vec3::new(0.0, -r, 0.0));
        let south = positions.len() as u32 - 1;
        let at = |i: u32, j: u32| 1 + (i - 1) * lon + j % lon;
        let mut indices = Vec::new();
        for j in 0..lon {
            indices.extend([0, at(1, j + 1), at(1, j)]);
            indices.extend([south, at(lat - 1, j), at(lat - 1, j + 1)]);
        }
        for i in 1..lat - 1 {
            for j in 0..lon {
                indices.extend([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
                indices.extend([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
        Mesh {
            normals: positions.iter().map(|p| p.normalize()).collect(),
            positions,
            indices,
            color: Vec3::ONE,
        }
    }

    /// An axis-aligned box from `lo` to `hi`, 12 triangles.
    fn cube(lo: Vec3, hi: Vec3) -> Mesh {
        let positions: Vec<Vec3> = (0..8)
            .map(|c| {
                Vec3::new(
                    if c & 1 == 0 { lo.x } else { hi.x },
                    if c & 2 == 0 { lo.y } else { hi.y },
                    if c & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let indices = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        Mesh {
            normals: positions.clone(),
            positions,
            indices,
            color: Vec3::ONE,
        }
    }

    /// The analytic signed distance to the box `[lo, hi]`.
    fn box_distance(p: Vec3, lo: Vec3, hi: Vec3) -> f32 {
        let (c, h) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
        let q = (p - c).abs() - h;
        q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
    }

    #[test]
    fn the_nodes_of_a_box_hold_its_exact_signed_distance() {
        // A box's faces are planes, so the grid nodes hold the analytic distance up to rounding, inside and
        // outside (the sweeps reach every node with its closest face, edge or corner). Measured worst 0 (bit-exact).
        let (lo, hi) = (Vec3::new(-0.5, -0.25, -0.125), Vec3::new(0.5, 0.25, 0.125));
        let g = SdfGrid::build(&[&cube(lo, hi)], 16, 0.01).unwrap();
        // Cell 1/16; pad ⌈0.01/0.0625⌉ + 2 = 3 cells: 16 + 7 nodes along x, 8 + 7 along y, 4 + 7 along z.
        assert_eq!(g.dims, [23, 15, 11]);
        assert_eq!(g.cell, 0.0625);
        let mut worst = 0f32;
        let (mut inside, mut outside) = (0, 0);
        for k in 0..g.dims[2] {
            for j in 0..g.dims[1] {
                for i in 0..g.dims[0] {
                    let p = g.node(i, j, k);
                    let want = box_distance(p, lo, hi);
                    let got = g.values[g.index(i as usize, j as usize, k as usize)];
                    if want < -1e-4 {
                        inside += 1;
                    } else if want > 1e-4 {
                        outside += 1;
                    }
                    worst = worst.max((got - want).abs());
                }
            }
        }
        eprintln!("box: worst node error {worst:e}, {inside} nodes inside, {outside} outside");
        assert!(inside > 100 && outside > 1000);
        assert!(worst < 1e-5, "worst node error {worst}");
        // Hand-checked, between nodes: the centre is 0.125 inside (the nearest faces are z = ±0.125); a point
        // 0.1 beyond the +x face is 0.1 outside (linear there, so trilinear is exact); off the corner,
        // (0.6, 0.35, 0.225) is |(0.1, 0.1, 0.1)| = 0.1732 away (curved there: within 3h²/(8·0.17) = 8.6e-3).
        assert!(
            (g.distance(Vec3::ZERO) + 0.125).abs() < 1e-5,
            "{}",
            g.distance(Vec3::ZERO)
        );
        assert!((g.distance(Vec3::new(0.6, 0.0, 0.0)) - 0.1).abs() < 1e-5);
        let corner = g.distance(Vec3::new(0.6, 0.35, 0.225));
        assert!((corner - 0.1732).abs() < 8.6e-3, "{corner}");
    }

    #[test]
    fn a_sphere_meshes_distance_is_the_analytic_one_within_the_tessellation_and_cell_bounds() {
        // Unit sphere, 24 × 48 facets: the mesh lies inside the sphere by at most the sagitta of its widest
        // facet, r(1 − cos(π/24)) ≈ 8.6e-3 (a facet spans π/24 along θ and 2π/48 along φ), so at the nodes
        // |d_grid − (|p| − 1)| ≤ 8.6e-3 (measured 4.3e-3).
        let r = 1.0;
        let g = SdfGrid::build(&[&sphere(r, 24, 48)], 32, 0.02).unwrap();
        let sagitta = r * (1.0 - (std::f32::consts::PI / 24.0).cos());
        let mut worst = 0f32;
        for k in 0..g.dims[2] {
            for j in 0..g.dims[1] {
                for i in 0..g.dims[0] {
                    let p = g.node(i, j, k);
                    let got = g.values[g.index(i as usize, j as usize, k as usize)];
                    worst = worst.max((got - (p.length() - r)).abs());
                }
            }
        }
        eprintln!(
            "sphere: worst node error {worst:e} (sagitta {sagitta:e}, cell {})",
            g.cell
        );
        assert!(
            worst <= sagitta + 1e-5,
            "worst node error {worst} against the sagitta {sagitta}"
        );
        // Between nodes the trilinear interpolation of a distance whose Hessian is at most 1/|p| adds at most
        // 3·h²/(8·|p|) (h = 1/16 the cell, |p| ≥ 0.5 here): 2.9e-3 on top of the sagitta; measured 4.9e-3 in all.
        let bound = sagitta + 3.0 * g.cell * g.cell / (8.0 * 0.5) + 1e-5;
        let mut worst_between = 0f32;
        let mut worst_angle = 0f32;
        for n in 0..2000 {
            // Deterministic points on a spiral through the shell 0.5 ≤ |p| ≤ 1.1 (inside the grid, which ends 3
            // cells, 0.1875, beyond the sphere).
            let u = (n as f32 + 0.5) / 2000.0;
            let (th, ph) = ((1.0 - 2.0 * u).acos(), n as f32 * 2.399_963);
            let dir = Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin());
            let p = dir * (0.5 + 0.6 * u);
            worst_between = worst_between.max((g.distance(p) - (p.length() - r)).abs());
            // The gradient points away from the centre (the analytic one is p/|p|).
            let grad = g.gradient(p).normalize();
            worst_angle = worst_angle.max(grad.dot(dir).clamp(-1.0, 1.0).acos());
        }
        eprintln!(
            "sphere between nodes: worst {worst_between:e} (bound {bound:e}), gradient worst {worst_angle} rad"
        );
        assert!(worst_between <= bound, "{worst_between} > {bound}");
        // Gradient direction: measured worst 0.019 rad (1.1°) from the analytic normal.
        assert!(worst_angle < 0.1, "gradient off the normal by {worst_angle} rad");
    }

    #[test]
    fn push_out_puts_a_point_on_the_margin_along_the_normal() {
        // Box faces are flat: a point 0.05 inside the +x face of the box (0.3 thick) moves out along +x to
        // 0.02 outside it (the margin), hand-checked: x = 0.5 + 0.02.
        let (lo, hi) = (Vec3::splat(-0.5), Vec3::splat(0.5));
        let g = SdfGrid::build(&[&cube(lo, hi)], 16, 0.02).unwrap();
        let p = Vec3::new(0.45, 0.1, -0.05);
        let q = g.push_out(p).expect("inside");
        assert!((q - Vec3::new(0.52, 0.1, -0.05)).length() < 1e-5, "{q}");
        assert!(
            g.push_out(Vec3::new(0.6, 0.0, 0.0)).is_none(),
            "outside the margin"
        );
        // A point outside the grid clamps to the border, far outside: it never collides.
        assert!(g.push_out(Vec3::new(40.0, 0.0, 0.0)).is_none());
    }

    #[test]
    fn empty_meshes_and_bad_parameters_are_refused_naming_the_key() {
        let empty = Mesh::default();
        let e = SdfGrid::build(&[&empty], 48, 0.01).unwrap_err().to_string();
        assert!(e.contains("motion.colliders") && e.contains("no triangle"), "{e}");
        let c = cube(Vec3::ZERO, Vec3::ONE);
        let e = SdfGrid::build(&[&c], 0, 0.01).unwrap_err().to_string();
        assert!(e.contains("motion.collider_resolution"), "{e}");
        let e = SdfGrid::build(&[&c], 48, f32::NAN).unwrap_err().to_string();
        assert!(e.contains("motion.collider_margin"), "{e}");
    }
}
