//! Light frames: view and projection of the light fitted tightly to a bounding box.
//!
//! Hair maps use a frame fitted to the strand bounds (every texel and every depth bit covers hair); the opaque
//! shadow map uses one fitted to the whole scene. Depth stored in light maps is the distance along the light axis,
//! normalised to [0,1] between the frame's near and far planes (`light_depth` in `shaders/common/frame.wgsl`).

use crate::scene::{Aabb, Light, LightKind};
use glam::{Mat4, Vec3, Vec3Swizzles};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFrame {
    pub world_to_view: Mat4,
    pub view_to_clip: Mat4,
    /// Distances along the light axis bounding the fitted box.
    pub near: f32,
    pub far: f32,
    /// Spot light position (world); for a directional light, a point behind the box.
    pub position: Vec3,
    /// Unit vector from the scene towards the light (directional) or the spot's axis reversed.
    pub to_light: Vec3,
}

impl LightFrame {
    pub fn world_to_clip(&self) -> Mat4 {
        self.view_to_clip * self.world_to_view
    }

    /// Normalised light depth of `p` (0 at the near plane, 1 at the far plane).
    pub fn depth(&self, p: Vec3) -> f32 {
        let v = self.world_to_view.transform_point3(p);
        (-v.z - self.near) / (self.far - self.near)
    }

    /// Fits the frame of `light` (placed around `scene_center` at `scene_radius` scale) to `fit`.
    pub fn fit(light: &Light, scene_center: Vec3, scene_radius: f32, fit: &Aabb) -> LightFrame {
        let to_light = light.to_light();
        let fit = if fit.is_empty() {
            Aabb {
                min: scene_center,
                max: scene_center,
            }
        } else {
            *fit
        };
        let radius = scene_radius.max(fit.radius()).max(1e-3);
        let position = match light.kind {
            LightKind::Directional => fit.center() + to_light * (fit.radius() + radius),
            LightKind::Spot => scene_center + to_light * radius * light.distance.max(1.01),
        };
        let up = if to_light.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let world_to_view = Mat4::look_at_rh(position, position - to_light, up);
        let corners = fit.corners().map(|c| world_to_view.transform_point3(c));
        let min_d = corners.iter().map(|c| -c.z).fold(f32::INFINITY, f32::min);
        let max_d = corners.iter().map(|c| -c.z).fold(f32::NEG_INFINITY, f32::max);
        // A hair's-breadth margin so the extreme strand points are not clipped.
        let pad = (max_d - min_d).max(1e-4) * 1e-3;
        let (near, far) = match light.kind {
            LightKind::Directional => (min_d - pad, max_d + pad),
            LightKind::Spot => ((min_d - pad).max(radius * 1e-3), max_d + pad),
        };
        let view_to_clip = match light.kind {
            LightKind::Directional => {
                let (mut lo, mut hi) = (
                    glam::Vec2::splat(f32::INFINITY),
                    glam::Vec2::splat(f32::NEG_INFINITY),
                );
                for c in &corners {
                    lo = lo.min(c.xy());
                    hi = hi.max(c.xy());
                }
                let m = (hi - lo).max(glam::Vec2::splat(1e-4)) * 1e-3;
                Mat4::orthographic_rh(lo.x - m.x, hi.x + m.x, lo.y - m.y, hi.y + m.y, near, far)
            }
            LightKind::Spot => {
                // Tightest symmetric frustum around the axis that holds every corner.
                let mut t = 1e-4f32;
                for c in &corners {
                    let z = (-c.z).max(near);
                    t = t.max(c.x.abs() / z).max(c.y.abs() / z);
                }
                Mat4::perspective_rh(2.0 * (t * 1.001).atan(), 1.0, near, far)
            }
        };
        LightFrame {
            world_to_view,
            view_to_clip,
            near,
            far,
            position,
            to_light,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_fits(kind: LightKind) {
        let b = Aabb {
            min: Vec3::new(-1.0, 0.0, -0.5),
            max: Vec3::new(1.0, 2.0, 0.5),
        };
        let light = Light {
            kind,
            azimuth_deg: 30.0,
            elevation_deg: 40.0,
            ..Light::default()
        };
        let f = LightFrame::fit(&light, b.center(), b.radius(), &b);
        let clip = f.world_to_clip();
        let mut touches = [false; 4];
        for c in b.corners() {
            let p = clip.project_point3(c);
            assert!(
                p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                "{kind:?} clips {c}"
            );
            let d = f.depth(c);
            assert!((0.0..=1.0).contains(&d));
            touches[0] |= d < 0.01;
            touches[1] |= d > 0.99;
            touches[2] |= p.x.abs() > 0.99 || p.y.abs() > 0.99;
            touches[3] = true;
        }
        // Tight: the nearest corner sits at depth ~0, the furthest at ~1, and the box reaches the frustum's side.
        assert!(
            touches.iter().all(|&t| t),
            "{kind:?} frame not tight: {touches:?}"
        );
    }

    #[test]
    fn directional_frame_is_tight() {
        check_fits(LightKind::Directional);
    }

    #[test]
    fn spot_frame_is_tight() {
        check_fits(LightKind::Spot);
    }
}
