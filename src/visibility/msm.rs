//! Moment shadow maps for translucent occluders: Peters & Klein, "Moment Shadow Mapping" (I3D 2015, the
//! Hamburger 4MSM bound); Münstermann, Krumpen, Klein & Peters, "Moment-Based Order-Independent Transparency"
//! (I3D 2018, MBOIT: the zeroth moment and 4 or 6 power moments of the absorbance); Peters, Münstermann,
//! Wetzstein & Klein, "Improved Moment Shadow Maps for Translucent Occluders, Soft Shadows and Single
//! Scattering" (JCGT 2017).
//!
//! Per texel, one additive pass stores `b_0 = Σ b` (`b = -ln(1 - alpha)`) and `b_j = Σ b·x^j`, `j = 1..n`
//! (`n` = 4 or 6), with `x = 2z - 1`: the light depth `z ∈ [0, 1]` mapped to MBOIT's interval `[-1, 1]` over
//! the strands' whole fitted light range (no per-texel range, so the pass needs no light-depth map). Storage
//! is f32 (RGBA32F), so MBOIT's 16-bit quantisation transform is not needed.
//!
//! Lookup at `z`: normalise `m_j = b_j / b_0`, bias toward MBOIT's known-good vector `m' = m (1 - β) + v β`
//! (`v` = (0, 0.375, 0, 0.375) for 4 moments, (0, 0.48, 0, 0.451, 0, 0.45) for 6: MBOIT's f32 vectors); solve
//! the Hankel system `B c = (1, x, x², …)` by an LDLᵀ (Cholesky) factorisation; the roots of `Σ c_k t^k` are
//! the other support points of the canonical representation with a point at `x`; the fraction of absorbance
//! in front of `x` is the integral of the polynomial interpolating 1 at support points before `x`, 0 behind
//! and the overestimation weight `w` at `x` itself (`w` = 0: the lower bound, 1: the upper bound, MBOIT's
//! 0.25 by default). `V = exp(-b_0 · clamp(fraction, 0, 1))`, so `exp(-b_0) <= V <= 1` always; the total
//! optical depth `b_0` is exact, and `V` reaches `exp(-b_0)` far behind the fragments (the bound is over the
//! whole real line, so not right behind the last one). A non-finite fraction (a support point that rounded onto
//! `x`, e.g. a fragment queried at its own depth) is taken again [`NUDGE`] behind `x`; if it is still not
//! finite (a system singular in f32), all absorbance counts at the mean `m_1` ([`one_point`]). An empty texel
//! (`b_0 = 0`) is lit.
//!
//! Defaults (MBOIT's supplementary document, for single-precision moments): β = 5e-7 with 4 moments, 5e-6
//! with 6; `w` = 0.25. The system is ill-conditioned: β trades bias for stability in f32.
//!
//! GPU contract: `shaders/msm.wgsl` and `shaders/methods/msm.wgsl` compute exactly these f32 expressions in
//! this order: `fma` exactly where MBOIT uses it, in the Hankel factorisation (`mul_add` here), nowhere else,
//! and no `mix` (the explicit products and sums written here). Map layout: layer 0 =
//! `(b_0, b_1, b_2, b_3)`, layer 1 = `(b_4, b_5, b_6, 0)` (`b_5 = b_6 = 0` with 4 moments).

use super::{Fragment, Model, Stored, TexelModel, depth_range, transmittance, valid};

/// MBOIT's single-precision bias vector for 4 power moments (`m_1..m_4`).
pub const BIAS_VECTOR_4: [f32; 4] = [0.0, 0.375, 0.0, 0.375];
/// MBOIT's single-precision bias vector for 6 power moments (`m_1..m_6`).
pub const BIAS_VECTOR_6: [f32; 6] = [0.0, 0.48, 0.0, 0.451, 0.0, 0.45];
/// MBOIT's moment bias β for 4 single-precision power moments.
pub const DEFAULT_BIAS_4: f32 = 5e-7;
/// MBOIT's moment bias β for 6 single-precision power moments.
pub const DEFAULT_BIAS_6: f32 = 5e-6;
/// MBOIT's overestimation weight (0 = lower bound, 1 = upper bound).
pub const DEFAULT_OVERESTIMATION: f32 = 0.25;
/// How far behind `x` a query is repeated when the bound is not finite at `x` (a support point that rounded
/// onto `x`): 2^-20 in `x`, 4.8e-7 in light depth.
pub const NUDGE: f32 = 1.0 / 1_048_576.0;
/// `sqrt(3) / 2`, in the trigonometric cubic solve.
const HALF_SQRT_3: f32 = 0.866_025_4;

