//! Temporal metrics of a method over a motion (docs/design.md, "Temporal metrics"), defined once here as pure
//! functions of what `measure motion` reads back each frame.
//!
//! A **tracked point** is a hair point followed across frames by its place on its strand: strand point `j`
//! (global point index) has the id `2j`, the midpoint of the segment from point `j` to `j + 1` the id `2j + 1`
//! ([`point_id`], [`midpoint_id`]), so an id names a strand and a parametric position whatever the frame. Frame
//! `f` holds the tracked points the camera sees in that frame, each with the method's visibility `V_m` and the
//! exact reference's `V_ref` ([`TrackedFrame`]). Between consecutive frames `f − 1, f`, over the points tracked
//! in both, the **pop** of a point is
//!
//! ```text
//! pop = |ΔV_m − ΔV_ref|,   ΔV = V(f) − V(f − 1)
//! ```
//!
//! how much more (or less) the method's shadow changed at the point than the truth did.

use crate::visibility::ErrorDistribution;
use image::RgbaImage;

/// A pop larger than this is counted by the pop rate.
pub const POP_THRESHOLD: f64 = 0.1;

/// The tracked-point id of strand point `j` (global point index).
pub fn point_id(j: usize) -> u32 {
    2 * j as u32
}

/// The tracked-point id of the midpoint of the segment from point `j` to point `j + 1`.
pub fn midpoint_id(j: usize) -> u32 {
    2 * j as u32 + 1
}

/// One hair point followed across the frames of a motion by its place on its strand (the time view of the
/// texel inspector, `measure motion --point`): the segment from global strand point `first` to `first + 1`, at
/// parameter `t` in `[0, 1]` along it. The motion keeps the topology, so the place names the same hair in every
/// frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowedPoint {
    pub first: u32,
    pub t: f32,
}

