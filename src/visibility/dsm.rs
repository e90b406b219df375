//! Compressed deep shadow maps: Lokovic & Veach, "Deep Shadow Maps" (SIGGRAPH 2000), §4 (compression). Each texel
//! keeps a piecewise-linear visibility function whose vertex count the greedy compressor decides, within an error
//! tolerance `epsilon` of the exact visibility at every depth.
//!
//! Input: the texel's exact step function `V_ref(z) = exp(-sum of b over fragments with depth < z)` (see
//! [`steps`]: distinct depths `d_1 < ... < d_m`, `V_i` the visibility just behind `d_i`, `V_0 = 1`). It is
//! left-continuous: `V_ref(d_i) = V_{i-1}`, `V_ref` on `(d_i, d_{i+1}]` is `V_i`.
//!
//! Compression (the paper's greedy "target window" algorithm): from the current origin vertex `(z_o, v_o)`, keep
//! the interval `[lo, hi]` of slopes whose line stays within `±epsilon` of every constraint point offered so far;
//! a point `(z, v)` with `z > z_o` narrows it to `[max(lo, (v - eps - v_o) / dz), min(hi, (v + eps - v_o) / dz)]`.
//! When the window would become empty, the segment ends at the last accepted depth with the slope
//! `min(0.5 (lo + hi), max(lo, 0))` (the window's midpoint, made non-increasing), that end is the next origin
//! and the point is offered again. The constraint points are the ends of each constant piece of `V_ref`:
//! `(d_i, V_{i-1})` and `(d_i, V_i)` per depth; since the output is linear inside each piece, checking the ends
//! bounds the error over the whole piece. A point at the origin's own depth (`z == z_o`, only `(d_i, V_i)` at a
//! step) is a constraint on `v_o`: when `|V_i - v_o| > epsilon` a second vertex `(d_i, V_i)` is emitted at the
//! same depth — a vertical step (the paper's discontinuities). Each distinct depth gets at most two vertices,
//! so a texel of `n` fragments has at most `2n`.
//!
//! Lookup (vertices `(z_k, v_k)`, `z` non-decreasing, `v` non-increasing): `V = v_0` for `z <= z_0`,
//! `v_last` for `z > z_last`, otherwise on the segment `z_{k-1} < z <= z_k` (the first `k` with `z_k >= z`, so
//! a vertical pair at `d` answers the upper vertex at `d` itself and the lower one just behind it, like the
//! reference's strict `<`): `max(max(v_{k-1} + (v_k - v_{k-1}) * ((z - z_{k-1}) / (z_k - z_{k-1})), v_k), 0)`.
//! The caps keep `V` non-increasing and in `[0, 1]` under f32 rounding and never move it away from `V_ref`.
//! Then `|V - V_ref| <= epsilon` at every depth, up to f32 rounding; `epsilon = 0` gives `V_ref` exactly (the
//! f32 cumulative sums: two vertices per distinct depth, flat segments).
//!
//! Every quantity is f32 and computed by the same expressions, in the same order, in `shaders/dsm.wgsl` (the
//! compressor) and `shaders/methods/dsm.wgsl` (the lookup); optical depths at one depth are summed in the
//! order the fragments come (a stable sort by depth here, of lists the reference sorts by (depth, segment); the
//! GPU walks its lists in (depth, segment) order), then added to the running sum.

use super::{Fragment, Model, Stored, TexelModel, optical_depth, transmittance, valid};

/// Compressed deep shadow map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DsmParams {
    /// Error tolerance `epsilon` in visibility, `>= 0`.
    pub epsilon: f32,
}

impl Default for DsmParams {
    /// `epsilon = 0.01`.
    fn default() -> Self {
        Self { epsilon: 0.01 }
    }
}

/// A texel: its vertices `[z, V]`, in depth order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DsmTexel {
    pub vertices: Vec<[f32; 2]>,
}

/// The exact step function of a texel: `(d_i, V_i)` per distinct finite depth, ascending, with `V_i` the
/// visibility just behind `d_i` (f32 sums: the optical depths at `d_i` summed, then added to the running sum).
pub fn steps(fragments: &[Fragment]) -> Vec<(f32, f32)> {
    let mut sorted: Vec<(f32, f32)> = valid(fragments)
        .map(|f| (f.depth, optical_depth(f.alpha)))
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f32, f32)> = Vec::new();
    let mut omega = 0.0f32;
    let mut i = 0;
    while i < sorted.len() {
        let d = sorted[i].0;
        let mut sum = 0.0f32;
        while i < sorted.len() && sorted[i].0 == d {
            sum += sorted[i].1;
            i += 1;
        }
        omega += sum;
        out.push((d, transmittance(omega)));
    }
    out
}

/// The greedy compressor's state (one segment in progress).
struct Greedy {
    epsilon: f32,
    origin: [f32; 2],
    /// `(lo, hi, last accepted depth)` once a point behind the origin was accepted.
    window: Option<(f32, f32, f32)>,
    vertices: Vec<[f32; 2]>,
}