/// Moment shadow map parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MsmParams {
    /// Power moments beyond `b_0`: 4 or 6 (any other value counts as 4).
    pub moments: u32,
    /// Moment bias β toward the bias vector, in `[0, 1)`.
    pub bias: f32,
    /// Weight of the support point at the queried depth, in `[0, 1]`.
    pub overestimation: f32,
}

impl Default for MsmParams {
    /// MBOIT's single-precision 4-moment setting.
    fn default() -> Self {
        Self {
            moments: 4,
            bias: DEFAULT_BIAS_4,
            overestimation: DEFAULT_OVERESTIMATION,
        }
    }
}

impl MsmParams {
    /// 4 or 6.
    pub fn moment_count(&self) -> usize {
        if self.moments == 6 { 6 } else { 4 }
    }
}

/// One texel: `b[0] = Σ b`, `b[j] = Σ b·x^j` (`j = 1..=6`; entries beyond the moment count are 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MsmTexel {
    pub b: [f32; 7],
}

/// Maps a light depth in `[0, 1]` to MBOIT's `[-1, 1]`: `z * 2 - 1`. GPU: the same expression.
pub fn warp(z: f32) -> f32 {
    z * 2.0 - 1.0
}

/// `(x, x², …, x⁶)` as the light pass computes them: `x2 = x·x`, `x3 = x2·x`, `x4 = x2·x2`, `x5 = x4·x`,
/// `x6 = x4·x2`.
pub fn powers(x: f32) -> [f32; 6] {
    let x2 = x * x;
    let x4 = x2 * x2;
    [x, x2, x2 * x, x4, x4 * x, x4 * x2]
}

/// Builds a texel: each fragment adds `b` and `b·x^j` (`b·power`, the power first).
pub fn build(params: &MsmParams, fragments: &[Fragment]) -> MsmTexel {
    let n = params.moment_count();
    let mut t = MsmTexel::default();
    for f in valid(fragments) {
        let b = f.optical_depth();
        let p = powers(warp(f.depth));
        t.b[0] += b;
        for (sum, power) in t.b[1..=n].iter_mut().zip(p) {
            *sum += power * b;
        }
    }
    t
}

/// The normalised, biased moments `m'_j = (b_j / b_0) (1 - β) + v_j β`, `j = 1..=n`.
pub fn biased_moments(params: &MsmParams, texel: &MsmTexel) -> [f32; 6] {
    let n = params.moment_count();
    let v: &[f32] = if n == 6 { &BIAS_VECTOR_6 } else { &BIAS_VECTOR_4 };
    let beta = params.bias;
    let mut m = [0.0f32; 6];
    for ((m, b), v) in m.iter_mut().zip(&texel.b[1..=n]).zip(v) {
        *m = (b / texel.b[0]) * (1.0 - beta) + v * beta;
    }
    m
}

/// The two roots of `c0 + c1 t + c2 t²`, smaller first when `c2 > 0`: `-p/2 ∓ sqrt(max(p²/4 - q, 0))`,
/// `p = c1 / c2`, `q = c0 / c2`.
pub fn quadratic_roots(c0: f32, c1: f32, c2: f32) -> [f32; 2] {
    let p = c1 / c2;
    let q = c0 / c2;
    let r = (p * p * 0.25 - q).max(0.0).sqrt();
    [-p * 0.5 - r, -p * 0.5 + r]
}

/// The three real roots of `c0 + c1 t + c2 t² + c3 t³` (Peters' trigonometric solve, "Moments in Graphics"
/// blog, as in MBOIT: normalise, depress, take the cube root of a unit complex number), each polished by two
/// Newton steps ([`polish`]).
pub fn cubic_roots(c0: f32, c1: f32, c2: f32, c3: f32) -> [f32; 3] {
    let a = c0 / c3;
    let b = c1 / c3 / 3.0;
    let c = c2 / c3 / 3.0;
    let dx = b - c * c;
    let dy = a - b * c;
    let dz = c * a - b * b;
    let disc = 4.0 * dx * dz - dy * dy;
    let depressed = dy - 2.0 * c * dx;
    let theta = disc.max(0.0).sqrt().atan2(-depressed) / 3.0;
    let (cr, ci) = (theta.cos(), theta.sin());
    let s = 2.0 * (-dx).max(0.0).sqrt();
    [
        s * cr - c,
        s * (-0.5 * cr - HALF_SQRT_3 * ci) - c,
        s * (-0.5 * cr + HALF_SQRT_3 * ci) - c,
    ]
    .map(|r| polish(c0, c1, c2, c3, polish(c0, c1, c2, c3, r)))
}

