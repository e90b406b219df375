//! Generated fur base meshes with the paper's triangle counts (Table 1): a cylinder of 64 around × 28 rings
//! = 3584 triangles (the mink-skin cylinder of Fig. 1) and a hat, a surface of revolution of a 44-segment
//! profile. The hat's crown is closed at a pole, whose segment is a fan of `around` triangles, so 64 × 44
//! gives 2·64·43 + 64 = 5568 triangles, not Table 1's 5632 = 2·64·44: that count needs every profile segment
//! to be a full quad ring, i.e. a crown left open (or 64 zero-area triangles at the pole, which welding
//! drops). Both meshes are indexed without seam duplicates and wound outward.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use crate::scene::Mesh;

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

/// The hat's profile (radius, height), from the crown's pole to the brim's rim: a domed top, the crown's wall
/// and an upturned brim, `segments` segments in all (at least 3).
pub fn hat_profile(segments: u32) -> Vec<Vec2> {
    let (top, wall) = (segments / 4, segments / 3);
    let brim = segments - top - wall;
    let (crown_r, crown_h, brim_r) = (0.09, 0.12, 0.17);
    let mut p = Vec::new();
    for k in 0..=top {
        let s = k as f32 / top as f32;
        p.push(Vec2::new(crown_r * s, crown_h + 0.015 * (1.0 - s * s)));
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

/// The hat: [`hat_profile`] revolved `around` times about +Y, a pole at the crown.
pub fn hat(around: u32, segments: u32) -> Mesh {
    let profile = hat_profile(segments);
    let mut positions = vec![Vec3::new(0.0, profile[0].y, 0.0)];
    for q in &profile[1..] {
        for j in 0..around {
            let phi = TAU * j as f32 / around as f32;
            positions.push(Vec3::new(q.x * phi.cos(), q.y, q.x * phi.sin()));
        }
    }
    // Ring i ≥ 1 of profile point i; ring 0 is the pole.
    let v = |i: u32, j: u32| {
        if i == 0 {
            0
        } else {
            1 + (i - 1) * around + j % around
        }
    };
    let mut indices = Vec::new();
    for i in 0..segments {
        for j in 0..around {
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            // Along φ then down the profile: (∂φ × ∂s) points out.
            if i > 0 {
                indices.extend_from_slice(&[a, b, c]);
            }
            indices.extend_from_slice(&[a, c, d]);
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
        assert_eq!(
            (h.positions.len(), h.indices.len() / 3),
            (1 + 5 * 6, 5 + 2 * 5 * 5)
        );
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
        // The crown's first fan triangle faces up; the upturned brim's last triangle faces up and in.
        let up = |k: usize| {
            let t = &h.indices[3 * k..3 * k + 3];
            let [a, b, d] = [0, 1, 2].map(|i| h.positions[t[i] as usize]);
            (b - a).cross(d - a).normalize().y
        };
        assert!(up(0) > 0.99);
        assert!(up(h.indices.len() / 3 - 1) > 0.5);
    }
}
