//! Generated fur base meshes with the paper's triangle counts (Table 1): a cylinder of 64 around × 28 rings
//! = 3584 triangles (the mink-skin cylinder of Fig. 1) and a hat of 64 around × 44 profile segments = 5632
//! triangles (Fig. 9). Table 1's 5632 = 2·64·44 means every profile segment is a full quad ring, so the hat's
//! profile must not end on the axis (a pole's segment is a fan of 64 triangles, 2·64·43 + 64 = 5568). The hat
//! is therefore a single surface with a small vent hole at the top of the crown (radius [`CROWN_HOLE`], under
//! the 1 cm default shell height, so the undercoat closes over it) and the brim's rim as its two boundary loops:
//! an intentionally bounded annulus, which the shell handles as it handles the open cylinder (walls on boundary
//! edges). A closed hat with thickness (a welded torus) was the alternative; it would have furred the inside of
//! the crown and the underside of the brim too. Both meshes are indexed without seam duplicates and wound
//! outward.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::Mesh;

/// Table 1's cylinder: around, rings.
pub const CYLINDER_GRID: (u32, u32) = (64, 28);
/// The hat's around and profile segments.
pub const HAT_GRID: (u32, u32) = (64, 44);
const SKIN: Vec3 = Vec3::new(0.72, 0.58, 0.50);

/// An open cylinder along +Y from y = 0 to `height`, `around` quads around and `rings` quads along, two
/// triangles per quad, normals radial.
pub fn cylinder(radius: f32, height: f32, around: u32, rings: u32) -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for i in 0..=rings {
        let y = height * i as f32 / rings as f32;
        for j in 0..around {
            let phi = TAU * j as f32 / around as f32;
            let n = Vec3::new(phi.cos(), 0.0, phi.sin());
            positions.push(radius * n + Vec3::Y * y);
            normals.push(n);
        }
    }
    let v = |i: u32, j: u32| i * around + j % around;
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..around {
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            // Up then along φ: (∂y × ∂φ) points out.
            indices.extend_from_slice(&[a, d, c, a, c, b]);
        }
    }
    Mesh {
        positions,
        normals,
        indices,
        color: SKIN,
    }
}

/// Table 1's cylinder (radius 0.04, length 0.3 world units).
pub fn fur_cylinder() -> Mesh {
    cylinder(0.04, 0.3, CYLINDER_GRID.0, CYLINDER_GRID.1)
}

/// Radius of the vent hole at the top of the hat's crown, in world units.
pub const CROWN_HOLE: f32 = 0.006;

/// The hat's profile (radius, height), `segments + 1` points from the rim of the crown's vent hole to the
/// brim's rim: a domed top, the crown's wall and an upturned brim, `segments` segments in all (at least 3).
pub fn hat_profile(segments: u32) -> Vec<Vec2> {
    let (top, wall) = (segments / 4, segments / 3);
    let brim = segments - top - wall;
    let (crown_r, crown_h, brim_r) = (0.09, 0.12, 0.17);
    let mut p = Vec::new();
    for k in 0..=top {
        let s = k as f32 / top as f32;
        let r = CROWN_HOLE + (crown_r - CROWN_HOLE) * s;
        p.push(Vec2::new(r, crown_h + 0.015 * (1.0 - (r / crown_r).powi(2))));
    }
    for k in 1..=wall {
        let s = k as f32 / wall as f32;
        p.push(Vec2::new(crown_r * (1.0 + 0.06 * s), crown_h * (1.0 - s)));
    }
    for k in 1..=brim {
        let s = k as f32 / brim as f32;
        p.push(Vec2::new(
            crown_r * 1.06 + (brim_r - crown_r * 1.06) * s,
            0.02 * s * s,
        ));
    }
    p
}

/// The hat: [`hat_profile`] revolved `around` times about +Y, every profile segment a ring of `around` quads
/// (`2 · around · segments` triangles).
pub fn hat(around: u32, segments: u32) -> Mesh {
    let profile = hat_profile(segments);
    let mut positions = Vec::new();
    for q in &profile {
        for j in 0..around {
            let phi = TAU * j as f32 / around as f32;
            positions.push(Vec3::new(q.x * phi.cos(), q.y, q.x * phi.sin()));
        }
    }
    let v = |i: u32, j: u32| i * around + j % around;
    let mut indices = Vec::new();
    for i in 0..segments {
        for j in 0..around {
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            // Along φ then down the profile: (∂φ × ∂s) points out.
            indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    let mut mesh = Mesh {
        positions,
        normals: Vec::new(),
        indices,
        color: SKIN,
    };
    mesh.compute_normals();
    mesh
}

/// The hat with the counts of [`HAT_GRID`].
pub fn fur_hat() -> Mesh {
    hat(HAT_GRID.0, HAT_GRID.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_by_hand() {
        let c = cylinder(1.0, 1.0, 5, 3);
        assert_eq!((c.positions.len(), c.indices.len() / 3), (5 * 4, 2 * 5 * 3));
        let h = hat(5, 6);
        assert_eq!(hat_profile(6).len(), 7);
        assert_eq!((h.positions.len(), h.indices.len() / 3), (5 * 7, 2 * 5 * 6));
        assert_eq!(hat_profile(6)[0].x, CROWN_HOLE);
    }

    #[test]
    fn windings_face_out() {
        let c = cylinder(1.0, 1.0, 8, 2);
        for t in c.indices.chunks_exact(3) {
            let [a, b, d] = [0, 1, 2].map(|k| c.positions[t[k] as usize]);
            let n = (b - a).cross(d - a);
            let centre = (a + b + d) / 3.0;
            assert!(n.dot(Vec3::new(centre.x, 0.0, centre.z)) > 0.0);
        }
        let h = fur_hat();
        // The crown's first triangle (at the vent hole) faces up; the upturned brim's last faces up and in.
        let up = |k: usize| {
            let t = &h.indices[3 * k..3 * k + 3];
            let [a, b, d] = [0, 1, 2].map(|i| h.positions[t[i] as usize]);
            (b - a).cross(d - a).normalize().y
        };
        assert!(up(0) > 0.99);
        assert!(up(h.indices.len() / 3 - 1) > 0.5);
    }
}