/// One Newton step `r - p(r) / p'(r)` on `c0 + c1 t + c2 t² + c3 t³` (Horner), skipped where not finite. Two
/// steps after the trigonometric solve make the roots independent of the precision of `atan2`, `cos` and
/// `sin` (Vulkan allows 4096 ULP for `atan2` and 2^-11 absolute error for `cos` and `sin`).
pub fn polish(c0: f32, c1: f32, c2: f32, c3: f32, r: f32) -> f32 {
    let p = ((c3 * r + c2) * r + c1) * r + c0;
    let dp = (3.0 * c3 * r + 2.0 * c2) * r + c1;
    let step = p / dp;
    if step.is_finite() { r - step } else { r }
}

/// 1 if support point `zi` lies in front of `x`, else 0.
fn in_front(zi: f32, x: f32) -> f32 {
    if zi < x { 1.0 } else { 0.0 }
}

/// The bound's fraction of absorbance in front of `x` from 4 biased moments (unclamped, possibly NaN).
pub fn fraction_4(m: &[f32; 6], x: f32, w: f32) -> f32 {
    let (m1, m2, m3, m4) = (m[0], m[1], m[2], m[3]);
    // B = [[1, m1, m2], [m1, m2, m3], [m2, m3, m4]] = L D Lᵀ.
    let d11 = (-m1).mul_add(m1, m2);
    let l21d11 = (-m1).mul_add(m2, m3);
    let l21 = l21d11 / d11;
    let d22 = (-l21d11).mul_add(l21, (-m2).mul_add(m2, m4));
    // Solve B c = (1, x, x²): forward, scale, backward.
    let mut c1 = x - m1;
    let mut c2 = x * x - (m2 + l21 * c1);
    c1 /= d11;
    c2 /= d22;
    c1 -= l21 * c2;
    let c0 = 1.0 - (m1 * c1 + m2 * c2);
    let [z1, z2] = quadratic_roots(c0, c1, c2);
    // Newton interpolation through (x, w), (z1, f1), (z2, f2), expanded to monomials.
    let (f0, f1, f2) = (w, in_front(z1, x), in_front(z2, x));
    let f01 = (f1 - f0) / (z1 - x);
    let f12 = (f2 - f1) / (z2 - z1);
    let f012 = (f12 - f01) / (z2 - x);
    let p2 = f012;
    let p1 = f01 - f012 * z1;
    let p0 = f0 - p1 * x;
    let p1 = p1 - p2 * x;
    p0 + p1 * m1 + p2 * m2
}

/// The bound's fraction of absorbance in front of `x` from 6 biased moments (unclamped, possibly NaN).
pub fn fraction_6(m: &[f32; 6], x: f32, w: f32) -> f32 {
    let (m1, m2, m3, m4, m5, m6) = (m[0], m[1], m[2], m[3], m[4], m[5]);
    // B = [[1, m1, m2, m3], [m1, m2, m3, m4], [m2, m3, m4, m5], [m3, m4, m5, m6]] = L D Lᵀ.
    let d11 = (-m1).mul_add(m1, m2);
    let l21d11 = (-m1).mul_add(m2, m3);
    let l21 = l21d11 / d11;
    let d22 = (-l21d11).mul_add(l21, (-m2).mul_add(m2, m4));
    let l31d11 = (-m1).mul_add(m3, m4);
    let l31 = l31d11 / d11;
    let l32d22 = (-l21d11).mul_add(l31, (-m2).mul_add(m3, m5));
    let l32 = l32d22 / d22;
    let d33 = (-m3).mul_add(m3, m6) - (l31d11 * l31 + l32d22 * l32);
    // Solve B c = (1, x, x², x³).
    let x2 = x * x;
    let mut c1 = x - m1;
    let mut c2 = x2 - (m2 + l21 * c1);
    let mut c3 = x2 * x - (m3 + (l31 * c1 + l32 * c2));
    c1 /= d11;
    c2 /= d22;
    c3 /= d33;
    c2 -= l32 * c3;
    c1 -= l21 * c2 + l31 * c3;
    let c0 = 1.0 - (m1 * c1 + m2 * c2 + m3 * c3);
    let [z1, z2, z3] = cubic_roots(c0, c1, c2, c3);
    let (f0, f1, f2, f3) = (w, in_front(z1, x), in_front(z2, x), in_front(z3, x));
    let f01 = (f1 - f0) / (z1 - x);
    let f12 = (f2 - f1) / (z2 - z1);
    let f23 = (f3 - f2) / (z3 - z2);
    let f012 = (f12 - f01) / (z2 - x);
    let f123 = (f23 - f12) / (z3 - z1);
    let f0123 = (f123 - f012) / (z3 - x);
    // f0 + f01 (t - x) + f012 (t - x)(t - z1) + f0123 (t - x)(t - z1)(t - z2), by Horner from the inside.
    let q1 = f0123;
    let q0 = f012 - f0123 * z2;
    let (q2, q1, q0) = (q1, q0 - q1 * z1, f01 - q0 * z1);
    let (p3, p2, p1, p0) = (q2, q1 - q2 * x, q0 - q1 * x, f0 - q0 * x);
    p0 + p1 * m1 + p2 * m2 + p3 * m3
}

