//! The fits of `measure fibres`: a density factor scaling a model onto measured slab figures (Zinke et al.
//! 2008's `d_f` in `T_f = d_f ā_f^n`, `d_b` in the back-scattering `d_b A_b`), and a free exponential `d a^n`
//! per channel to show how far the measured fall with depth departs from `ā_f^n`.

use serde::Serialize;

/// A scale fitted to measured values, and how well it fits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ScaleFit {
    pub scale: f64,
    /// RMS over the points and channels of `measured / (scale · model) − 1`.
    pub residual: f64,
    /// Points × channels that entered the fit.
    pub points: usize,
}

/// The scale `d` of `measured ≈ d · model` by least squares on the logarithms (every point and channel equally,
/// so a deep slab's small figures weigh as much as a shallow one's): `ln d` the mean of `ln(measured / model)`.
/// Points or channels where either side is not positive are left out; `None` when none is left.
pub fn fit_scale(points: &[([f64; 3], [f64; 3])]) -> Option<ScaleFit> {
    let ratios: Vec<f64> = points
        .iter()
        .flat_map(|(m, model)| (0..3).map(move |c| (m[c], model[c])))
        .filter(|&(m, model)| m > 0.0 && model > 0.0 && m.is_finite() && model.is_finite())
        .map(|(m, model)| m / model)
        .collect();
    if ratios.is_empty() {
        return None;
    }
    let k = ratios.len() as f64;
    let scale = (ratios.iter().map(|r| r.ln()).sum::<f64>() / k).exp();
    let residual = (ratios.iter().map(|r| (r / scale - 1.0).powi(2)).sum::<f64>() / k).sqrt();
    Some(ScaleFit {
        scale,
        residual,
        points: ratios.len(),
    })
}

/// `value ≈ d · a^n` by least squares of `ln value` on `n`, with the RMS of `value / (d a^n) − 1`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ExponentialFit {
    pub d: f64,
    pub a: f64,
    pub residual: f64,
}

/// [`ExponentialFit`] through `(n, value)` points with positive values (`None` below two distinct `n`).
pub fn fit_exponential(points: &[(f64, f64)]) -> Option<ExponentialFit> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|&&(n, v)| v > 0.0 && v.is_finite() && n.is_finite())
        .map(|&(n, v)| (n, v.ln()))
        .collect();
    let k = p.len() as f64;
    let (mn, ml) = (
        p.iter().map(|q| q.0).sum::<f64>() / k,
        p.iter().map(|q| q.1).sum::<f64>() / k,
    );
    let sxx: f64 = p.iter().map(|q| (q.0 - mn).powi(2)).sum();
    if p.len() < 2 || sxx <= 0.0 {
        return None;
    }
    let slope = p.iter().map(|q| (q.0 - mn) * (q.1 - ml)).sum::<f64>() / sxx;
    let (d, a) = ((ml - slope * mn).exp(), slope.exp());
    let residual = (p
        .iter()
        .map(|q| (q.1.exp() / (d * a.powf(q.0)) - 1.0).powi(2))
        .sum::<f64>()
        / k)
        .sqrt();
    Some(ExponentialFit { d, a, residual })
}

/// Zinke et al. 2008 §4.3's back-scattered energy of the hair behind a point, as hairlab's real-time model
/// writes it (`shading::dual_scattering`): with `q = 1 − ā_f²`, `A_b = ā_b ā_f² / q + ā_b³ ā_f² / q³` (the one-
/// and three-bounce back paths; the single scattering of the first fibre is not in it).
pub fn back_energy(forward: f64, backward: f64) -> f64 {
    let af2 = forward * forward;
    let q = (1.0 - af2).max(1e-4);
    backward * af2 / q + backward.powi(3) * af2 / q.powi(3)
}
