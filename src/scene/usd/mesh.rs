//! `Mesh` prims to hairlab meshes: polygons triangulated as fans, the winding of left-handed and mirrored prims
//! flipped, smooth normals, a constant `displayColor`.

use super::curves::Interp;
use super::{Reader, UsdError, When, ints, type_of};
use crate::scene::Mesh;
use glam::Vec3;
use openusd::usd::Prim;

/// One Mesh prim as a triangle mesh in the world.
pub(super) fn read_mesh(r: &Reader, prim: &Prim) -> Result<Mesh, UsdError> {
    let points = r.points(prim, When::Default)?;
    let fv = r
        .value(prim, "faceVertexIndices", When::Default)?
        .ok_or_else(|| r.err(prim, "faceVertexIndices", "missing"))?;
    let fv = ints(&fv).ok_or_else(|| {
        r.err(
            prim,
            "faceVertexIndices",
            format!("expected int[], found {}", type_of(&fv)),
        )
    })?;
    let counts = r.counts(prim, "faceVertexCounts", When::Default, fv.len())?;
    let mut idx = Vec::with_capacity(fv.len());
    for (i, &k) in fv.iter().enumerate() {
        match usize::try_from(k).ok().filter(|&k| k < points.len()) {
            Some(k) => idx.push(k as u32),
            None => {
                return Err(r.err(
                    prim,
                    "faceVertexIndices",
                    format!("index {i} is {k}, outside the {} points", points.len()),
                ));
            }
        }
    }
    let m = r.world(prim, When::Default)?;
    let left = r.token(prim, "orientation", "rightHanded")? == "leftHanded";
    let flip = left != (m.determinant() < 0.0);
    let mut indices = Vec::with_capacity(3 * fv.len());
    let mut first = 0;
    for &n in &counts {
        let face = &idx[first..first + n];
        first += n;
        for k in 2..n {
            let (a, b, c) = (face[0], face[k - 1], face[k]);
            indices.extend(if flip { [a, c, b] } else { [a, b, c] });
        }
    }
    let color = r.primvar(prim, "primvars:displayColor", When::Default, Interp::Constant)?;
    let color = match color {
        Some(c) if c.interp == Interp::Constant && c.values.len() == 1 => c.values[0].truncate().as_vec3(),
        _ => Vec3::splat(0.7),
    };
    let positions: Vec<Vec3> = points.iter().map(|&p| m.transform_point3(p).as_vec3()).collect();
    if let Some((i, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(r.err(
            prim,
            "points",
            format!("point {i} is not finite after the transform: {p}"),
        ));
    }
    let mut mesh = Mesh {
        positions,
        normals: Vec::new(),
        indices,
        color,
    };
    mesh.compute_normals();
    Ok(mesh)
}