/// The fallback for a singular system: all absorbance at the mean `m_1`, weighted `w` within one standard
/// deviation of it (`(x - m_1)² <= m_2 - m_1²`), 0 in front and 1 behind.
pub fn one_point(m: &[f32; 6], x: f32, w: f32) -> f32 {
    let d = x - m[0];
    if d * d <= m[1] - m[0] * m[0] {
        w
    } else if x > m[0] {
        1.0
    } else {
        0.0
    }
}

/// The fraction of the texel's absorbance in front of `z`, in `[0, 1]`.
pub fn fraction_in_front(params: &MsmParams, texel: &MsmTexel, z: f32) -> f32 {
    let m = biased_moments(params, texel);
    let x = warp(z);
    let w = params.overestimation;
    let at = |x| {
        if params.moment_count() == 6 {
            fraction_6(&m, x, w)
        } else {
            fraction_4(&m, x, w)
        }
    };
    let mut f = at(x);
    if !f.is_finite() {
        f = at(x + NUDGE);
    }
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        one_point(&m, x, w)
    }
}

/// `V(z) = exp(-b_0 · fraction)`; 1 in an empty texel (`b_0 <= 0`).
pub fn visibility(params: &MsmParams, texel: &MsmTexel, z: f32) -> f32 {
    let b0 = texel.b[0];
    if b0 <= 0.0 {
        return 1.0;
    }
    transmittance(b0 * fraction_in_front(params, texel, z))
}

impl Model for MsmParams {
    type Texel = MsmTexel;

    fn build(&self, fragments: &[Fragment]) -> MsmTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &MsmTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

/// Depths of the inspector's bound-curve knots per texel.
const CURVE_KNOTS: usize = 64;

impl TexelModel for MsmParams {
    fn label(&self) -> String {
        format!("msm-{}", self.moment_count())
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).b[..=self.moment_count()].to_vec()
    }

    /// The moments in the summary; the bound curve sampled across the texel's depth range as knots.
    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = build(self, fragments);
        let n = self.moment_count();
        let mut s = Stored::new(self.label());
        s.summary.push(format!(
            "b0 = Σb = {:.4}; power moments of x = 2z - 1: {}",
            t.b[0],
            super::list(&t.b[1..=n])
        ));
        s.summary.push(format!(
            "bias β = {:e}, overestimation {:.2}; V floor exp(-b0) = {:.4}",
            self.bias,
            self.overestimation,
            transmittance(t.b[0])
        ));
        let (near, far) = depth_range(fragments);
        if near > far {
            return Some(s);
        }
        let (lo, hi) = ((near - 0.05).max(0.0), (far + 0.05).min(1.0));
        s.knots = (0..=CURVE_KNOTS)
            .map(|i| {
                let z = lo + (hi - lo) * i as f32 / CURVE_KNOTS as f32;
                [z, visibility(self, &t, z)]
            })
            .collect();
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::reference;
    use crate::visibility::test_support::{Rng, extreme_texels, probe_depths, random_texel};

    fn p(moments: u32, bias: f32, overestimation: f32) -> MsmParams {
        MsmParams {
            moments,
            bias,
            overestimation,
        }
    }

