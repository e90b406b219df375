//! The generator's meshes: the head ellipsoid hair grows around and the floor that catches the hair's shadow.

use crate::scene::{Aabb, Mesh, Strands};
use glam::Vec3;

/// Longitude and latitude subdivisions of the head mesh.
const HEAD_LON: u32 = 40;
const HEAD_LAT: u32 = 24;
const SKIN: Vec3 = Vec3::new(0.80, 0.60, 0.50);
const FLOOR_COLOR: Vec3 = Vec3::new(0.55, 0.55, 0.55);

/// Lat/long ellipsoid with outward normals; degenerate triangles at the poles are left out.
pub(super) fn ellipsoid_mesh(r: Vec3) -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for i in 0..=HEAD_LAT {
        let theta = std::f32::consts::PI * i as f32 / HEAD_LAT as f32;
        for j in 0..=HEAD_LON {
            let phi = std::f32::consts::TAU * j as f32 / HEAD_LON as f32;
            let w = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            positions.push(w * r);
            normals.push((w / r).normalize_or(Vec3::Y));
        }
    }
    let row = HEAD_LON + 1;
    let mut indices = Vec::new();
    for i in 0..HEAD_LAT {
        for j in 0..HEAD_LON {
            let a = i * row + j;
            let (b, c, d) = (a + row, a + row + 1, a + 1);
            if i + 1 < HEAD_LAT {
                indices.extend_from_slice(&[a, c, b]);
            }
            if i > 0 {
                indices.extend_from_slice(&[a, d, c]);
            }
        }
    }
    Mesh {
        positions,
        normals,
        indices,
        color: SKIN,
    }
}

/// A square ground quad facing +Y below everything (at `y` when given), wide enough to catch the hair's
/// shadow.
pub(super) fn floor_mesh(strands: &Strands, meshes: &[Mesh], y: Option<f32>) -> Mesh {
    let b = meshes.iter().fold(Aabb::from_points(&strands.points), |b, m| {
        b.union(Aabb::from_points(&m.positions))
    });
    let (c, e) = (b.center(), b.extent());
    // Wide enough for the shadow of the top of the hair from a light about 50° up.
    let half = 0.5 * e.x.max(e.z) + 0.9 * e.y;
    let y = y.unwrap_or(b.min.y - 0.01 * e.y.max(1e-3));
    let positions = vec![
        Vec3::new(c.x - half, y, c.z - half),
        Vec3::new(c.x - half, y, c.z + half),
        Vec3::new(c.x + half, y, c.z + half),
        Vec3::new(c.x + half, y, c.z - half),
    ];
    Mesh {
        normals: vec![Vec3::Y; 4],
        positions,
        indices: vec![0, 1, 2, 0, 2, 3],
        color: FLOOR_COLOR,
    }
}