impl FollowedPoint {
    /// The place of `world` on the segment starting at point `first` of `points` (projected onto the segment).
    pub fn on_segment(points: &[glam::Vec3], first: u32, world: glam::Vec3) -> FollowedPoint {
        let (a, b) = (points[first as usize], points[first as usize + 1]);
        let d = b - a;
        let t = if d.length_squared() > 0.0 {
            ((world - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        FollowedPoint { first, t }
    }

    /// `FIRST[:T]`, the global index of the segment's first point and the parameter (0.5 when omitted).
    pub fn parse(text: &str) -> Result<FollowedPoint, String> {
        let (first, t) = text.split_once(':').unwrap_or((text, "0.5"));
        let first = first
            .trim()
            .parse::<u32>()
            .map_err(|_| format!("--point '{text}': expected FIRST[:T] with FIRST a strand point index"))?;
        let t = t.trim().parse::<f32>().ok().filter(|t| (0.0..=1.0).contains(t));
        let t = t.ok_or_else(|| format!("--point '{text}': T must be a number in [0, 1]"))?;
        Ok(FollowedPoint { first, t })
    }

    /// Checks that the point is a segment of `strands` (its first point is not a strand's last).
    pub fn check(&self, strands: &crate::scene::Strands) -> Result<(), String> {
        let first = self.first as usize;
        let on_segment = strands
            .ranges()
            .any(|(start, n)| (start..(start + n).saturating_sub(1)).contains(&first));
        if on_segment {
            Ok(())
        } else {
            Err(format!(
                "point {first}: not the first point of a segment (the scene has {} strand points in {} strands)",
                strands.point_count(),
                strands.strand_count()
            ))
        }
    }

    /// The point in a frame's strand points.
    pub fn at(&self, points: &[glam::Vec3]) -> glam::Vec3 {
        let i = self.first as usize;
        points[i].lerp(points[i + 1], self.t)
    }

    /// `(strand, s)`: the strand holding the point and its parametric position along it in `[0, 1]` (root 0).
    pub fn on_strand(&self, strands: &crate::scene::Strands) -> Option<(usize, f32)> {
        let first = self.first as usize;
        strands.ranges().enumerate().find_map(|(k, (start, n))| {
            (start..(start + n).saturating_sub(1))
                .contains(&first)
                .then(|| (k, ((first - start) as f32 + self.t) / (n - 1) as f32))
        })
    }

    pub fn label(&self) -> String {
        format!("{}:{}", self.first, self.t)
    }
}

/// The pop of one point between two frames, `|ΔV_m − ΔV_ref|`: the method's change in visibility less the
/// reference's, from `(method, reference)` before to after. The one definition every pop figure uses.
pub fn pop(before: (f32, f32), after: (f32, f32)) -> f64 {
    let dm = f64::from(after.0) - f64::from(before.0);
    let dr = f64::from(after.1) - f64::from(before.1);
    (dm - dr).abs()
}

/// One followed point's visibility over the frames: the reference's, a method's, and the method's pops
/// (frame `f` ≥ 1 and `|ΔV_m − ΔV_ref|` from frame `f − 1`, where it exceeds [`POP_THRESHOLD`]).
pub fn followed_pops(method: &[f32], reference: &[f32]) -> Vec<(usize, f64)> {
    (1..method.len().min(reference.len()))
        .filter_map(|f| {
            let p = pop((method[f - 1], reference[f - 1]), (method[f], reference[f]));
            (p > POP_THRESHOLD).then_some((f, p))
        })
        .collect()
}

/// One frame's tracked points: ids ascending, with the method's and the reference's visibility at each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackedFrame {
    pub ids: Vec<u32>,
    pub method: Vec<f32>,
    pub reference: Vec<f32>,
}

/// The **shading error** of one frame: `(1/n) Σ |V_m − V_ref|` over its `n` tracked points (0 when none).
pub fn shading_error(frame: &TrackedFrame) -> f64 {
    if frame.ids.is_empty() {
        return 0.0;
    }
    frame
        .method
        .iter()
        .zip(&frame.reference)
        .map(|(m, r)| (m - r).abs() as f64)
        .sum::<f64>()
        / frame.ids.len() as f64
}

/// How a per-frame error spreads over the frames: the mean, the 95th percentile by nearest rank (as
/// [`ErrorDistribution`]: the `ceil(0.95 n)`-th smallest), the worst value and the first frame that has it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OverFrames {
    pub mean: f64,
    pub p95: f64,
    pub worst: f64,
    pub worst_frame: usize,
}

impl OverFrames {
    /// Over `per_frame[f]`, frame `f`'s error (all zero when empty).
    pub fn of(per_frame: &[f64]) -> OverFrames {
        if per_frame.is_empty() {
            return OverFrames::default();
        }
        let d = ErrorDistribution::of(per_frame);
        let worst_frame = per_frame
            .iter()
            .position(|&v| v == d.worst || (v.is_nan() && d.worst.is_infinite()))
            .unwrap_or(0);
        OverFrames {
            mean: per_frame.iter().sum::<f64>() / per_frame.len() as f64,
            p95: d.p95,
            worst: d.worst,
            worst_frame,
        }
    }
}

/// The pops `|ΔV_m − ΔV_ref|` from frame `a` to frame `b` at the points tracked in both, in id order.
pub fn pops(a: &TrackedFrame, b: &TrackedFrame) -> Vec<f64> {
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::new();
    while i < a.ids.len() && j < b.ids.len() {
        match a.ids[i].cmp(&b.ids[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                out.push(pop((a.method[i], a.reference[i]), (b.method[j], b.reference[j])));
                i += 1;
                j += 1;
            }
        }
    }
    out
}

/// The flicker figures of one frame pair, or pooled over a motion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Flicker {
    /// Pops counted (points tracked in both frames of each pair, summed over the pairs).
    pub points: usize,
    /// **flicker**: the mean pop over every (pair, point).
    pub mean: f64,
    /// **flicker p99**: the 99th percentile by nearest rank of the pops over every (pair, point).
    pub p99: f64,
    /// **pop rate**: the mean over the frame pairs of the share of the pair's tracked points whose pop exceeds
    /// [`POP_THRESHOLD`] (strictly); a pair without common points counts as 0.
    pub pop_rate: f64,
    /// **max pop**: the largest pop.
    pub max_pop: f64,
}

