//! Fourier Opacity Mapping (Jansen & Bavoil, "Fourier Opacity Mapping", I3D 2010): the absorption density
//! `σ(d)` along the light ray, over the GLOBAL fitted light range `d ∈ [0, 1]` (hairlab's normalised light
//! depth across the strands, standing for the paper's light near/far range; not the texel's own near/far), as
//! a Fourier series truncated after `K` terms.
//!
//! Each fragment is a Dirac of strength `b = -ln(1 - alpha)` at its depth `d`, so the `2K + 1` coefficients are
//! sums over fragments: `a_0 = 2 Σ b`, `a_k = 2 Σ b cos(2πk d)`, `b_k = 2 Σ b sin(2πk d)`. The optical depth in
//! front of `z` is the series integrated from 0 to `z`:
//! `T(z) = a_0 z / 2 + Σ_k w_k [a_k sin(2πk z) + b_k (1 - cos(2πk z))] / (2πk)`, and `V = exp(-T)` clamped to
//! `[0, 1]` (the series can leave it). `w_k` is the window: 1 for the paper's plain truncation (`plain`),
//! `1 - k / (K + 1)` for the Fejér (Cesàro) window (`fejer`, hairlab's addition: its kernel is non-negative,
//! so `T` never decreases, at the price of a blurrier density; it is the default because every method's
//! default curve must be non-increasing). Both use the same stored coefficients.
//!
//! Exact: `T(0) = 0` and `T(z >= 1) = a_0 / 2 = Σ b` (all fragments), for either window. Approximate: in
//! between, where the truncated series of a sum of Diracs rings (the Gibbs phenomenon; the paper's §7.3 ties it
//! to feature size and opacity): without a window the density goes negative, `T` decreases and dips below 0,
//! and `V` rises with depth or above 1 before the clamp ([`unclamped_visibility`]). The ringing narrows as `K`
//! grows but its height (about 9 % of a step) does not fall: the Gibbs overshoot.
//!
//! Constants: [`MAX_TERMS`] (16), [`DEFAULT_TERMS`] (3: the paper's 7 coefficients in two RGBA targets),
//! `KNOTS_PER_COEFFICIENT` (4, the inspector's sampling of the curve), and `TWO_PI`, the f32 2π = 6.2831855
//! (`std::f32::consts::TAU`).
//!
//! GPU contract (per texel, the `2K + 1` f32 coefficients in the order `a_0, a_1, b_1, …, a_K, b_K`, four per
//! RGBA32F layer):
//! - phase: `x = f32(k) * d`, `r = x - floor(x + 0.5)` (in `[-0.5, 0.5]`, where sin/cos are most accurate),
//!   angle `TWO_PI * r`;
//! - build, per fragment (additive blending): coefficient `i` gets `(2.0 * b) * basis` with basis 1 for
//!   `i = 0`, `cos` of the angle of `k = (i + 1) / 2` for odd `i`, `sin` for even `i > 0`;
//! - lookup: `zc = clamp(z, 0.0, 1.0)`, `t = (a_0 * 0.5) * zc`, then for `k = 1..=K`:
//!   `t += w_k * (a_k * sin(θ) + b_k * (1.0 - cos(θ))) / (TWO_PI * f32(k))` with θ the angle of `(k, zc)` and
//!   `w_k = 1.0` or `1.0 - f32(k) / f32(K + 1)`; `V = clamp(exp(-t), 0.0, 1.0)`.

use super::{Fragment, Model, Stored, TexelModel, list, transmittance, valid};
use std::f32::consts::TAU;

/// Largest number of Fourier terms `K` (33 coefficients, 9 RGBA32F layers).
pub const MAX_TERMS: u32 = 16;

/// The default number of terms: the paper's 7 coefficients (`a_0` and three cosine and sine pairs) in two
/// RGBA targets.
pub const DEFAULT_TERMS: u32 = 3;

