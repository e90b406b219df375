//! Roots on a mesh's triangles (a loaded scalp, a fur base mesh): area-weighted points with the interpolated
//! vertex normal as the growth direction.

use super::{GenError, Root};
use crate::rng::SplitMix64 as Rng;
use crate::scene::Mesh;
use glam::Vec3;

/// `n` roots on `tris` of `mesh` (non-empty, positive total area), area-weighted, from `seed`'s root stream.
pub(super) fn mesh_roots(mesh: &Mesh, tris: &[MeshTri], n: usize, seed: u64) -> Vec<Root> {
    let total = tris.last().map_or(0.0, |t| t.cum_area);
    let mut rng = Rng::stream(seed, 0);
    (0..n)
        .map(|_| {
            let target = f64::from(rng.unit()) * total;
            let k = tris
                .partition_point(|t| t.cum_area <= target)
                .min(tris.len().saturating_sub(1));
            tris.get(k).map_or(
                Root {
                    pos: Vec3::ZERO,
                    dir: Vec3::Y,
                },
                |t| t.sample(mesh, &mut rng),
            )
        })
        .collect()
}

/// The scalp's upward-facing filter: triangles whose normal has y above this grow hair.
pub(super) const SCALP_MIN_NORMAL_Y: f32 = -0.2;

/// A triangle hair grows on, with the running total of area up to and including it.
pub(super) struct MeshTri {
    corners: [u32; 3],
    normal: Vec3,
    pub(super) cum_area: f64,
}

impl MeshTri {
    /// A uniform point on the triangle, with the interpolated vertex normal (or the face normal).
    fn sample(&self, mesh: &Mesh, rng: &mut Rng) -> Root {
        let (r1, r2) = (rng.unit().sqrt(), rng.unit());
        let (wb, wc) = (r1 * (1.0 - r2), r1 * r2);
        let corner = |k: usize, v: &[Vec3]| {
            self.corners
                .get(k)
                .and_then(|&i| v.get(i as usize))
                .copied()
                .unwrap_or(Vec3::ZERO)
        };
        let [a, b, c] = [0, 1, 2].map(|k| corner(k, &mesh.positions));
        let pos = a + (b - a) * wb + (c - a) * wc;
        let normal = if mesh.normals.len() == mesh.positions.len() {
            let [na, nb, nc] = [0, 1, 2].map(|k| corner(k, &mesh.normals));
            na + (nb - na) * wb + (nc - na) * wc
        } else {
            self.normal
        };
        Root {
            pos,
            dir: normal
                .try_normalize()
                .filter(|n| n.is_finite())
                .unwrap_or(self.normal),
        }
    }
}

/// The mesh's non-degenerate triangles (only those with normal.y above `min_normal_y` when given) with
/// cumulative areas; errors on indices out of range or non-finite positions.
pub(super) fn mesh_triangles(mesh: &Mesh, min_normal_y: Option<f32>) -> Result<Vec<MeshTri>, GenError> {
    let bad = |reason: String| GenError::BadScalp { reason };
    let vertex = |i: u32| {
        let p = mesh.positions.get(i as usize).copied().ok_or_else(|| {
            bad(format!(
                "index {i} is out of range for {} vertices",
                mesh.positions.len()
            ))
        })?;
        if p.is_finite() {
            Ok(p)
        } else {
            Err(bad(format!("vertex {i} has a non-finite position {p}")))
        }
    };
    let has_normals = mesh.normals.len() == mesh.positions.len();
    let mut out = Vec::new();
    let mut total = 0.0f64;
    for &corners in mesh.indices.as_chunks::<3>().0 {
        let [a, b, c] = corners;
        let (pa, pb, pc) = (vertex(a)?, vertex(b)?, vertex(c)?);
        let cross = (pb - pa).cross(pc - pa);
        let Some(mut normal) = cross.try_normalize() else {
            continue;
        };
        if has_normals {
            let vn: Vec3 = corners.iter().filter_map(|&i| mesh.normals.get(i as usize)).sum();
            if vn.dot(normal) < 0.0 {
                normal = -normal;
            }
        }
        if min_normal_y.is_none_or(|y| normal.y > y) {
            total += f64::from(cross.length()) * 0.5;
            out.push(MeshTri {
                corners,
                normal,
                cum_area: total,
            });
        }
    }
    Ok(out)
}
