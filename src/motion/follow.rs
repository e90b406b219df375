//! Guide-and-follow interpolation (`motion.guides`): only a share of the strands — the **guides** — is
//! simulated, and every other strand — a **follower** — is rebuilt each frame from its nearest guides, as the
//! seed papers' animated timings assume (Sintorn & Assarsson interpolate their 20,000 strands from guides) and as
//! engines do (TressFX's follow hairs, Unreal's guide interpolation).
//!
//! Guides: strand `s` with `s mod m = 0`, `m = round(1 / guides)`, and every swept strand (the stray strands a
//! `sweep` moves must move themselves). Each follower takes the [`NEIGHBOURS`] guides whose roots are nearest its
//! own at rest, weighted by `w_g ∝ 1 / (|root_f − root_g| + ε)` and normalised. Point `i` of a follower of `n`
//! points is
//!
//! ```text
//! x_f,i = P(r_f,i) + Σ_g w_g · D_g(u),   u = i / (n − 1),
//! D_g(u) = lerp over the guide's points at u · (n_g − 1) of (x_g,j − P(r_g,j))
//! ```
//!
//! where `P` is the root frame's pose at the frame's time and `r` the rest positions: the follower is its rest
//! shape carried rigidly by the head, plus the weighted deviation of its guides from theirs at the same place
//! along the strand. The root's deviation is 0 (guides' roots are pinned), so a follower's root sits exactly on
//! the moving scalp. Guides that bend differently would stretch the blend (69 % at worst in a shake test), so the
//! points are then walked from the root with follow-the-leader (Müller et al. 2012, as the simulation's length
//! pass): `x_i ← x_{i−1} + L_i · (x_i − x_{i−1}) / |x_i − x_{i−1}|`, each segment its rest length `L_i`, and a point
//! that lands inside the collider is moved out (as the simulation's collision step does) and put back on its
//! leader's sphere, up to sixteen rounds, exactly as the simulation's length pass does for the guides.

use super::pose::{COLLISION_ROUNDS, Collider, Pose};
use glam::Vec3;

/// Guides each follower interpolates.
pub const NEIGHBOURS: usize = 3;
/// Added to a root distance before it is inverted (world units).
const EPSILON: f32 = 1e-6;

/// Which strands are simulated, and each follower's guides and weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Follow {
    /// Per strand: whether it is simulated.
    pub simulated: Vec<bool>,
    /// Per follower strand (in strand order): its index and `(guide strand, weight)` pairs.
    pub followers: Vec<(usize, Vec<(usize, f32)>)>,
}

impl Follow {
    /// The split of strands `ranges` (`(first point, count)`) with rest points `rest` for a simulated share
    /// `guides` in `(0, 1]`; strands at or after `swept_from` are always simulated. `None` when every strand is
    /// simulated.
    pub fn new(rest: &[Vec3], ranges: &[(usize, usize)], guides: f32, swept_from: usize) -> Option<Follow> {
        let every = (1.0 / guides).round().max(1.0) as usize;
        if every == 1 {
            return None;
        }
        let simulated: Vec<bool> = (0..ranges.len())
            .map(|s| s % every == 0 || s >= swept_from || ranges[s].1 < 2)
            .collect();
        let guide_roots: Vec<(usize, Vec3)> = (0..ranges.len())
            .filter(|&s| simulated[s] && ranges[s].1 >= 2)
            .map(|s| (s, rest[ranges[s].0]))
            .collect();
        if guide_roots.is_empty() {
            return None;
        }
        let followers = (0..ranges.len())
            .filter(|&s| !simulated[s])
            .map(|s| {
                let root = rest[ranges[s].0];
                let mut near: Vec<(f32, usize)> =
                    guide_roots.iter().map(|&(g, r)| (r.distance(root), g)).collect();
                near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                near.truncate(NEIGHBOURS);
                let inv: Vec<f32> = near.iter().map(|(d, _)| 1.0 / (d + EPSILON)).collect();
                let sum: f32 = inv.iter().sum();
                (
                    s,
                    near.iter().zip(&inv).map(|(&(_, g), w)| (g, w / sum)).collect(),
                )
            })
            .collect();
        Some(Follow { simulated, followers })
    }