/// How the series is truncated at lookup (the stored coefficients are the same for both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FomWindow {
    /// The paper's plain truncation: rings around sharp absorbers.
    None,
    /// Fejér weights `1 - k / (K + 1)`: a non-negative kernel, so `T` is non-decreasing.
    Fejer,
}

impl FomWindow {
    /// The window's index (the GPU's `window` uniform and the parameter's choice index).
    pub fn index(self) -> u32 {
        match self {
            FomWindow::None => 0,
            FomWindow::Fejer => 1,
        }
    }

    /// The window of choice index `i` (anything but 1 is `None`).
    pub fn from_index(i: u32) -> FomWindow {
        if i == 1 { FomWindow::Fejer } else { FomWindow::None }
    }
}

/// Fourier Opacity Mapping parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FomParams {
    /// Fourier terms `K`, clamped to `1..=16`.
    pub terms: u32,
    pub window: FomWindow,
}

impl Default for FomParams {
    /// The paper's 7 coefficients, with the Fejér window (the plain truncation is the `plain` choice).
    fn default() -> Self {
        Self {
            terms: DEFAULT_TERMS,
            window: FomWindow::Fejer,
        }
    }
}

impl FomParams {
    /// The term count actually used: `terms` clamped to `1..=16`.
    pub fn term_count(&self) -> usize {
        self.terms.clamp(1, MAX_TERMS) as usize
    }

    /// Stored coefficients per texel, `2K + 1`.
    pub fn coefficient_count(&self) -> usize {
        2 * self.term_count() + 1
    }

    /// The window weight `w_k` of term `k` (of `n` terms).
    fn weight(&self, k: usize, n: usize) -> f32 {
        match self.window {
            FomWindow::None => 1.0,
            FomWindow::Fejer => 1.0 - k as f32 / (n + 1) as f32,
        }
    }
}

/// One FOM texel: `coefficients = [a_0, a_1, b_1, …, a_K, b_K]`.
#[derive(Clone, Debug, PartialEq)]
pub struct FomTexel {
    pub coefficients: Vec<f32>,
}

/// The angle `2π k d` reduced to `[-π, π]`: `TWO_PI * (x - floor(x + 0.5))` with `x = k * d`.
pub fn angle(k: usize, d: f32) -> f32 {
    let x = k as f32 * d;
    TAU * (x - (x + 0.5).floor())
}

/// Builds a FOM texel: each fragment adds its Dirac's `2K + 1` coefficients.
pub fn build(params: &FomParams, fragments: &[Fragment]) -> FomTexel {
    let mut coefficients = vec![0.0f32; params.coefficient_count()];
    for f in valid(fragments) {
        let b2 = 2.0 * f.optical_depth();
        coefficients[0] += b2;
        for (i, c) in coefficients.iter_mut().enumerate().skip(1) {
            let a = angle(i.div_ceil(2), f.depth);
            *c += b2 * if i % 2 == 1 { a.cos() } else { a.sin() };
        }
    }
    FomTexel { coefficients }
}

/// The reconstructed optical depth `T(z)` in front of `z`, before any clamping (it can be negative and can
/// decrease with `z` without a window). `K` is the texel's (what [`build`] made).
pub fn optical_depth_at(params: &FomParams, texel: &FomTexel, z: f32) -> f32 {
    let c = &texel.coefficients;
    let Some(&a0) = c.first() else { return 0.0 };
    let n = (c.len() - 1) / 2;
    let zc = z.clamp(0.0, 1.0);
    let mut t = (a0 * 0.5) * zc;
    for k in 1..=n {
        let a = angle(k, zc);
        let (ak, bk) = (c[2 * k - 1], c[2 * k]);
        t += params.weight(k, n) * (ak * a.sin() + bk * (1.0 - a.cos())) / (TAU * k as f32);
    }
    t
}

/// `exp(-T(z))` before the clamp to `[0, 1]`: above 1 where the ringing makes `T` negative.
pub fn unclamped_visibility(params: &FomParams, texel: &FomTexel, z: f32) -> f32 {
    transmittance(optical_depth_at(params, texel, z))
}