impl Greedy {
    fn new(epsilon: f32, first: [f32; 2]) -> Greedy {
        Greedy {
            epsilon,
            origin: first,
            window: None,
            vertices: vec![first],
        }
    }

    /// Ends the open segment at its last accepted depth (the next origin).
    fn close(&mut self, lo: f32, hi: f32, last: f32) {
        let [zo, vo] = self.origin;
        let slope = (0.5 * (lo + hi)).min(lo.max(0.0));
        let v = (vo + slope * (last - zo)).min(vo);
        self.origin = [last, v];
        self.vertices.push(self.origin);
        self.window = None;
    }

    /// Offers the constraint point `(z, v)`, `z` at or behind the origin.
    fn offer(&mut self, z: f32, v: f32) {
        let eps = self.epsilon;
        loop {
            let [zo, vo] = self.origin;
            if z > zo {
                let dz = z - zo;
                let a = (v - eps - vo) / dz;
                let b = (v + eps - vo) / dz;
                match self.window {
                    None => self.window = Some((a, b, z)),
                    Some((lo, hi, last)) => {
                        let (lo2, hi2) = (lo.max(a), hi.min(b));
                        if lo2 <= hi2 {
                            self.window = Some((lo2, hi2, z));
                        } else {
                            self.close(lo, hi, last);
                            continue;
                        }
                    }
                }
                return;
            }
            if (v - vo).abs() > eps {
                self.origin = [zo, v.min(vo)];
                self.vertices.push(self.origin);
            }
            return;
        }
    }

    fn finish(mut self) -> Vec<[f32; 2]> {
        if let Some((lo, hi, last)) = self.window {
            self.close(lo, hi, last);
        }
        self.vertices
    }
}

/// The compressed vertices of the step function `steps` (see the module doc).
pub fn compress(steps: &[(f32, f32)], epsilon: f32) -> Vec<[f32; 2]> {
    let Some(&(d1, v1)) = steps.first() else {
        return Vec::new();
    };
    let mut g = Greedy::new(epsilon, [d1, 1.0]);
    g.offer(d1, v1);
    for w in steps.windows(2) {
        let ((_, before), (d, after)) = (w[0], w[1]);
        g.offer(d, before);
        g.offer(d, after);
    }
    g.finish()
}

/// `V(z)` of a texel's vertices (see the module doc); 1 with no vertex.
pub fn visibility(vertices: &[[f32; 2]], z: f32) -> f32 {
    let Some(last) = vertices.last() else {
        return 1.0;
    };
    let k = vertices.partition_point(|p| p[0] < z);
    if k == 0 {
        return vertices[0][1];
    }
    if k == vertices.len() {
        return last[1].max(0.0);
    }
    let ([z0, v0], [z1, v1]) = (vertices[k - 1], vertices[k]);
    (v0 + (v1 - v0) * ((z - z0) / (z1 - z0))).max(v1).max(0.0)
}

impl Model for DsmParams {
    type Texel = DsmTexel;

    fn build(&self, fragments: &[Fragment]) -> DsmTexel {
        DsmTexel {
            vertices: compress(&steps(fragments), self.epsilon),
        }
    }

    fn visibility(&self, texel: &DsmTexel, z: f32) -> f32 {
        visibility(&texel.vertices, z)
    }
}

impl TexelModel for DsmParams {
    fn label(&self) -> String {
        format!("dsm ε{}", self.epsilon)
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    /// The vertex count.
    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        vec![self.build(fragments).vertices.len() as f32]
    }

    /// The vertices as knots.
    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = self.build(fragments);
        let mut s = Stored::new(self.label());
        s.knots = t.vertices.iter().map(|&[z, v]| [z, v.max(0.0)]).collect();
        s.summary.push(format!(
            "{} vertices for {} distinct depths (ε = {})",
            t.vertices.len(),
            steps(fragments).len(),
            self.epsilon
        ));
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::reference;
    use crate::visibility::test_support::{
        Rng, assert_valid_curve, extreme_texels, probe_depths, random_texel,
    };

    /// f32 rounding allowed on top of epsilon (cumulative sums, slopes and interpolation in f32 against the
    /// reference's f64); measured: 6.0e-8 at epsilon 0, 0 for the others (printed by
    /// `error_is_within_epsilon_everywhere`).
    const ROUNDING: f32 = 1e-6;

    fn p(epsilon: f32) -> DsmParams {
        DsmParams { epsilon }
    }

