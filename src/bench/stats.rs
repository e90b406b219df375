//! The statistics of the bench: the median and spread of the timed frames, the Pareto front of speed against
//! accuracy, and the least-squares line of the scaling mode.

use serde::Serialize;

/// GPU milliseconds over the timed frames.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// Median (upper median for an even count, as `measure` takes it), minimum and maximum, rounded to whole
    /// nanoseconds (timestamps resolve no finer); all 0 when empty.
    pub fn of(values: &[f64]) -> Spread {
        let mut v: Vec<f64> = values.iter().map(|ms| (ms * 1e6).round() / 1e6).collect();
        v.sort_by(f64::total_cmp);
        match (v.first(), v.last()) {
            (Some(&min), Some(&max)) => Spread {
                median: v[v.len() / 2],
                min,
                max,
            },
            _ => Spread {
                median: 0.0,
                min: 0.0,
                max: 0.0,
            },
        }
    }
}

/// Indices of the points no other point beats on both coordinates (smaller is better on both: at most equal
/// on each and smaller on one), sorted by x. Points with a non-finite coordinate are left out.
pub fn pareto_front(points: &[[f64; 2]]) -> Vec<usize> {
    let finite = |p: &[f64; 2]| p[0].is_finite() && p[1].is_finite();
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| finite(&points[i]))
        .filter(|&i| {
            let p = points[i];
            !points
                .iter()
                .any(|q| finite(q) && q[0] <= p[0] && q[1] <= p[1] && (q[0] < p[0] || q[1] < p[1]))
        })
        .collect();
    front.sort_by(|&a, &b| {
        points[a][0]
            .total_cmp(&points[b][0])
            .then(points[a][1].total_cmp(&points[b][1]))
    });
    front
}

/// Least-squares line `y = slope·x + intercept` through `points`, with R²; `None` with fewer than two distinct
/// x values.
pub fn fit_line(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if points.len() < 2 || sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_tot: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
    let ss_res: f64 = points
        .iter()
        .map(|p| (p.1 - slope * p.0 - intercept).powi(2))
        .sum();
    let r2 = if ss_tot > 0.0 { 1.0 - ss_res / ss_tot } else { 1.0 };
    Some((slope, intercept, r2))
}

/// The exponent `p` of `t ∝ n^p` fitted by least squares on `(ln n, ln t)` over the points with positive `n` and
/// `t`: 1 for a cost linear in `n` without a fixed cost, below 1 where a fixed cost weighs, near 2 for a cost
/// quadratic in `n` (e.g. a per-texel walk over each list for each of its fragments). `None` with fewer than two
/// such points of distinct `n`.
pub fn growth_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    fit_line(&logs).map(|(slope, _, _)| slope)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_line_recovers_a_line() {
        let pts: Vec<(f64, f64)> = (1..6)
            .map(|i| (i as f64 * 1000.0, 0.002 * i as f64 * 1000.0 + 0.5))
            .collect();
        let (slope, intercept, r2) = fit_line(&pts).unwrap();
        assert!(
            (slope - 0.002).abs() < 1e-12 && (intercept - 0.5).abs() < 1e-9,
            "{slope} {intercept}"
        );
        assert!((r2 - 1.0).abs() < 1e-12);
        assert_eq!(fit_line(&[(1.0, 2.0), (1.0, 3.0)]), None);
    }

    #[test]
    fn growth_exponent_reads_the_power() {
        let square: Vec<(f64, f64)> = (1..6)
            .map(|i| (i as f64 * 1e5, 3e-9 * (i as f64 * 1e5).powi(2)))
            .collect();
        assert!((growth_exponent(&square).unwrap() - 2.0).abs() < 1e-9);
        let line: Vec<(f64, f64)> = (1..6).map(|i| (i as f64 * 1e5, 2e-6 * i as f64 * 1e5)).collect();
        assert!((growth_exponent(&line).unwrap() - 1.0).abs() < 1e-9);
        assert_eq!(growth_exponent(&[(0.0, 1.0), (1.0, 0.0), (2.0, 1.0)]), None);
    }

    #[test]
    fn spread_takes_median_min_max() {
        let s = Spread::of(&[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.median, s.min, s.max), (3.0, 1.0, 10.0));
    }
}
