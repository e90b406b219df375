//! The rigid pose of the root frame (a head turn, nod or shake) and the head's ellipsoid collider, shared by the
//! simulation (`sim.rs`) and the guide-and-follow interpolation (`follow.rs`).

use glam::{Quat, Vec3};

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
