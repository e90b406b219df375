//! One substep of the CPU strand simulation for one strand (`sim.rs`'s steps 1–7: Verlet, root, global and
//! local shape, collision, follow the leader, velocity), and what it reads, so that a substep's strands run on
//! every core. Strands do not interact within a substep.

use glam::{Quat, Vec3};

use super::HeadMotion;
use super::follow::Follow;
use super::params::SimParams;
use super::pose::{COLLISION_ROUNDS, Collider, Pose};

/// The pose of strand `s` of `strands` at time `t`: the head's, or the sweep's for the last swept strands.
pub(super) fn strand_pose(params: &SimParams, pivot: Vec3, strands: usize, t: f64, s: usize) -> Pose {
    let mut pose = params.head_pose(t, pivot);
    if params.head == HeadMotion::Sweep && s + (params.sweep_strands as usize) >= strands {
        pose.translation = params.sweep_offset(t);
    }
    pose
}

/// What every strand of a substep reads of the simulation.
pub(super) struct Shared<'a> {
    pub(super) params: &'a SimParams,
    pub(super) rest: &'a [Vec3],
    pub(super) rest_len: &'a [f32],
    pub(super) head: Option<&'a Collider>,
    pub(super) pivot: Vec3,
    pub(super) ranges: &'a [(usize, usize)],
    pub(super) follow: Option<&'a Follow>,
}

/// Strands one rayon task of a substep steps.
pub(super) const STRANDS_PER_TASK: usize = 64;

/// One substep's values, shared by its strands.
pub(super) struct Substep<'a> {
    pub(super) sim: Shared<'a>,
    pub(super) t: f64,
    pub(super) h: f32,
    pub(super) decay: f32,
    pub(super) gravity: Vec3,
    pub(super) ks: f32,
    pub(super) head_pose: Pose,
}

impl Substep<'_> {
    /// Steps strand `s`, whose points are `x` (now), `prev` (before) and `corr` (scratch), `q` scratch too.
    pub(super) fn strand(
        &self,
        s: usize,
        q: &mut Vec<Vec3>,
        x: &mut [Vec3],
        prev: &mut [Vec3],
        corr: &mut [Vec3],
    ) {
        let (sim, h, decay, gravity, ks, head_pose) = (
            &self.sim,
            self.h,
            self.decay,
            self.gravity,
            self.ks,
            self.head_pose,
        );
        let (first, n) = sim.ranges[s];
        if n == 0 || !sim.follow.is_none_or(|f| f.simulated[s]) {
            return;
        }
        let p = sim.params;
        let pose = strand_pose(p, sim.pivot, sim.ranges.len(), self.t, s);
        let wind = p.wind_at(self.t, s);
        let rest = &sim.rest[first..first + n];
        let rest_len = &sim.rest_len[first..first + n];
        // 1. Verlet.
        q.clear();
        for i in 0..n {
            let mut a = gravity;
            if i > 0 {
                let seg = (x[i] - x[i - 1]).normalize_or_zero();
                a += wind - seg * seg.dot(wind);
            }
            q.push(x[i] + (x[i] - prev[i]) * decay + a * (h * h));
        }
        // 2. Root.
        q[0] = pose.apply(rest[0]);
        // 3. Global shape.
        if p.global_stiffness > 0.0 {
            let reach = p.global_range * n as f32;
            for i in 1..n {
                if (i as f32) < reach {
                    let pull = (pose.apply(rest[i]) - q[i]) * p.global_stiffness;
                    q[i] += pull;
                }
            }
        }
        // 4. Local shape.
        if ks > 0.0 {
            let mut g = pose.rotation;
            for i in 0..n - 1 {
                let target = q[i] + g * (rest[i + 1] - rest[i]);
                let del = (target - q[i + 1]) * ks;
                if i > 0 {
                    q[i] -= del;
                }
                q[i + 1] += del;
                let from = (target - q[i]).normalize_or_zero();
                let to = (q[i + 1] - q[i]).normalize_or_zero();
                if from != Vec3::ZERO && to != Vec3::ZERO {
                    g = (Quat::from_rotation_arc(from, to) * g).normalize();
                }
            }
        }
        // 5. Collision (the head's own pose, also for swept strands).
        if let Some(c) = sim.head {
            for qi in q.iter_mut().skip(1) {
                if let Some(out) = c.push_out(head_pose.inverse_apply(*qi)) {
                    *qi = head_pose.apply(out);
                }
            }
        }
        // 6. Follow the leader.
        corr[0] = Vec3::ZERO;
        for i in 1..n {
            let lead = q[i - 1];
            let follow = |to: Vec3| {
                let d = to - lead;
                let len = d.length();
                if len > 0.0 {
                    lead + d * (rest_len[i] / len)
                } else {
                    lead + (pose.apply(rest[i]) - pose.apply(rest[i - 1]))
                }
            };
            let mut fixed = follow(q[i]);
            // A follower the length pass put back inside the collider: out as in step 5, then back on its
            // leader's sphere, a few times (each round leaves it shallower on a convex collider).
            if let Some(c) = sim.head {
                for _ in 0..COLLISION_ROUNDS {
                    let Some(out) = c.push_out(head_pose.inverse_apply(fixed)) else {
                        break;
                    };
                    fixed = follow(head_pose.apply(out));
                }
            }
            corr[i] = fixed - q[i];
            q[i] = fixed;
        }
        // 7. Velocity (DFTL) and the new state.
        let s_damp = p.ftl_damping;
        for i in 0..n {
            let next = if i + 1 < n { corr[i + 1] } else { Vec3::ZERO };
            prev[i] = x[i] + next * s_damp;
            x[i] = q[i];
        }
    }
}
