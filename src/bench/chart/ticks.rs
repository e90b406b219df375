//! The charts' axis ranges and ticks: decades with 1-2-5 labels on a logarithmic axis, round steps on a linear one.

use super::Tick;

pub(super) fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// `v` with `decimals` decimals.
fn fmt_fixed(v: f64, decimals: i32) -> String {
    format!("{v:.*}", decimals.max(0) as usize)
}

/// Ticks at log10 of 1..9 × 10^k inside `lo..=hi` (plot coordinates, decades).
pub(super) fn log_ticks(lo: f64, hi: f64) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return Vec::new();
    }
    let few = hi - lo <= 2.5;
    let values: Vec<(i32, i32)> = (lo.floor() as i32..=hi.ceil() as i32)
        .flat_map(|k| (1..10).map(move |m| (m, k)))
        .filter(|&(m, k)| {
            let at = (m as f64 * 10f64.powi(k)).log10();
            at >= lo - 1e-9 && at <= hi + 1e-9
        })
        .collect();
    let labelled = |m: i32| m == 1 || (few && (m == 2 || m == 5));
    // Under a decade the 1-2-5 steps may leave fewer than three labels: then every tick has one.
    let all = values.iter().filter(|(m, _)| labelled(*m)).count() < 3;
    values
        .into_iter()
        .map(|(m, k)| {
            let v = m as f64 * 10f64.powi(k);
            Tick {
                at: v.log10(),
                label: (all || labelled(m)).then(|| fmt_fixed(v, -k)),
            }
        })
        .collect()
}

/// A 1-2-5 step giving about `target` intervals over `span`, and its decimal exponent.
fn nice_step(span: f64, target: f64) -> (f64, i32) {
    let raw = (span / target).max(f64::MIN_POSITIVE);
    let e = raw.log10().floor() as i32;
    let base = 10f64.powi(e);
    let m = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| m * base >= raw)
        .unwrap_or(10.0);
    if m == 10.0 {
        (base * 10.0, e + 1)
    } else {
        (m * base, e)
    }
}

/// Labelled ticks at a 1-2-5 step (about 8 intervals) inside `lo..=hi`.
pub(super) fn linear_ticks(lo: f64, hi: f64) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite()) || lo >= hi {
        return Vec::new();
    }
    let (step, e) = nice_step(hi - lo, 8.0);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|i| {
            let v = i as f64 * step;
            Tick {
                at: v,
                label: Some(if i == 0 { "0".to_string() } else { fmt_fixed(v, -e) }),
            }
        })
        .collect()
}

/// A linear range from `min(0, lo)` to a tick at or above `hi`, and its ticks.
pub(super) fn linear_range(lo: f64, hi: f64) -> (f64, f64, Vec<Tick>) {
    let lo = if lo.is_finite() { lo.min(0.0) } else { 0.0 };
    let hi = if hi.is_finite() && hi > lo { hi } else { lo + 1.0 };
    let (step, _) = nice_step(hi - lo, 8.0);
    let top = (hi / step).ceil() * step;
    let bottom = (lo / step).floor() * step;
    (bottom, top, linear_ticks(bottom, top))
}

/// A logarithmic range from the largest m × 10^k (m = 1..9, a tick) below `lo` to the smallest above `hi`
/// (positive), with a little room on both sides: the axis spans the data, not the decades around them.
pub(super) fn log_range(lo: f64, hi: f64) -> (f64, f64) {
    let ticks = |k: i32| (1..10).map(move |m| m as f64 * 10f64.powi(k));
    let (lo, hi) = (lo / 1.15, hi * 1.15);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let below = (k0..=k0 + 1)
        .flat_map(ticks)
        .filter(|v| *v <= lo)
        .fold(10f64.powi(k0), f64::max);
    let above = (k1 - 1..=k1)
        .flat_map(ticks)
        .filter(|v| *v >= hi)
        .fold(10f64.powi(k1), f64::min);
    (below, above.max(below * 2.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_label_decades() {
        let t = log_ticks(-1.0, 2.0);
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
        assert_eq!(t.len(), 28);
        let few: Vec<_> = log_ticks(0.0, 1.0).into_iter().filter_map(|t| t.label).collect();
        assert_eq!(few, ["1", "2", "5", "10"]);
        // 400 k .. 3 M (the scaling chart's 0.5 M .. 2 M): 1-2-5 would label 500 k, 1 M and 2 M.
        let (lo, hi) = log_range(5e5, 2e6);
        assert_eq!((lo, hi), (4e5, 3e6));
        let scaling: Vec<_> = log_ticks(lo.log10(), hi.log10())
            .into_iter()
            .filter_map(|t| t.label)
            .collect();
        assert_eq!(scaling, ["500000", "1000000", "2000000"]);
        // Within a decade with one 1-2-5 value, every tick is labelled.
        let (lo, hi) = log_range(3.5e5, 7e5);
        assert_eq!((lo, hi), (3e5, 9e5));
        let narrow: Vec<_> = log_ticks(lo.log10(), hi.log10())
            .into_iter()
            .filter_map(|t| t.label)
            .collect();
        assert_eq!(
            narrow,
            [
                "300000", "400000", "500000", "600000", "700000", "800000", "900000"
            ]
        );
    }

    #[test]
    fn linear_range_ends_on_ticks() {
        let (lo, hi, t) = linear_range(0.0, 0.27);
        assert_eq!(lo, 0.0);
        assert!((hi - 0.3).abs() < 1e-12, "{hi}");
        let labels: Vec<_> = t.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0", "0.05", "0.10", "0.15", "0.20", "0.25", "0.30"]);
    }
}
