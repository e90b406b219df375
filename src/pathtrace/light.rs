//! The path tracer's lights: a directional light, and a spot light as Mitsuba 3's `spot` emitter defines it (a
//! point of radiant intensity `intensity`, full inside `beam` of its axis, falling linearly in angle to nothing at
//! `cutoff`, over the squared distance) so an exported scene renders the same in both.

use glam::Vec3;

/// A directional light: the unit direction towards it and the irradiance it gives a surface facing it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    pub to_light: Vec3,
    pub irradiance: Vec3,
}

/// A spot light at `position` shining along the unit `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    pub axis: Vec3,
    /// Radiant intensity on the axis.
    pub intensity: Vec3,
    /// Half-angles in radians: full intensity within `beam`, none beyond `cutoff`.
    pub beam: f32,
    pub cutoff: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Directional(DirectionalLight),
    Spot(SpotLight),
}

/// Where the light reaches a point from: the unit direction towards the light, the distance to it (infinite for
/// a directional light) and the irradiance it gives a surface facing it there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrival {
    pub to_light: Vec3,
    pub distance: f32,
    pub irradiance: Vec3,
}

impl SpotLight {
    /// The share of the axis intensity sent at `angle` radians off the axis.
    pub fn falloff(&self, angle: f32) -> f32 {
        if angle >= self.cutoff {
            0.0
        } else if angle <= self.beam {
            1.0
        } else {
            (self.cutoff - angle) / (self.cutoff - self.beam)
        }
    }
}

/// What the integrator asks of a light: how it reaches a point. [`Light`] is the truth's; the raster's light
/// (`effects::RasterLight`, a spot with no falloff over distance) lights the traced probe
/// (`pathtrace::probe`) as the eye pass lights the hair.
pub trait Lighting: Sync {
    /// How the light reaches `p`; `None` where it sends nothing.
    fn arrival(&self, p: Vec3) -> Option<Arrival>;
}

impl Lighting for Light {
    fn arrival(&self, p: Vec3) -> Option<Arrival> {
        Light::arrival(self, p)
    }
}

impl Light {
    /// How the light reaches `p`; `None` where it sends nothing.
    pub fn arrival(&self, p: Vec3) -> Option<Arrival> {
        match self {
            Light::Directional(d) => Some(Arrival {
                to_light: d.to_light,
                distance: f32::INFINITY,
                irradiance: d.irradiance,
            }),
            Light::Spot(s) => {
                let d = s.position - p;
                let distance = d.length();
                let to_light = d / distance;
                let falloff = s.falloff((-to_light).dot(s.axis).clamp(-1.0, 1.0).acos());
                (falloff > 0.0 && distance > 0.0).then(|| Arrival {
                    to_light,
                    distance,
                    irradiance: s.intensity * falloff / (distance * distance),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spot_falls_off_linearly_in_angle_and_with_the_squared_distance() {
        let spot = SpotLight {
            position: Vec3::new(0.0, 2.0, 0.0),
            axis: -Vec3::Y,
            intensity: Vec3::splat(8.0),
            beam: 10f32.to_radians(),
            cutoff: 30f32.to_radians(),
        };
        let light = Light::Spot(spot);
        let at = |p: Vec3| light.arrival(p).map(|a| a.irradiance.x);
        assert_eq!(at(Vec3::ZERO), Some(2.0));
        assert_eq!(at(Vec3::new(0.0, 1.0, 0.0)), Some(8.0));
        // 20° off the axis at distance 2: half the way from beam to cutoff.
        let p = spot.position + 2.0 * Vec3::new(20f32.to_radians().sin(), -20f32.to_radians().cos(), 0.0);
        assert!((at(p).unwrap() - 1.0).abs() < 1e-5, "{:?}", at(p));
        let outside = spot.position + Vec3::new(31f32.to_radians().sin(), -31f32.to_radians().cos(), 0.0);
        assert_eq!(at(outside), None);
        let a = light.arrival(Vec3::ZERO).unwrap();
        assert_eq!((a.to_light, a.distance), (Vec3::Y, 2.0));
    }
}
