//! The scene's meshes for the fibres model's light probe (`shading::mesh_bounce`): the path tracer's hierarchy
//! ([`Bvh`]) over the mesh triangles alone, so that the probe's rays and shadow rays cost the log of the
//! triangles rather than their number (hair on a scalp of 86 400 triangles: a 320×240 `render` 8.6 s with every
//! triangle tested, 1.1 s through the hierarchy).

use glam::Vec3;

use super::bvh::Bvh;
use super::fibre::{Ray, Surface};
use super::triangle::Triangle;
use crate::shading::mesh_bounce::{MeshHit, MeshRays};

/// How far from its origin a probe ray starts to count a crossing ([`MeshRays`]).
const NEAR: f32 = 1e-5;

/// A hierarchy over mesh triangles and no fibres.
pub struct MeshBvh(Bvh);

impl MeshBvh {
    pub fn new(triangles: Vec<Triangle>) -> MeshBvh {
        MeshBvh(Bvh::with_triangles(Vec::new(), triangles))
    }

    /// The ray from `NEAR` along `dir` past `origin`, so that a crossing at `t` is one at `NEAR + t` from it.
    fn ray(origin: Vec3, dir: Vec3) -> Ray {
        Ray::new(origin + dir * NEAR, dir)
    }
}

impl MeshRays for MeshBvh {
    fn nearest(&self, origin: Vec3, dir: Vec3) -> Option<MeshHit> {
        let hit = self.0.closest_hit(&Self::ray(origin, dir), f32::INFINITY)?;
        let Surface::Mesh { albedo } = hit.surface else {
            return None;
        };
        Some(MeshHit {
            distance: NEAR + hit.t,
            normal: hit.normal,
            albedo,
        })
    }

    fn blocked(&self, origin: Vec3, dir: Vec3, max: f32) -> bool {
        max > NEAR && self.0.any_hit(&Self::ray(origin, dir), max - NEAR)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// The hierarchy answers as every triangle tested one by one does: over 300 random triangles and 2000 random
    /// rays (origins inside and around them), the same nearest distance within 1e-5 relative, the same normal
    /// (facing the ray) and albedo, and the same answer to "blocked within a random distance" (rays whose
    /// nearest crossing lies within 1e-4 of that distance left out); an empty scene meets nothing.
    #[test]
    fn the_hierarchy_equals_testing_every_triangle() {
        let mut rng = SplitMix64::new(5);
        let point = |rng: &mut SplitMix64| {
            Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
        };
        let triangles: Vec<Triangle> = (0..300)
            .map(|k| {
                let a = point(&mut rng);
                Triangle {
                    p0: a,
                    e1: point(&mut rng) * 0.3,
                    e2: point(&mut rng) * 0.3,
                    albedo: Vec3::splat(k as f32 / 300.0),
                }
            })
            .collect();
        let bvh = MeshBvh::new(triangles.clone());
        let (mut met, mut blocked) = (0, 0);
        for _ in 0..2000 {
            let origin = point(&mut rng) * 1.5;
            let dir = point(&mut rng).normalize_or(Vec3::Z);
            let ray = Ray::new(origin, dir);
            let each = triangles
                .iter()
                .filter_map(|t| t.intersect(&ray, NEAR, f32::INFINITY))
                .min_by(|a, b| a.t.total_cmp(&b.t));
            let got = bvh.nearest(origin, dir);
            match (each, got) {
                (None, None) => {}
                (Some(e), Some(g)) => {
                    met += 1;
                    assert!(
                        (e.t - g.distance).abs() <= 1e-5 * e.t.max(1.0),
                        "{} vs {}",
                        e.t,
                        g.distance
                    );
                    assert_eq!(g.normal, e.normal);
                    assert_eq!(Surface::Mesh { albedo: g.albedo }, e.surface);
                }
                (e, g) => panic!("{origin} {dir}: one by one {e:?}, hierarchy {g:?}"),
            }
            let max = rng.range(0.0, 3.0);
            if each.is_some_and(|e| (e.t - max).abs() < 1e-4) {
                continue;
            }
            let want = each.is_some_and(|e| e.t < max);
            blocked += usize::from(want);
            assert_eq!(bvh.blocked(origin, dir, max), want, "{origin} {dir} within {max}");
        }
        assert!(
            met > 200 && blocked > 100,
            "{met} rays met a triangle, {blocked} blocked"
        );
        let empty = MeshBvh::new(Vec::new());
        assert_eq!(empty.nearest(Vec3::ZERO, Vec3::Z), None);
        assert!(!empty.blocked(Vec3::ZERO, Vec3::Z, 10.0));
    }
}