    #[test]
    fn hand_computed_moments() {
        // alpha 0.5 -> b = ln 2 at z = 0.75 (x = 0.5) and alpha 0.75 -> b = 2 ln 2 at z = 0.25 (x = -0.5).
        let ln2 = std::f32::consts::LN_2;
        let f = [Fragment::new(0.75, 0.5), Fragment::new(0.25, 0.75)];
        let t = build(&p(6, 0.0, 0.0), &f);
        let want = [
            3.0 * ln2,
            ln2 * 0.5 - 2.0 * ln2 * 0.5,
            ln2 * 0.25 + 2.0 * ln2 * 0.25,
            ln2 * 0.125 - 2.0 * ln2 * 0.125,
            ln2 * 0.0625 + 2.0 * ln2 * 0.0625,
            ln2 * 0.03125 - 2.0 * ln2 * 0.03125,
            ln2 * 0.015625 + 2.0 * ln2 * 0.015625,
        ];
        for (j, (got, want)) in t.b.iter().zip(want).enumerate() {
            assert!((got - want).abs() < 1e-6, "b_{j}: {got} vs {want}");
        }
        assert_eq!(build(&p(4, 0.0, 0.0), &f).b[5..], [0.0, 0.0]);
        assert_eq!(p(4, 0.0, 0.0).stored_values(&f).len(), 5);
        assert_eq!(p(6, 0.0, 0.0).stored_values(&f).len(), 7);
    }

    #[test]
    fn roots_of_known_polynomials() {
        // (t - 1)(t + 2) = t² + t - 2.
        let [a, b] = quadratic_roots(-2.0, 1.0, 1.0);
        assert!((a + 2.0).abs() < 1e-6 && (b - 1.0).abs() < 1e-6, "{a} {b}");
        // 2 (t + 0.5)(t - 0.25)(t - 0.75) = 2t³ - t² - 0.625t + 0.1875.
        let mut r = cubic_roots(0.1875, -0.625, -1.0, 2.0);
        r.sort_by(f32::total_cmp);
        for (got, want) in r.iter().zip([-0.5, 0.25, 0.75]) {
            assert!((got - want).abs() < 1e-5, "{r:?}");
        }
    }

    /// MBOIT's f32 setting for `m` moments.
    fn mboit(m: u32) -> MsmParams {
        let bias = if m == 6 { DEFAULT_BIAS_6 } else { DEFAULT_BIAS_4 };
        p(m, bias, DEFAULT_OVERESTIMATION)
    }

    #[test]
    fn two_fragments_are_recovered_away_from_them() {
        // Two Diracs are determined by their first 3 moments, so the bound is the exact step curve wherever z
        // is not a support point, up to the bias: V = 1 before the first fragment, exp(-2 ln 2) = 1/4 between,
        // 1/8 behind both (measured: within 3.3e-6).
        let f = [Fragment::new(0.25, 0.75), Fragment::new(0.75, 0.5)];
        for m in [4, 6] {
            let q = mboit(m);
            let t = build(&q, &f);
            for (z, want) in [(0.1, 1.0), (0.5, 0.25), (0.9, 0.125)] {
                let v = visibility(&q, &t, z);
                assert!((v - want).abs() < 1e-5, "msm-{m}: V({z}) = {v}, want {want}");
            }
        }
    }

    #[test]
    fn overestimation_weights_a_fragment_at_its_own_depth() {
        // At a single fragment's own depth the lower bound puts none of it in front, the upper bound all of it;
        // w weights it: V = exp(-w b) (measured: within 3e-6).
        let f = [Fragment::new(0.5, 0.5), Fragment::new(0.3, 0.0)];
        for m in [4, 6] {
            for w in [0.0, 0.25, 1.0] {
                let q = MsmParams {
                    overestimation: w,
                    ..mboit(m)
                };
                let v = visibility(&q, &build(&q, &f), 0.5);
                let want = (-w * std::f32::consts::LN_2).exp();
                assert!((v - want).abs() < 1e-5, "msm-{m}, w {w}: {v} vs {want}");
            }
        }
    }

    #[test]
    fn a_system_singular_in_f32_falls_back_to_the_mean() {
        // No bias: one fragment's Hankel matrix is singular, the bound is not finite, so all absorbance
        // counts at the mean x = 0 (z = 0.5), weighted w there.
        let q = p(4, 0.0, 0.25);
        let t = build(&q, &[Fragment::new(0.5, 0.5)]);
        assert!(!fraction_4(&biased_moments(&q, &t), 0.0, 0.25).is_finite());
        assert_eq!(fraction_in_front(&q, &t, 0.4), 0.0);
        assert_eq!(fraction_in_front(&q, &t, 0.5), 0.25);
        assert_eq!(fraction_in_front(&q, &t, 0.6), 1.0);
    }

