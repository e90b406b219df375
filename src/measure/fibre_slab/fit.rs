//! The fits of `measure fibres`: a density factor scaling a model onto measured slab figures (Zinke et al.
//! 2008's `d_f` in `T_f = d_f ā_f^n`, `d_b` in the back-scattering `d_b A_b`), and a free exponential `d a^n`
//! per channel to show how far the measured fall with depth departs from `ā_f^n`.

use serde::Serialize;

/// A scale fitted to measured values, and how well it fits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ScaleFit {
    pub scale: f64,
    /// `√(Σ (measured − scale · model)² / Σ measured²)`: the misfit as a share of the light measured.
    pub residual: f64,
    /// Points × channels that entered the fit.
    pub points: usize,
}

/// The scale `d` of `measured ≈ d · model` by least squares on the values themselves (`d = Σ m·model / Σ
/// model²`), so the points carrying light weigh most: a deep slab's `T` of 10⁻⁴ matters to no image. Points or
/// channels that are not finite are left out; `None` when every model value is 0.
pub fn fit_scale(points: &[([f64; 3], [f64; 3])]) -> Option<ScaleFit> {
    let pairs: Vec<(f64, f64)> = points
        .iter()
        .flat_map(|(m, model)| (0..3).map(move |c| (m[c], model[c])))
        .filter(|&(m, model)| m.is_finite() && model.is_finite())
        .collect();
    let mm: f64 = pairs.iter().map(|p| p.1 * p.1).sum();
    if mm <= 0.0 {
        return None;
    }
    let scale = pairs.iter().map(|p| p.0 * p.1).sum::<f64>() / mm;
    let misfit: f64 = pairs.iter().map(|p| (p.0 - scale * p.1).powi(2)).sum();
    let total: f64 = pairs.iter().map(|p| p.0 * p.0).sum();
    Some(ScaleFit {
        scale,
        residual: (misfit / total.max(f64::MIN_POSITIVE)).sqrt(),
        points: pairs.len(),
    })
}

/// `value ≈ d · a^n` fitted freely, with [`ScaleFit`]'s residual.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ExponentialFit {
    pub d: f64,
    pub a: f64,
    pub residual: f64,
}

/// [`ExponentialFit`] through `(n, value)` points with positive values, by least squares of `ln value` on `n`
/// weighted by `value²` (the linearised least squares on the values, as [`fit_scale`] weighs them); `None`
/// below two distinct `n`.
pub fn fit_exponential(points: &[(f64, f64)]) -> Option<ExponentialFit> {
    let p: Vec<(f64, f64, f64)> = points
        .iter()
        .filter(|&&(n, v)| v > 0.0 && v.is_finite() && n.is_finite())
        .map(|&(n, v)| (n, v.ln(), v * v))
        .collect();
    let w: f64 = p.iter().map(|q| q.2).sum();
    let (mn, ml) = (
        p.iter().map(|q| q.2 * q.0).sum::<f64>() / w,
        p.iter().map(|q| q.2 * q.1).sum::<f64>() / w,
    );
    let sxx: f64 = p.iter().map(|q| q.2 * (q.0 - mn).powi(2)).sum();
    if p.len() < 2 || sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let slope = p.iter().map(|q| q.2 * (q.0 - mn) * (q.1 - ml)).sum::<f64>() / sxx;
    let (d, a) = ((ml - slope * mn).exp(), slope.exp());
    let misfit: f64 = p.iter().map(|q| (q.1.exp() - d * a.powf(q.0)).powi(2)).sum();
    Some(ExponentialFit {
        d,
        a,
        residual: (misfit / w).sqrt(),
    })
}

/// Zinke et al. 2008 §4.3's back-scattered energy of the hair behind a point, as hairlab's real-time model
/// writes it (`shading::dual_scattering`): with `q = 1 − ā_f²`, `A_b = ā_b ā_f² / q + ā_b³ ā_f² / q³` (the one-
/// and three-bounce back paths; the single scattering of the first fibre is not in it).
pub fn back_energy(forward: f64, backward: f64) -> f64 {
    let af2 = forward * forward;
    let q = (1.0 - af2).max(1e-4);
    backward * af2 / q + backward.powi(3) * af2 / q.powi(3)
}