    #[test]
    fn hand_computed_exact_steps() {
        // Alpha 0.5 at 0.2 and 0.75 at 0.6: V = 1, 1/2 behind 0.2, 1/8 behind 0.6.
        let f = [Fragment::new(0.6, 0.75), Fragment::new(0.2, 0.5)];
        let s = steps(&f);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].0, s[1].0), (0.2, 0.6));
        assert!((s[0].1 - 0.5).abs() < 1e-7 && (s[1].1 - 0.125).abs() < 1e-7);
        // epsilon 0: two vertices per depth, vertical steps, flat in between.
        let t = p(0.0).build(&f);
        let zs: Vec<f32> = t.vertices.iter().map(|v| v[0]).collect();
        assert_eq!(zs, [0.2, 0.2, 0.6, 0.6]);
        let vs: Vec<f32> = t.vertices.iter().map(|v| v[1]).collect();
        assert_eq!(vs, [1.0, s[0].1, s[0].1, s[1].1]);
        for (z, v) in [
            (0.0, 1.0),
            (0.2, 1.0),
            (0.3, s[0].1),
            (0.6, s[0].1),
            (0.61, s[1].1),
            (2.0, s[1].1),
        ] {
            assert_eq!(p(0.0).visibility(&t, z), v, "z = {z}");
        }
        assert_eq!(p(0.0).visibility(&t, 0.2f32.next_up()), s[0].1);
    }

    #[test]
    fn hand_computed_merge_within_epsilon() {
        // Three fragments of alpha 0.01 at 0.1, 0.2, 0.3: steps of about 0.01. With epsilon 0.05 one segment
        // from (0.1, 1) spans all of them; the window's midpoint ends it at 0.3.
        let f = [0.1, 0.2, 0.3].map(|d| Fragment::new(d, 0.01));
        let t = p(0.05).build(&f);
        assert_eq!(t.vertices.len(), 2, "{:?}", t.vertices);
        assert_eq!(t.vertices[0], [0.1, 1.0]);
        assert_eq!(t.vertices[1][0], 0.3);
        // A step of 0.5 is above 2 epsilon: it stays vertical.
        let t = p(0.05).build(&[Fragment::new(0.4, 0.5)]);
        assert_eq!(t.vertices.len(), 2);
        assert_eq!((t.vertices[0], t.vertices[1][0]), ([0.4, 1.0], 0.4));
        assert!((t.vertices[1][1] - 0.5).abs() < 1e-7);
        // ... and one of 0.08 is not: a single vertex at 1 within 0.05 of both sides would need |1 - 0.92| <= 0.05,
        // so it is vertical too; with epsilon 0.1 it is not.
        assert_eq!(p(0.05).build(&[Fragment::new(0.4, 0.08)]).vertices.len(), 2);
        assert_eq!(p(0.1).build(&[Fragment::new(0.4, 0.08)]).vertices, [[0.4, 1.0]]);
        assert!(p(0.1).build(&[]).vertices.is_empty());
        assert_eq!(p(0.1).curve(&[], &[0.0, 1.0]), [1.0, 1.0]);
    }

    /// `|V - V_ref| <= epsilon` at every fragment depth, just before and after each and a fine grid, for random
    /// and extreme texels and every epsilon of the sweep.
    #[test]
    fn error_is_within_epsilon_everywhere() {
        let mut rng = Rng::new(77);
        let mut texels = extreme_texels();
        texels.extend((0..400).map(|_| random_texel(&mut rng, 120)));
        for eps in [0.0, 0.01, 0.05, 0.1, 0.5] {
            let mut worst = 0.0f32;
            for f in &texels {
                let zs = probe_depths(f);
                let t = p(eps).build(f);
                assert!(t.vertices.len() <= 2 * f.len(), "{} vertices", t.vertices.len());
                for &z in &zs {
                    let d = (p(eps).visibility(&t, z) - reference::visibility(f, z)).abs();
                    worst = worst.max(d - eps);
                    assert!(d <= eps + ROUNDING, "ε {eps}: |ΔV| {d} at z {z}; fragments {f:?}");
                }
            }
            eprintln!("dsm ε {eps}: max |ΔV| - ε = {worst:.3e}");
        }
    }

    #[test]
    fn curves_are_valid_and_vertices_fall_with_epsilon() {
        let mut rng = Rng::new(78);
        let texels: Vec<_> = (0..200).map(|_| random_texel(&mut rng, 80)).collect();
        let mut counts = Vec::new();
        for eps in [0.0, 0.01, 0.05, 0.1] {
            for f in extreme_texels().iter().chain(&texels) {
                assert_valid_curve(&p(eps), f, "dsm");
            }
            counts.push(
                texels
                    .iter()
                    .map(|f| p(eps).build(f).vertices.len())
                    .sum::<usize>(),
            );
        }
        assert!(counts.windows(2).all(|w| w[1] <= w[0]), "{counts:?}");
        assert!(counts[3] < counts[0], "{counts:?}");
    }

    #[test]
    fn stored_knots_are_the_vertices() {
        let f = [Fragment::new(0.6, 0.75), Fragment::new(0.2, 0.5)];
        let s = p(0.0).stored(&f).unwrap();
        assert_eq!(s.knots.len(), 4);
        assert_eq!(s.summary[0], "4 vertices for 2 distinct depths (ε = 0)");
        assert_eq!(p(0.0).stored_values(&f), [4.0]);
    }
}