    #[test]
    fn empty_texel_is_lit_and_the_floor_is_the_total_optical_depth() {
        assert_eq!(MsmParams::default().curve(&[], &[0.0, 0.5, 1.0]), [1.0; 3]);
        let mut rng = Rng::new(7);
        for m in [4, 6] {
            let q = mboit(m);
            for _ in 0..300 {
                let f = random_texel(&mut rng, 60);
                let t = build(&q, &f);
                let floor = transmittance(t.b[0]);
                let total = reference::Reference.curve(&f, &[2.0])[0];
                // b0 is the same sum the reference takes (another order): f32 rounding only.
                assert!((floor - total).abs() < 1e-5, "{floor} vs {total}");
                for z in [-0.1, 0.0, 0.3, 0.7, 1.0, 1.1] {
                    let v = visibility(&q, &t, z);
                    assert!(v >= floor && v <= 1.0, "msm-{m}: V({z}) = {v}, floor {floor}");
                }
            }
        }
    }

    #[test]
    fn far_behind_the_fragments_v_is_the_total_transmittance() {
        // The zeroth moment keeps the total optical depth, but the Hamburger bound is over the whole real
        // line: other distributions with the same moments may still hold absorbance behind the last fragment,
        // so V reaches exp(-b_0) only far behind it. Measured over the random texels ending before z = 0.9:
        // |V - exp(-b_0)| at far + 0.1 at most 1.3e-2 (4 moments) and 3.5e-3 (6), at z = 10 (x = 19) 6e-8.
        let mut rng = Rng::new(11);
        for (m, near_limit) in [(4, 0.03), (6, 0.01)] {
            let q = mboit(m);
            let (mut near_worst, mut far_worst) = (0.0f32, 0.0f32);
            for _ in 0..400 {
                let f = random_texel(&mut rng, 60);
                let (_, far) = depth_range(&f);
                if far > 0.9 {
                    continue;
                }
                let t = build(&q, &f);
                let off = |z| (visibility(&q, &t, z) - transmittance(t.b[0])).abs();
                near_worst = near_worst.max(off(far + 0.1));
                far_worst = far_worst.max(off(10.0));
            }
            assert!(
                near_worst <= near_limit,
                "msm-{m}: |V - exp(-b0)| = {near_worst} at far + 0.1"
            );
            assert!(
                far_worst <= 1e-6,
                "msm-{m}: |V - exp(-b0)| = {far_worst} at z = 10"
            );
        }
    }

    /// Largest increase of `V` between neighbouring probe depths, over the curve of `fragments`.
    fn largest_increase(q: &MsmParams, fragments: &[Fragment]) -> f32 {
        let zs = probe_depths(fragments);
        let v = q.curve(fragments, &zs);
        assert!(v.iter().all(|v| (0.0..=1.0).contains(v)), "{v:?}");
        v.windows(2).map(|w| w[1] - w[0]).fold(0.0, f32::max)
    }

    #[test]
    fn curves_are_monotone_up_to_f32_noise() {
        // The bound is non-increasing in exact arithmetic; in f32 the ill-conditioned solve wiggles. Measured
        // largest increase over the extreme texels and 400 random ones: 3.2e-5 (4 moments, β 5e-7), 3.6e-5
        // (6, 5e-6), 2.3e-4 (4, 5e-6), 6.4e-6 (4, 1e-2), 1.3e-6 (6, 1e-2).
        let mut rng = Rng::new(43);
        for (q, allowed) in [
            (mboit(4), 1e-4),
            (mboit(6), 1e-4),
            (p(4, DEFAULT_BIAS_6, 0.25), 5e-4),
            (p(4, 1e-2, 0.0), 2e-5),
            (p(6, 1e-2, 1.0), 2e-5),
        ] {
            let mut texels = extreme_texels();
            texels.extend((0..400).map(|_| random_texel(&mut rng, 40)));
            let worst = texels.iter().map(|f| largest_increase(&q, f)).fold(0.0, f32::max);
            assert!(worst <= allowed, "{}: V increases by {worst}", q.label());
        }
    }
}