/// `V(z)`: [`unclamped_visibility`] clamped to `[0, 1]`.
pub fn visibility(params: &FomParams, texel: &FomTexel, z: f32) -> f32 {
    unclamped_visibility(params, texel, z).clamp(0.0, 1.0)
}

impl Model for FomParams {
    type Texel = FomTexel;

    fn build(&self, fragments: &[Fragment]) -> FomTexel {
        build(self, fragments)
    }

    fn visibility(&self, texel: &FomTexel, z: f32) -> f32 {
        visibility(self, texel, z)
    }
}

/// Knots the inspector draws: the reconstruction sampled this many times per coefficient across `[0, 1]`.
const KNOTS_PER_COEFFICIENT: usize = 4;

impl TexelModel for FomParams {
    fn label(&self) -> String {
        match self.window {
            FomWindow::None => format!("fom-{}", self.term_count()),
            FomWindow::Fejer => format!("fom-{} fejer", self.term_count()),
        }
    }

    fn curve(&self, fragments: &[Fragment], zs: &[f32]) -> Vec<f32> {
        super::model_curve(self, fragments, zs)
    }

    fn stored_values(&self, fragments: &[Fragment]) -> Vec<f32> {
        build(self, fragments).coefficients
    }

    /// The reconstructed `V = exp(-T)` (clamped) as knots over the whole range, with the lowest unclamped `T`
    /// and the largest rise of `V` in the summary.
    fn stored(&self, fragments: &[Fragment]) -> Option<Stored> {
        let t = build(self, fragments);
        let n = KNOTS_PER_COEFFICIENT * t.coefficients.len();
        let mut s = Stored::new(self.label());
        let ts: Vec<(f32, f32)> = (0..=n)
            .map(|i| {
                let z = i as f32 / n as f32;
                (z, optical_depth_at(self, &t, z))
            })
            .collect();
        s.knots = ts
            .iter()
            .map(|&(z, tz)| [z, transmittance(tz).clamp(0.0, 1.0)])
            .collect();
        let lowest = ts.iter().map(|p| p.1).fold(0.0f32, f32::min);
        let fall = ts.windows(2).map(|w| w[0].1 - w[1].1).fold(0.0f32, f32::max);
        s.summary.push(format!(
            "{} Fourier coefficients of the absorption density over the whole light range",
            t.coefficients.len()
        ));
        s.summary
            .push(format!("a0, a1, b1, …: {}", list(&t.coefficients)));
        s.summary.push(format!(
            "ringing: lowest T {lowest:.4}, largest fall of T {fall:.4} (0 for a monotone T)"
        ));
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::test_support::{Rng, extreme_texels, probe_depths, random_texel};
    use crate::visibility::{optical_depth, reference};
    use std::f32::consts::{LN_2, PI};

    fn p(terms: u32, window: FomWindow) -> FomParams {
        FomParams { terms, window }
    }

    #[test]
    fn hand_computed_single_fragment() {
        // One fragment, alpha 1/2 (b = ln 2) at d = 1/4, K = 1: a0 = 2 ln 2, a1 = 2 ln 2 cos(π/2) = 0,
        // b1 = 2 ln 2 sin(π/2) = 2 ln 2.
        let t = build(&p(1, FomWindow::None), &[Fragment::new(0.25, 0.5)]);
        let want = [2.0 * LN_2, 0.0, 2.0 * LN_2];
        for (got, want) in t.coefficients.iter().zip(want) {
            assert!((got - want).abs() < 1e-6, "{:?}", t.coefficients);
        }
        // T(z) = ln 2 z + 2 ln 2 (1 - cos 2πz) / 2π. At z = 1/2: ln 2 / 2 + 2 ln 2 / π.
        let pn = p(1, FomWindow::None);
        let tz = optical_depth_at(&pn, &t, 0.5);
        assert!((tz - (LN_2 / 2.0 + 2.0 * LN_2 / PI)).abs() < 1e-6, "{tz}");
        // At z = 1/4: ln 2 / 4 + 2 ln 2 / 2π.
        let tz = optical_depth_at(&pn, &t, 0.25);
        assert!((tz - (LN_2 / 4.0 + LN_2 / PI)).abs() < 1e-6, "{tz}");
        // Fejér with K = 1 halves the first term: ln 2 / 2 + ln 2 / π at z = 1/2.
        let tz = optical_depth_at(&p(1, FomWindow::Fejer), &t, 0.5);
        assert!((tz - (LN_2 / 2.0 + LN_2 / PI)).abs() < 1e-6, "{tz}");
        // Exact ends: T(0) = 0, T(1) = b (V = 1/2), and beyond the range the ends hold.
        assert_eq!(visibility(&pn, &t, 0.0), 1.0);
        assert_eq!(visibility(&pn, &t, -3.0), 1.0);
        assert!((visibility(&pn, &t, 1.0) - 0.5).abs() < 1e-6);
        assert!((visibility(&pn, &t, 7.0) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn hand_computed_two_fragments_ring() {
        // Fragments at d = 0 and d = 1/2, b = ln 2 each, K = 1: a0 = 4 ln 2, a1 = 2 ln 2 (cos 0 + cos π) = 0,
        // b1 = 0 (sin 0 + sin π). T(z) = 2 ln 2 z: the K = 1 series cannot tell them apart from a uniform
        // density. With K = 2: a2 = 2 ln 2 (1 + 1) = 4 ln 2, b2 = 0, so T(z) = 2 ln 2 z + ln 2 sin(4πz) / π:
        // T(1/4) = ln 2 / 2 = 0.3466 but T(3/8) = 3 ln 2 / 4 - ln 2 / π = 0.2993 (sin(4πz) = -1).
        let f = [Fragment::new(0.0, 0.5), Fragment::new(0.5, 0.5)];
        let t1 = build(&p(1, FomWindow::None), &f);
        for (got, want) in t1.coefficients.iter().zip([4.0 * LN_2, 0.0, 0.0]) {
            assert!((got - want).abs() < 1e-6, "{:?}", t1.coefficients);
        }
        let t2 = build(&p(2, FomWindow::None), &f);
        assert!((t2.coefficients[3] - 4.0 * LN_2).abs() < 1e-6);
        assert!(t2.coefficients[4].abs() < 1e-6);
        let tz = optical_depth_at(&p(2, FomWindow::None), &t2, 0.375);
        assert!((tz - (0.75 * LN_2 - LN_2 / PI)).abs() < 1e-6, "{tz}");
        // The density there is negative: T falls between z = 1/4 and 3/8, so V rises from 2^-1/2 = 0.7071 to
        // 0.7413 (ringing).
        let v = |z| visibility(&p(2, FomWindow::None), &t2, z);
        assert!((v(0.25) - 0.5f32.sqrt()).abs() < 1e-6);
        assert!((v(0.375) - 0.7413).abs() < 1e-4, "{}", v(0.375));
    }

    #[test]
    fn angle_is_reduced_and_periodic() {
        assert_eq!(angle(0, 0.7), 0.0);
        assert_eq!(angle(3, 1.0), 0.0);
        assert_eq!(angle(4, 0.25), 0.0);
        assert!((angle(1, 0.25) - PI / 2.0).abs() < 1e-6);
        assert!((angle(1, 0.75) + PI / 2.0).abs() < 1e-6);
        for k in 1..=16 {
            for i in 0..=100 {
                let a = angle(k, i as f32 / 100.0);
                assert!(a.abs() <= PI + 1e-6, "k={k} i={i}: {a}");
            }
        }
    }

    #[test]
    fn ends_are_exact_for_every_k_and_window() {
        let mut rng = Rng::new(40);
        for _ in 0..50 {
            let f = random_texel(&mut rng, 60);
            let total: f32 = f.iter().map(|f| optical_depth(f.alpha)).sum();
            for k in [1, 2, 3, 4, 8, 16] {
                for w in [FomWindow::None, FomWindow::Fejer] {
                    let t = build(&p(k, w), &f);
                    assert_eq!(optical_depth_at(&p(k, w), &t, 0.0), 0.0);
                    let end = optical_depth_at(&p(k, w), &t, 1.0);
                    assert!(
                        (end - total).abs() < 1e-5 * total.max(1.0),
                        "K={k}: {end} vs {total}"
                    );
                }
            }
        }
    }

    /// Largest fall of `T` between neighbouring probe depths (0 when `T` is non-decreasing).
    fn largest_fall(params: &FomParams, f: &[Fragment]) -> f32 {
        let t = build(params, f);
        let ts: Vec<f32> = probe_depths(f)
            .iter()
            .map(|&z| optical_depth_at(params, &t, z))
            .collect();
        ts.windows(2).map(|w| w[0] - w[1]).fold(0.0, f32::max)
    }

    #[test]
    fn fejer_is_monotone_and_plain_truncation_rings() {
        let mut rng = Rng::new(41);
        let mut rang = 0;
        for _ in 0..100 {
            let f = random_texel(&mut rng, 60);
            for k in [1, 2, 4, 8, 16] {
                // f32 rounding of the sums only: a fall at most a few ulps of the total.
                let fall = largest_fall(&p(k, FomWindow::Fejer), &f);
                assert!(fall < 1e-5, "Fejér K={k}: T falls by {fall}; fragments {f:?}");
                if largest_fall(&p(k, FomWindow::None), &f) > 1e-3 {
                    rang += 1;
                }
            }
        }
        // The plain truncation rings on most of these clumped texels (measured: 458 of 500).
        assert!(rang > 400, "only {rang} of 500 texels ring without a window");
    }

    /// Mean |V - V_ref| over the grid z_i = (i + 0.5) / 2048.
    fn grid_error(params: &FomParams, f: &[Fragment]) -> f64 {
        let t = build(params, f);
        let m = 2048;
        (0..m)
            .map(|i| {
                let z = (i as f32 + 0.5) / m as f32;
                f64::from((visibility(params, &t, z) - reference::visibility(f, z)).abs())
            })
            .sum::<f64>()
            / m as f64
    }

    #[test]
    fn error_falls_with_terms() {
        let mut rng = Rng::new(42);
        let texels: Vec<Vec<Fragment>> = (0..100).map(|_| random_texel(&mut rng, 60)).collect();
        for w in [FomWindow::None, FomWindow::Fejer] {
            let means: Vec<f64> = [1u32, 2, 4, 8, 16]
                .iter()
                .map(|&k| texels.iter().map(|f| grid_error(&p(k, w), f)).sum::<f64>() / 100.0)
                .collect();
            // Measured (seed 42), K = 1, 2, 4, 8, 16: plain 0.123, 0.096, 0.064, 0.041, 0.033 (3.7x in all);
            // Fejér 0.174, 0.153, 0.124, 0.095, 0.069 (2.5x: the window's blur costs accuracy).
            assert!(
                means.windows(2).all(|m| m[1] < 0.9 * m[0]),
                "{w:?}: mean grid error does not fall with K: {means:?}"
            );
            let gain = if w == FomWindow::None { 3.0 } else { 2.0 };
            assert!(means[4] < means[0] / gain, "{w:?}: {means:?}");
        }
    }

    #[test]
    fn order_does_not_matter() {
        let mut rng = Rng::new(43);
        let mut f = random_texel(&mut rng, 50);
        let a = build(&p(16, FomWindow::None), &f);
        f.reverse();
        let b = build(&p(16, FomWindow::None), &f);
        for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
            assert!((x - y).abs() < 1e-5);
        }
    }

    /// The f32 sums of `2b cos(2πkd)` over a long list against the same terms summed in f64: the rounding the
    /// coefficient sums add to `T` grows with the fragment count (what the GPU = CPU tolerance has to cover).
    #[test]
    fn rounding_of_long_sums() {
        let mut rng = Rng::new(44);
        let params = p(16, FomWindow::None);
        let mut worst = Vec::new();
        for n in [10usize, 100, 1000, 4000] {
            let f: Vec<Fragment> = (0..n)
                .map(|_| Fragment::new(rng.unit(), rng.range(0.05, 0.6)))
                .collect();
            let t = build(&params, &f);
            let mut exact = vec![0.0f64; t.coefficients.len()];
            for f in &f {
                let b2 = 2.0 * f.optical_depth();
                exact[0] += f64::from(b2);
                for (i, c) in exact.iter_mut().enumerate().skip(1) {
                    let a = angle(i.div_ceil(2), f.depth);
                    *c += f64::from(b2 * if i % 2 == 1 { a.cos() } else { a.sin() });
                }
            }
            let rounded = FomTexel {
                coefficients: exact.iter().map(|&c| c as f32).collect(),
            };
            let dt = (0..=256)
                .map(|i| i as f32 / 256.0)
                .map(|z| (optical_depth_at(&params, &t, z) - optical_depth_at(&params, &rounded, z)).abs())
                .fold(0.0f32, f32::max);
            worst.push(dt);
        }
        // Measured max |ΔT| for n = 10, 100, 1000, 4000: 9.5e-7, 5.7e-6, 1.8e-4, 3.3e-3 (T(1) about 0.42 n, so
        // 2e-6 of it at n = 4000). In front of a deep texel T rings about 0 while the coefficients are of the
        // size of T(1): there |ΔV| is |ΔT| itself. hairlab's texels hold at most a few hundred fragments.
        assert!(worst[3] > 100.0 * worst[0], "{worst:?}");
        assert!(worst[3] < 1e-2, "{worst:?}");
    }

    #[test]
    fn properties_and_extremes() {
        for k in [0u32, 1, 2, 3, 16, 17, u32::MAX] {
            for w in [FomWindow::None, FomWindow::Fejer] {
                for f in extreme_texels() {
                    let params = p(k, w);
                    let t = build(&params, &f);
                    assert_eq!(t.coefficients.len(), params.coefficient_count());
                    for z in probe_depths(&f) {
                        let v = visibility(&params, &t, z);
                        assert!((0.0..=1.0).contains(&v), "K={k} {w:?}: V({z}) = {v}; {f:?}");
                    }
                    assert_eq!(visibility(&params, &t, 0.0), 1.0);
                }
            }
        }
        assert_eq!(build(&p(0, FomWindow::None), &[]).coefficients.len(), 3);
        assert_eq!(build(&p(100, FomWindow::None), &[]).coefficients.len(), 33);
    }

    #[test]
    fn unclamped_visibility_exceeds_one_where_t_is_negative() {
        // A single opaque-ish fragment at 0.9 with K = 2: T rings below 0 in front of it.
        let f = [Fragment::new(0.9, 0.9)];
        let params = p(2, FomWindow::None);
        let t = build(&params, &f);
        let (z, vmax) = (0..=100)
            .map(|i| i as f32 / 100.0)
            .map(|z| (z, unclamped_visibility(&params, &t, z)))
            .fold((0.0, 0.0f32), |a, b| if b.1 > a.1 { b } else { a });
        assert!(vmax > 1.01, "max unclamped V {vmax} at {z}");
        assert_eq!(visibility(&params, &t, z), 1.0);
    }

    #[test]
    fn stored_describes_the_coefficients() {
        let params = p(3, FomWindow::None);
        let f = [Fragment::new(0.3, 0.5), Fragment::new(0.6, 0.5)];
        assert_eq!(params.stored_values(&f).len(), 7);
        let s = params.stored(&f).unwrap();
        assert_eq!(s.label, "fom-3");
        assert_eq!(s.knots.len(), 4 * 7 + 1);
        assert_eq!(s.knots[0], [0.0, 1.0]);
        assert!((s.knots[28][1] - 0.25).abs() < 1e-5, "{:?}", s.knots[28]);
        assert!(s.summary[2].contains("lowest T"));
    }
}
