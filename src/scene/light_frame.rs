//! Light frames: view and projection of the light fitted tightly to a bounding box.
//!
//! Hair maps use a frame fitted to the strand bounds (every texel and every depth bit covers hair); the opaque
//! shadow map uses one fitted to the whole scene. Depth stored in light maps is the distance along the light axis,
//! normalised to [0,1] between the frame's near and far planes (`light_depth` in `shaders/common/frame.wgsl`).
//! Under `light.fit = stable` the hair maps' frame is [`LightFrame::stable`]: fitted to a bounding sphere, its
//! light-space origin snapped to whole texels (Valient 2008).

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

    /// Fits the frame of `light` (a spot placed around `around`, [`Light::spot_position`]) to `fit`.
    pub fn fit(light: &Light, around: &Aabb, fit: &Aabb) -> LightFrame {
        let to_light = light.to_light();
        let fit = match (fit.is_empty(), around.is_empty()) {
            (false, _) => *fit,
            (true, false) => Aabb {
                min: around.center(),
                max: around.center(),
            },
            (true, true) => Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            },
        };
        let radius = around.radius().max(fit.radius()).max(1e-3);
        let position = match light.kind {
            LightKind::Directional => fit.center() + to_light * (fit.radius() + radius),
            LightKind::Spot => light.spot_position(around),
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

    /// The stabilised frame of `light` ([`crate::scene::LightFit::Stable`]; Valient 2008, "Stable rendering of
    /// cascaded shadow maps"): fitted to the sphere around `hair`'s centre through its corners, so the extent and
    /// the depth range are the sphere's whatever the pose inside it or the light direction. A directional
    /// light's square window is centred on the sphere's centre snapped to whole texels of a
    /// `resolution`-texel map in a light space whose origin is the world's, so two spheres of one radius share
    /// one texel grid; a spot light is placed around `around` ([`Light::spot_position`]), its frustum the cone
    /// holding the sphere.
    pub fn stable(light: &Light, hair: &Aabb, around: &Aabb, resolution: u32) -> LightFrame {
        let to_light = light.to_light();
        let (center, r) = match (hair.is_empty(), around.is_empty()) {
            (false, _) => (hair.center(), hair.radius().max(1e-3)),
            (true, false) => (around.center(), around.radius().max(1e-3)),
            (true, true) => (Vec3::ZERO, 1e-3),
        };
        let up = if to_light.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        match light.kind {
            LightKind::Directional => {
                let res = resolution.max(4) as f32;
                // Half the window's side: the sphere, a hair's-breadth margin, and room for the snap (the
                // centre moves at most half a texel, h / res, and h (1 - 1 / res) ≥ r for res ≥ 2).
                let h = r * (1.0 + 1e-3 + 2.0 / res);
                let texel = 2.0 * h / res;
                let rotation = Mat4::look_at_rh(Vec3::ZERO, -to_light, up);
                let c = rotation.transform_point3(center);
                let snapped = (c.xy() / texel).round() * texel;
                // The eye 2h in front of the centre along the light axis: the sphere spans view depths
                // [2h - r, 2h + r] inside [h, 3h].
                let eye = snapped.extend(c.z + 2.0 * h);
                let world_to_view = Mat4::from_translation(-eye) * rotation;
                let (near, far) = (h, 3.0 * h);
                LightFrame {
                    world_to_view,
                    view_to_clip: Mat4::orthographic_rh(-h, h, -h, h, near, far),
                    near,
                    far,
                    position: rotation.transpose().transform_point3(eye),
                    to_light,
                }
            }
            LightKind::Spot => {
                let radius = around.radius().max(r);
                let position = light.spot_position(around);
                let world_to_view = Mat4::look_at_rh(position, position - to_light, up);
                let v = world_to_view.transform_point3(center);
                let m = r * (1.0 + 1e-3);
                let near = (-v.z - m).max(radius * 1e-3);
                let far = -v.z + m;
                // Every point of the sphere has |x| ≤ |v.x| + m at a depth ≥ near.
                let t = (v.x.abs().max(v.y.abs()) + m) / near;
                LightFrame {
                    world_to_view,
                    view_to_clip: Mat4::perspective_rh(2.0 * t.atan(), 1.0, near, far),
                    near,
                    far,
                    position,
                    to_light,
                }
            }
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
        let f = LightFrame::fit(&light, &b, &b);
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

    /// Points on the sphere `stable` fits to: its centre ± the radius along 26 directions.
    fn sphere_points(b: &Aabb) -> Vec<Vec3> {
        let mut out = Vec::new();
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    let d = Vec3::new(x as f32, y as f32, z as f32);
                    if d != Vec3::ZERO {
                        out.push(b.center() + d.normalize() * b.radius());
                    }
                }
            }
        }
        out
    }

    fn check_stable_holds_the_sphere(kind: LightKind) {
        let b = Aabb {
            min: Vec3::new(-0.3, 0.1, -0.2),
            max: Vec3::new(0.4, 0.5, 0.25),
        };
        for azimuth_deg in [0.0, 35.0, 90.0, 200.0] {
            let light = Light {
                kind,
                azimuth_deg,
                elevation_deg: 20.0,
                ..Light::default()
            };
            let f = LightFrame::stable(&light, &b, &b, 256);
            let clip = f.world_to_clip();
            for p in sphere_points(&b) {
                let c = clip.project_point3(p);
                assert!(
                    c.x.abs() <= 1.0 && c.y.abs() <= 1.0 && (0.0..=1.0).contains(&f.depth(p)),
                    "{kind:?} at azimuth {azimuth_deg} clips {p}: {c}"
                );
            }
        }
    }

    #[test]
    fn stable_directional_frame_holds_its_sphere_from_every_direction() {
        check_stable_holds_the_sphere(LightKind::Directional);
    }

    #[test]
    fn stable_spot_frame_holds_its_sphere_from_every_direction() {
        check_stable_holds_the_sphere(LightKind::Spot);
    }

    /// The window's side and the depth range are the sphere's: the same for every light direction.
    #[test]
    fn stable_extent_and_depth_range_do_not_change_with_the_light_direction() {
        let b = Aabb {
            min: Vec3::new(-0.3, 0.1, -0.2),
            max: Vec3::new(0.4, 0.5, 0.25),
        };
        let frame = |azimuth_deg: f32, elevation_deg: f32| {
            let light = Light {
                azimuth_deg,
                elevation_deg,
                ..Light::default()
            };
            LightFrame::stable(&light, &b, &b, 128)
        };
        let first = frame(0.0, 10.0);
        for (az, el) in [(35.0, 50.0), (90.0, 10.0), (270.0, 80.0)] {
            let f = frame(az, el);
            assert_eq!(f.view_to_clip, first.view_to_clip, "azimuth {az}, elevation {el}");
            assert_eq!((f.near, f.far), (first.near, first.far));
        }
    }

    /// Two spheres of one radius, their centres 0.37 texels apart across the light: both frames put the texel
    /// edges on one grid (a world point's texel coordinate differs by a whole number of texels), and the
    /// window moved by a whole texel.
    #[test]
    fn stable_snaps_the_light_space_origin_to_whole_texels() {
        let res = 64u32;
        let light = Light::default();
        let a = Aabb {
            min: Vec3::new(-0.5, -0.5, -0.5),
            max: Vec3::new(0.5, 0.5, 0.5),
        };
        let fa = LightFrame::stable(&light, &a, &a, res);
        let texel = 2.0 / (fa.view_to_clip.x_axis.x * res as f32);
        let across = fa.world_to_view.inverse().transform_vector3(Vec3::X);
        let shift = across * (0.37 * texel) + across * (5.0 * texel);
        let b = Aabb {
            min: a.min + shift,
            max: a.max + shift,
        };
        let fb = LightFrame::stable(&light, &b, &b, res);
        let texel_x =
            |f: &LightFrame, p: Vec3| (f.world_to_clip().project_point3(p).x * 0.5 + 0.5) * res as f32;
        for p in sphere_points(&a) {
            let d = texel_x(&fa, p) - texel_x(&fb, p);
            assert!(
                (d - d.round()).abs() < 1e-3,
                "{p}: texel coordinates {d} apart, not a whole number"
            );
            assert_eq!(d.round(), 5.0, "{p}: the window moved {d} texels");
        }
    }
}
