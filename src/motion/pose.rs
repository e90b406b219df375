//! The rigid pose of the root frame (a head turn, nod or shake) and the colliders (the head's ellipsoid, a
//! mesh's signed distance grid), shared by the simulation (`sim.rs`) and the guide-and-follow interpolation
//! (`follow.rs`).

use super::sdf::SdfGrid;
use glam::{Affine3A, Quat, Vec3};
use std::sync::Arc;

/// Rounds of collision and re-following per point in the length pass (the simulation's and the followers').
pub const COLLISION_ROUNDS: usize = 16;

/// A rigid pose: `x ↦ rotation · (x − pivot) + pivot + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Quat,
    pub pivot: Vec3,
    pub translation: Vec3,
}

impl Pose {
    pub const IDENTITY: Pose = Pose {
        rotation: Quat::IDENTITY,
        pivot: Vec3::ZERO,
        translation: Vec3::ZERO,
    };
    pub fn apply(&self, x: Vec3) -> Vec3 {
        self.rotation * (x - self.pivot) + self.pivot + self.translation
    }
    pub fn inverse_apply(&self, x: Vec3) -> Vec3 {
        self.rotation.inverse() * (x - self.pivot - self.translation) + self.pivot
    }
    /// The same map as an affine transform (for the meshes that ride on the root frame).
    pub fn affine(&self) -> Affine3A {
        Affine3A::from_rotation_translation(
            self.rotation,
            self.pivot + self.translation - self.rotation * self.pivot,
        )
    }
}

/// An ellipsoid collider in the head's rest frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    pub center: Vec3,
    pub radii: Vec3,
}

impl Ellipsoid {
    /// `|(x − c) / r|`: below 1 inside.
    pub fn level(&self, x: Vec3) -> f32 {
        ((x - self.center) / self.radii).length()
    }
    /// How far inside `x` is, in world units along the ray from the centre (0 outside).
    pub fn depth(&self, x: Vec3) -> f32 {
        let l = self.level(x);
        if l >= 1.0 || l == 0.0 {
            return 0.0;
        }
        let d = x - self.center;
        d.length() * (1.0 / l - 1.0)
    }
}

/// What the hair collides with, in the head's (root frame's) rest space: the generator's head ellipsoid or a
/// signed distance grid of meshes ([`super::sdf`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Collider {
    Ellipsoid(Ellipsoid),
    Sdf(Arc<SdfGrid>),
}

impl Collider {
    /// `local` (rest space) moved out of the collider, or `None` when it is not inside: the ellipsoid along
    /// the ray from its centre onto its surface, the grid along its gradient to its margin.
    pub fn push_out(&self, local: Vec3) -> Option<Vec3> {
        match self {
            Collider::Ellipsoid(e) => {
                let l = e.level(local);
                (l < 1.0 && l > 0.0).then(|| e.center + (local - e.center) / l)
            }
            Collider::Sdf(g) => g.push_out(local),
        }
    }

    /// How far inside the collider's surface `local` is (0 outside).
    pub fn depth(&self, local: Vec3) -> f32 {
        match self {
            Collider::Ellipsoid(e) => e.depth(local),
            Collider::Sdf(g) => g.depth(local),
        }
    }
}
