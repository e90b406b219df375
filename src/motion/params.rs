//! The simulation's parameters (`sim.rs`): time step, damping, stiffness, the keyframed root-frame motion, the
//! sweep and the wind (TressFX's model; see `sim.rs`'s module doc for the equations).

use glam::{Quat, Vec3};

use super::pose::Pose;
use super::{HeadMotion, MotionSettings};

/// Strands fall into this many wind classes by index, each gusting with its own phase
/// (`shaders/motion/simulate.wgsl` holds one wind vector per class).
pub const WIND_CLASSES: usize = 20;

/// Smooth 0 → 1 over `[0, 1]` (cubic), clamped outside.
fn ease(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// Keyframes `(time s, value)` eased between, held after the last, looped over `period` when given.
fn keyframed(keys: &[(f64, f64)], t: f64) -> f64 {
    let Some(&(t0, v0)) = keys.first() else { return 0.0 };
    if t <= t0 {
        return v0;
    }
    for w in keys.windows(2) {
        let ((ta, va), (tb, vb)) = (w[0], w[1]);
        if t <= tb {
            return va + (vb - va) * ease((t - ta) / (tb - ta));
        }
    }
    keys.last().map_or(0.0, |k| k.1)
}

/// The simulation's parameters as numbers (from [`MotionSettings`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SimParams {
    pub fps: f32,
    pub substeps: u32,
    pub damping: f32,
    pub gravity: f32,
    pub global_stiffness: f32,
    pub global_range: f32,
    pub local_stiffness: f32,
    pub ftl_damping: f32,
    pub wind: f32,
    pub wind_dir: Vec3,
    pub gust: f32,
    pub head: HeadMotion,
    pub head_angle_deg: f32,
    pub head_period: f32,
    pub sweep_strands: u32,
    pub sweep_amplitude: f32,
    /// Share of the strands simulated; the rest follow them ([`super::follow`]).
    pub guides: f32,
}

impl SimParams {
    pub fn from_settings(m: &MotionSettings) -> SimParams {
        SimParams {
            fps: m.fps,
            substeps: m.substeps,
            damping: m.damping,
            gravity: m.gravity,
            global_stiffness: m.global_stiffness,
            global_range: m.global_range,
            local_stiffness: m.local_stiffness,
            ftl_damping: m.ftl_damping,
            wind: m.wind,
            wind_dir: Vec3::from(m.wind_dir).normalize_or(Vec3::X),
            gust: m.gust,
            head: m.head,
            head_angle_deg: m.head_angle_deg,
            head_period: m.head_period,
            sweep_strands: m.sweep_strands,
            sweep_amplitude: m.sweep_amplitude,
            guides: m.guides,
        }
    }

    /// The substep length in seconds.
    pub fn h(&self) -> f32 {
        (1.0 / (f64::from(self.fps) * f64::from(self.substeps))) as f32
    }

    /// The root frame's pose at time `t` seconds (the head's rigid motion, about the neck at `pivot`).
    pub fn head_pose(&self, t: f64, pivot: Vec3) -> Pose {
        let a = f64::from(self.head_angle_deg).to_radians();
        let p = f64::from(self.head_period);
        // Looped motions: one period out and back; `turn` holds after one period.
        let phase = |t: f64| t.rem_euclid(p);
        let (yaw, pitch) = match self.head {
            HeadMotion::Still | HeadMotion::Sweep => (0.0, 0.0),
            HeadMotion::Turn => (keyframed(&[(0.1 * p, 0.0), (0.6 * p, a)], t), 0.0),
            HeadMotion::Nod => (
                0.0,
                keyframed(&[(0.0, 0.0), (0.25 * p, a), (0.75 * p, -a), (p, 0.0)], phase(t)),
            ),
            HeadMotion::Shake => (
                keyframed(&[(0.0, 0.0), (0.25 * p, a), (0.75 * p, -a), (p, 0.0)], phase(t)),
                0.0,
            ),
        };
        Pose {
            rotation: Quat::from_rotation_y(yaw as f32) * Quat::from_rotation_x(pitch as f32),
            pivot,
            translation: Vec3::ZERO,
        }
    }

    /// The sweep's translation at time `t` (the last `sweep_strands` strands' roots, along +Z).
    pub fn sweep_offset(&self, t: f64) -> Vec3 {
        if self.head != HeadMotion::Sweep {
            return Vec3::ZERO;
        }
        let s = (std::f64::consts::TAU * t / f64::from(self.head_period)).sin();
        Vec3::new(0.0, 0.0, (f64::from(self.sweep_amplitude) * s) as f32)
    }

    /// The wind vector for strand `s` at time `t`.
    pub fn wind_at(&self, t: f64, s: usize) -> Vec3 {
        if self.wind == 0.0 {
            return Vec3::ZERO;
        }
        let tau = std::f64::consts::TAU;
        let class = (s % WIND_CLASSES) as f64 / WIND_CLASSES as f64;
        let ts = t - 0.25 * class;
        let g = 0.6 * (tau * 0.7 * ts).sin() + 0.4 * (tau * 1.9 * ts + 1.3).sin();
        let swing = 20f64.to_radians() * (tau * 0.23 * t).sin();
        let dir = Quat::from_rotation_y(swing as f32) * self.wind_dir;
        dir * (self.wind * (1.0 + self.gust * g as f32))
    }
}