impl Flicker {
    /// The pops of each frame pair (`per_pair[p]`: the pair's pops, from [`pops`]) pooled as above.
    pub fn of(per_pair: &[Vec<f64>]) -> Flicker {
        let all: Vec<f64> = per_pair.iter().flatten().copied().collect();
        if all.is_empty() {
            return Flicker::default();
        }
        let share = |p: &Vec<f64>| {
            if p.is_empty() {
                0.0
            } else {
                p.iter().filter(|&&d| d > POP_THRESHOLD).count() as f64 / p.len() as f64
            }
        };
        let d = ErrorDistribution::of(&all);
        Flicker {
            points: all.len(),
            mean: all.iter().sum::<f64>() / all.len() as f64,
            p99: d.p99,
            pop_rate: per_pair.iter().map(share).sum::<f64>() / per_pair.len() as f64,
            max_pop: d.worst,
        }
    }

    /// Over the frames in order: the pops of each consecutive pair.
    pub fn over(frames: &[TrackedFrame]) -> Flicker {
        Flicker::of(&frames.windows(2).map(|w| pops(&w[0], &w[1])).collect::<Vec<_>>())
    }
}

/// Sum of squared differences, over the RGB channels in `[0, 1]` of every pixel, of the frame-to-frame change
/// of the method's image (`m0 → m1`) and the reference's (`r0 → r1`), and the channel count: the terms of
/// [`image_flicker`]. The images must share one size.
fn image_change_error(m0: &RgbaImage, m1: &RgbaImage, r0: &RgbaImage, r1: &RgbaImage) -> (f64, usize) {
    let mut sum = 0.0;
    let mut n = 0;
    for (((a0, a1), b0), b1) in m0.pixels().zip(m1.pixels()).zip(r0.pixels()).zip(r1.pixels()) {
        for c in 0..3 {
            let dm = (f64::from(a1[c]) - f64::from(a0[c])) / 255.0;
            let dr = (f64::from(b1[c]) - f64::from(b0[c])) / 255.0;
            sum += (dm - dr) * (dm - dr);
            n += 1;
        }
    }
    (sum, n)
}