    /// Rebuilds every follower's points in `x` from the guides' points in `x`, the rest pose `rest` and the
    /// root frame's pose `pose`, colliding with `head` (in the head's rest frame, posed by `pose`) when given
    /// (see the module docs).
    pub fn interpolate(
        &self,
        x: &mut [Vec3],
        rest: &[Vec3],
        ranges: &[(usize, usize)],
        pose: Pose,
        head: Option<&Collider>,
    ) {
        for (f, guides) in &self.followers {
            let (first, n) = ranges[*f];
            for i in 0..n {
                let u = if n > 1 { i as f32 / (n - 1) as f32 } else { 0.0 };
                let mut d = Vec3::ZERO;
                for &(g, w) in guides {
                    d += deviation(x, rest, ranges[g], pose, u) * w;
                }
                let mut p = pose.apply(rest[first + i]) + d;
                if i > 0 {
                    let lead = x[first + i - 1];
                    let rest_len = (rest[first + i] - rest[first + i - 1]).length();
                    let follow = |to: Vec3| {
                        let (d, len) = (to - lead, (to - lead).length());
                        if len > 0.0 {
                            lead + d * (rest_len / len)
                        } else {
                            lead + (pose.apply(rest[first + i]) - pose.apply(rest[first + i - 1]))
                        }
                    };
                    p = follow(p);
                    if let Some(c) = head {
                        for _ in 0..COLLISION_ROUNDS {
                            let Some(out) = c.push_out(pose.inverse_apply(p)) else {
                                break;
                            };
                            p = follow(pose.apply(out));
                        }
                    }
                }
                x[first + i] = p;
            }
        }
    }
}

/// A guide's deviation from its posed rest shape at parameter `u` along it (linear between its points).
fn deviation(x: &[Vec3], rest: &[Vec3], (first, n): (usize, usize), pose: Pose, u: f32) -> Vec3 {
    let at = u * (n - 1) as f32;
    let j0 = (at.floor() as usize).min(n - 1);
    let j1 = (j0 + 1).min(n - 1);
    let t = at - j0 as f32;
    let dev = |j: usize| x[first + j] - pose.apply(rest[first + j]);
    dev(j0).lerp(dev(j1), t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mth_strand_guides_and_followers_weigh_their_nearest_guides() {
        // Five strands of 3 points, roots on the X axis at 0, 1, 2, 3, 10; guides = 0.5: m = 2, strands 0, 2, 4.
        let roots = [0.0, 1.0, 2.0, 3.0, 10.0];
        let rest: Vec<Vec3> = roots
            .iter()
            .flat_map(|&x| (0..3).map(move |i| Vec3::new(x, -(i as f32), 0.0)))
            .collect();
        let ranges: Vec<(usize, usize)> = (0..5).map(|s| (3 * s, 3)).collect();
        let f = Follow::new(&rest, &ranges, 0.5, 5).unwrap();
        assert_eq!(f.simulated, [true, false, true, false, true]);
        // Strand 1: guides 0 and 2 at distance 1 (weights 1/2 each), guide 4 at 9 (1/9 against 1 and 1).
        let (s, w) = &f.followers[0];
        assert_eq!(*s, 1);
        let total = 1.0 + 1.0 + 1.0 / 9.0;
        let expect = [(0, 1.0 / total), (2, 1.0 / total), (4, (1.0 / 9.0) / total)];
        for ((g, w), (eg, ew)) in w.iter().zip(expect) {
            assert_eq!(*g, eg);
            assert!((w - ew).abs() < 1e-5, "{w} vs {ew}");
        }
        // A swept strand (from 3 on) is simulated whatever m says.
        let f = Follow::new(&rest, &ranges, 0.5, 3).unwrap();
        assert_eq!(f.simulated, [true, false, true, true, true]);
        assert!(Follow::new(&rest, &ranges, 1.0, 5).is_none());
    }

    #[test]
    fn a_follower_is_its_posed_rest_plus_its_guides_deviation() {
        // Two strands of 3 points; guides = 0.5 → strand 0 guides, strand 1 follows it alone.
        let rest = vec![
            Vec3::ZERO,
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, -2.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, -2.0, 0.0),
        ];
        let ranges = [(0, 3), (3, 3)];
        let f = Follow::new(&rest, &ranges, 0.5, 2).unwrap();
        // The guide swings: its middle point by +0.5 in Z, its tip by +1; the pose lifts everything by 2 in Y.
        let pose = Pose {
            translation: Vec3::new(0.0, 2.0, 0.0),
            ..Pose::IDENTITY
        };
        let mut x = vec![
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 1.0, 0.5),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
        ];
        f.interpolate(&mut x, &rest, &ranges, pose, None);
        // Blended: (1, 2, 0), (1, 1, 0.5), (1, 0, 1); then each segment back to length 1 from the root:
        // (1, 2 − 1/√1.25, 0.5/√1.25) = (1, 1.105573, 0.447214), and the tip 1 along (0, −1.105573, 0.552786)
        // from there: (1, 0.211146, 0.894427).
        let expect = [
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(1.0, 1.105573, 0.447214),
            Vec3::new(1.0, 0.211146, 0.894427),
        ];
        for (got, want) in x[3..].iter().zip(expect) {
            assert!((*got - want).length() < 1e-5, "{got} vs {want}");
        }
    }
}