/// **Image flicker**: the RMSE of the frame-to-frame change of the method's image against the reference's,
/// `sqrt(Σ (ΔI_m − ΔI_ref)² / (3 · pixels · pairs))` over the RGB channels in `[0, 1]` of every pixel and
/// every consecutive pair of frames (`ΔI = I(f) − I(f − 1)`, sRGB values as stored). 0 with fewer than two frames.
pub fn image_flicker(method: &[RgbaImage], reference: &[RgbaImage]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (m, r) in method.windows(2).zip(reference.windows(2)) {
        let (s, k) = image_change_error(&m[0], &m[1], &r[0], &r[1]);
        sum += s;
        n += k;
    }
    if n == 0 { 0.0 } else { (sum / n as f64).sqrt() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(ids: &[u32], method: &[f32], reference: &[f32]) -> TrackedFrame {
        TrackedFrame {
            ids: ids.to_vec(),
            method: method.to_vec(),
            reference: reference.to_vec(),
        }
    }

    #[test]
    fn a_followed_point_is_a_place_on_its_strand() {
        use glam::Vec3;
        // Two strands: points 0..3 (3 segments) and 3..5 (1 segment).
        let strands = crate::scene::Strands {
            points: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(3.0, 0.0, 0.0),
                Vec3::Y,
                Vec3::new(0.0, 3.0, 0.0),
            ],
            counts: vec![4, 2],
            thickness: None,
            alpha: None,
            color: None,
        };
        let p = FollowedPoint::on_segment(&strands.points, 1, Vec3::new(1.25, 0.5, 0.0));
        assert_eq!(p, FollowedPoint { first: 1, t: 0.25 });
        assert_eq!(p.at(&strands.points), Vec3::new(1.25, 0.0, 0.0));
        // Segment 1 of 3 at a quarter: (1 + 0.25) / 3 along strand 0.
        assert_eq!(p.on_strand(&strands), Some((0, 1.25 / 3.0)));
        let q = FollowedPoint { first: 4, t: 0.5 };
        assert_eq!(q.on_strand(&strands), Some((1, 0.5)));
        assert_eq!(q.at(&strands.points), Vec3::new(0.0, 2.0, 0.0));
        // A strand's last point starts no segment.
        assert!(FollowedPoint { first: 3, t: 0.0 }.check(&strands).is_err());
        assert!(FollowedPoint { first: 5, t: 0.0 }.check(&strands).is_err());
        assert!(q.check(&strands).is_ok());
        assert_eq!(
            FollowedPoint::parse("7:0.75"),
            Ok(FollowedPoint { first: 7, t: 0.75 })
        );
        assert_eq!(FollowedPoint::parse("7"), Ok(FollowedPoint { first: 7, t: 0.5 }));
        assert!(FollowedPoint::parse("7:1.5").unwrap_err().contains("[0, 1]"));
        assert!(FollowedPoint::parse("x").unwrap_err().contains("FIRST[:T]"));
    }

    #[test]
    fn followed_pops_are_the_frames_where_the_method_changes_unlike_the_truth() {
        // Reference 1, 0.9, 0.9, 0.5; method 1, 0.6, 0.9, 0.5: |−0.4 + 0.1| = 0.3 at frame 1, |0.3 − 0| = 0.3 at
        // frame 2, |−0.4 + 0.4| = 0 at frame 3.
        let pops = followed_pops(&[1.0, 0.6, 0.9, 0.5], &[1.0, 0.9, 0.9, 0.5]);
        assert_eq!(pops.len(), 2);
        assert_eq!((pops[0].0, pops[1].0), (1, 2));
        assert!(
            (pops[0].1 - 0.3).abs() < 1e-6 && (pops[1].1 - 0.3).abs() < 1e-6,
            "{pops:?}"
        );
    }

    #[test]
    fn ids_name_points_and_midpoints_apart() {
        assert_eq!(
            [point_id(0), midpoint_id(0), point_id(1), midpoint_id(7)],
            [0, 1, 2, 15]
        );
    }

    #[test]
    fn shading_error_is_the_mean_absolute_difference() {
        // |0.5-0.25| + |1-1| + |0-0.5| = 0.75 over 3 points.
        let f = frame(&[0, 1, 4], &[0.5, 1.0, 0.0], &[0.25, 1.0, 0.5]);
        assert_eq!(shading_error(&f), 0.25);
        assert_eq!(shading_error(&TrackedFrame::default()), 0.0);
    }

    #[test]
    fn over_frames_gives_mean_nearest_rank_p95_and_the_first_worst_frame() {
        // 20 frames 0.0, 0.1, ..., 1.9 with frame 7 raised to 5: mean (sum 0..19 · 0.1 − 0.7 + 5) / 20 =
        // (19 + 4.3) / 20 = 1.165; p95 = the 19th smallest of 20 = 1.9 (the sorted values are 0.0..1.9 without
        // 0.7, then 5).
        let mut v: Vec<f64> = (0..20).map(|i| i as f64 / 10.0).collect();
        v[7] = 5.0;
        let o = OverFrames::of(&v);
        assert!((o.mean - 1.165).abs() < 1e-12, "{o:?}");
        assert_eq!((o.p95, o.worst, o.worst_frame), (1.9, 5.0, 7));
        // Ties: the first frame with the worst value.
        let o = OverFrames::of(&[0.1, 0.3, 0.2, 0.3]);
        assert_eq!((o.worst, o.worst_frame), (0.3, 1));
        assert_eq!(OverFrames::of(&[]), OverFrames::default());
    }

    #[test]
    fn pops_compare_the_changes_at_points_tracked_in_both_frames() {
        // Point 2 leaves the view and point 6 enters: pops at 0 and 4 only.
        // id 0: method 0.5 -> 0.9 (Δ 0.4), reference 0.5 -> 0.6 (Δ 0.1): pop 0.3.
        // id 4: method 1.0 -> 0.5 (Δ −0.5), reference 1.0 -> 0.75 (Δ −0.25): pop 0.25.
        let a = frame(&[0, 2, 4], &[0.5, 0.2, 1.0], &[0.5, 0.2, 1.0]);
        let b = frame(&[0, 4, 6], &[0.9, 0.5, 0.0], &[0.6, 0.75, 1.0]);
        let p = pops(&a, &b);
        assert_eq!(p.len(), 2);
        assert!((p[0] - 0.3).abs() < 1e-6 && (p[1] - 0.25).abs() < 1e-6, "{p:?}");
        // A method that changes exactly as the reference does never pops, however wrong it is.
        let c = frame(&[0, 4], &[0.0, 0.0], &[0.5, 0.5]);
        let d = frame(&[0, 4], &[0.25, 0.0], &[0.75, 0.5]);
        assert_eq!(pops(&c, &d), vec![0.0, 0.0]);
    }

    #[test]
    fn flicker_pools_the_pops_and_the_pop_rate_averages_the_pairs() {
        // Pair 1: pops 0.0, 0.2, 0.05, 0.15 (2 of 4 above 0.1: share 0.5); pair 2: pop 0.5 (share 1).
        // mean = 0.9 / 5 = 0.18; p99 = the ceil(4.95) = 5th smallest = 0.5 = the max; pop rate (0.5 + 1) / 2.
        let f = Flicker::of(&[vec![0.0, 0.2, 0.05, 0.15], vec![0.5]]);
        assert_eq!(f.points, 5);
        assert!((f.mean - 0.18).abs() < 1e-12, "{f:?}");
        assert_eq!((f.p99, f.max_pop, f.pop_rate), (0.5, 0.5, 0.75));
        // Exactly 0.1 is not a pop; a pair with no common point counts as share 0.
        let f = Flicker::of(&[vec![0.1, 0.1], vec![]]);
        assert_eq!(f.pop_rate, 0.0);
        assert_eq!(Flicker::of(&[]), Flicker::default());
        // 100 pops 0.01, 0.02, ..., 1.00: p99 is the 99th smallest, 0.99.
        let f = Flicker::of(&[(1..=100).map(|i| i as f64 / 100.0).collect()]);
        assert_eq!(f.p99, 0.99);
        assert_eq!(f.pop_rate, 0.9);
    }

    #[test]
    fn flicker_over_frames_takes_consecutive_pairs() {
        // Frames 0 -> 1: pop |0.5 − 0| = 0.5; 1 -> 2: pop |0 − 0.25| = 0.25. Mean 0.375.
        let frames = [
            frame(&[3], &[0.0], &[0.0]),
            frame(&[3], &[0.5], &[0.0]),
            frame(&[3], &[0.5], &[0.25]),
        ];
        let f = Flicker::over(&frames);
        assert_eq!((f.points, f.mean, f.max_pop, f.pop_rate), (2, 0.375, 0.5, 1.0));
    }

    fn grey(w: u32, values: &[u8]) -> RgbaImage {
        let bytes: Vec<u8> = values.iter().flat_map(|&v| [v, v, v, 255]).collect();
        RgbaImage::from_raw(w, values.len() as u32 / w, bytes).unwrap()
    }

    #[test]
    fn image_flicker_is_the_rmse_of_the_change_against_the_reference_change() {
        // Two pixels, grey. Method 0 -> 51 and 0 -> 0; reference 0 -> 0 and 0 -> 0: the change differs by
        // 51/255 = 0.2 on one pixel's 3 channels: sqrt(3 · 0.04 / 6) = sqrt(0.02).
        let m = [grey(2, &[0, 0]), grey(2, &[51, 0])];
        let r = [grey(2, &[0, 0]), grey(2, &[0, 0])];
        assert!((image_flicker(&m, &r) - 0.02f64.sqrt()).abs() < 1e-12);
        // A method wrong by a constant offset changes as the reference does: no image flicker.
        let m = [grey(2, &[10, 200]), grey(2, &[30, 200])];
        let r = [grey(2, &[0, 100]), grey(2, &[20, 100])];
        assert_eq!(image_flicker(&m, &r), 0.0);
        // Pooled over pairs: pair 1 as the first case (sum 0.12 over 6), pair 2 no change (0 over 6):
        // sqrt(0.12 / 12) = 0.1.
        let m = [grey(2, &[0, 0]), grey(2, &[51, 0]), grey(2, &[51, 0])];
        let r = [grey(2, &[0, 0]), grey(2, &[0, 0]), grey(2, &[0, 0])];
        assert!((image_flicker(&m, &r) - 0.1).abs() < 1e-12);
        assert_eq!(image_flicker(&m[..1], &r[..1]), 0.0);
    }
}
