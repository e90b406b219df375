//! The synthetic texel lab: one texel's fragments made up without a scene, to compare the methods' CPU models on
//! the papers' texel experiments. Either a mixture of `Q` Gaussians along the light ray (Mertens et al. 2004 §5,
//! Fig. 5: "random depth values between 0 and 1 using a mix of Q gaussian distributions with a random mean and
//! variance", `Q = K` against `Q > K`), or fragments typed in as `depth,alpha` lines, the format of
//! `hairlab curve --fragments`. [`LabSettings::ui`] draws its controls in the inspector window.

use crate::rng::SplitMix64;
use crate::visibility::Fragment;

/// Largest number of Gaussians.
pub const MAX_GAUSSIANS: u32 = 32;
/// Largest number of fragments per Gaussian.
pub const MAX_PER_GAUSSIAN: u32 = 500;
/// Largest spread (the largest standard deviation a Gaussian may draw), in normalised light depth.
pub const MAX_SPREAD: f32 = 0.25;
/// XORed into the lab seed, so the lab does not share the first stream of a generator seeded alike.
const SEED_SALT: u64 = 0x5EED_1AB0_7E8E_1000;

/// Where the lab's fragments come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LabSource {
    /// A mixture of Gaussians ([`gaussian_mixture`]).
    #[default]
    Gaussians,
    /// `depth,alpha` lines typed into [`LabSettings::text`].
    Typed,
}

/// The lab's inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct LabSettings {
    pub source: LabSource,
    /// Number of Gaussians `Q` (1..=[`MAX_GAUSSIANS`]).
    pub gaussians: u32,
    /// Fragments drawn from each Gaussian (1..=[`MAX_PER_GAUSSIAN`]).
    pub per_gaussian: u32,
    /// Each Gaussian's standard deviation is drawn uniformly from `[spread / 4, spread]`.
    pub spread: f32,
    /// Opacity of every fragment.
    pub alpha: f32,
    pub seed: u64,
    /// Typed `depth,alpha` lines.
    pub text: String,
}

impl Default for LabSettings {
    /// Four Gaussians of 25 fragments: the 100 fragments of Mertens et al.'s simulation, with `Q = K = 4`.
    fn default() -> Self {
        Self {
            source: LabSource::Gaussians,
            gaussians: 4,
            per_gaussian: 25,
            spread: 0.04,
            alpha: 0.05,
            seed: 1,
            text: "# depth,alpha\n0.20,0.3\n0.22,0.3\n0.25,0.3\n0.60,0.5\n0.62,0.5\n0.90,0.2\n".to_string(),
        }
    }
}

impl LabSettings {
    /// The lab's fragment list, or why the typed text cannot be read.
    pub fn fragments(&self) -> Result<Vec<Fragment>, String> {
        match self.source {
            LabSource::Gaussians => Ok(gaussian_mixture(
                self.gaussians,
                self.per_gaussian,
                self.spread,
                self.alpha,
                self.seed,
            )),
            LabSource::Typed => {
                crate::cli::parse_fragments_csv(&self.text, "typed fragments").map_err(|e| format!("{e:#}"))
            }
        }
    }

    /// The uniform hair alpha the occupancy model assumes for these fragments: the lab's alpha for Gaussians,
    /// the mean alpha of typed fragments (as `hairlab curve` does).
    pub fn hair_alpha(&self, fragments: &[Fragment]) -> f32 {
        match self.source {
            LabSource::Gaussians => self.alpha,
            LabSource::Typed if fragments.is_empty() => 0.5,
            LabSource::Typed => fragments.iter().map(|f| f.alpha).sum::<f32>() / fragments.len() as f32,
        }
    }

    /// A short description for legends and pins.
    pub fn label(&self) -> String {
        match self.source {
            LabSource::Gaussians => format!(
                "Q={} ×{} σ≤{} α={} seed {}",
                self.gaussians, self.per_gaussian, self.spread, self.alpha, self.seed
            ),
            LabSource::Typed => "typed fragments".to_string(),
        }
    }

    /// The lab's controls (the window's "Synthetic texel" part); `error`: why the typed text cannot be read.
    pub fn ui(&mut self, ui: &mut egui::Ui, error: Option<&str>) {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.source, LabSource::Gaussians, "Gaussian mixture");
            ui.selectable_value(&mut self.source, LabSource::Typed, "Typed fragments");
        });
        match self.source {
            LabSource::Gaussians => {
                egui::Grid::new("lab").num_columns(4).show(ui, |ui| {
                    let l = ui.label("Gaussians Q");
                    ui.add(egui::Slider::new(&mut self.gaussians, 1..=MAX_GAUSSIANS))
                        .labelled_by(l.id);
                    let l = ui.label("per Gaussian");
                    ui.add(egui::DragValue::new(&mut self.per_gaussian).range(1..=MAX_PER_GAUSSIAN))
                        .labelled_by(l.id);
                    ui.end_row();
                    let l = ui.label("spread σ");
                    ui.add(egui::Slider::new(&mut self.spread, 0.0..=MAX_SPREAD))
                        .labelled_by(l.id)
                        .on_hover_text("each Gaussian's standard deviation is drawn from [σ/4, σ]");
                    let l = ui.label("alpha");
                    ui.add(egui::Slider::new(&mut self.alpha, 0.01..=0.99).logarithmic(true))
                        .labelled_by(l.id);
                    ui.end_row();
                    row(ui, "seed", egui::DragValue::new(&mut self.seed));
                });
                ui.weak("means uniform in [0.1, 0.9] (Mertens et al. 2004, Fig. 5: Q Gaussians against K clusters)");
            }
            LabSource::Typed => {
                let l = ui.label("fragments, one `depth,alpha` per line (as `hairlab curve --fragments`)");
                ui.add(
                    egui::TextEdit::multiline(&mut self.text)
                        .desired_rows(5)
                        .code_editor()
                        .hint_text("0.25,0.3"),
                )
                .labelled_by(l.id);
            }
        }
        if let Some(e) = error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
    }
}

/// One labelled grid row; the label names the widget for screen readers.
fn row(ui: &mut egui::Ui, label: &str, widget: impl egui::Widget) -> egui::Response {
    let l = ui.label(label);
    let r = ui.add(widget).labelled_by(l.id);
    ui.end_row();
    r
}

/// `gaussians` Gaussians with means uniform in `[0.1, 0.9]` and standard deviations uniform in
/// `[spread / 4, spread]`, `per_gaussian` fragments of opacity `alpha` drawn from each, depths clamped to
/// `[0, 1]`. Deterministic in `seed`; the counts are clamped to their maxima, spread and alpha to their ranges.
pub fn gaussian_mixture(
    gaussians: u32,
    per_gaussian: u32,
    spread: f32,
    alpha: f32,
    seed: u64,
) -> Vec<Fragment> {
    let q = gaussians.clamp(1, MAX_GAUSSIANS);
    let n = per_gaussian.clamp(1, MAX_PER_GAUSSIAN);
    let spread = if spread.is_finite() {
        spread.clamp(0.0, MAX_SPREAD)
    } else {
        0.0
    };
    let alpha = if alpha.is_finite() {
        alpha.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut rng = SplitMix64::new(seed ^ SEED_SALT);
    let mut out = Vec::with_capacity((q * n) as usize);
    for _ in 0..q {
        let mean = 0.1 + 0.8 * rng.unit();
        let sigma = spread * (0.25 + 0.75 * rng.unit());
        for _ in 0..n {
            out.push(Fragment::new(
                (mean + sigma * rng.normal()).clamp(0.0, 1.0),
                alpha,
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::DcParams;
    use crate::visibility::metrics::{DEFAULT_GRID_POINTS, texel_error};

    #[test]
    fn mixture_is_deterministic_and_in_range() {
        let a = gaussian_mixture(4, 25, 0.05, 0.3, 7);
        assert_eq!(a.len(), 100);
        assert_eq!(a, gaussian_mixture(4, 25, 0.05, 0.3, 7));
        assert_ne!(a, gaussian_mixture(4, 25, 0.05, 0.3, 8));
        assert!(a.iter().all(|f| (0.0..=1.0).contains(&f.depth) && f.alpha == 0.3));
        // Zero spread: every fragment of a Gaussian sits at its mean, so there are exactly Q distinct depths.
        let mut d: Vec<f32> = gaussian_mixture(3, 10, 0.0, 0.5, 1)
            .iter()
            .map(|f| f.depth)
            .collect();
        d.sort_by(f32::total_cmp);
        d.dedup();
        assert_eq!(d.len(), 3);
        assert!(d.iter().all(|z| (0.1..=0.9).contains(z)));
        // Clamped inputs never panic or leave the ranges.
        let c = gaussian_mixture(0, 10_000, f32::NAN, 7.0, 0);
        assert_eq!(c.len(), MAX_PER_GAUSSIAN as usize);
        assert!(c.iter().all(|f| f.alpha == 1.0));
    }

    #[test]
    fn more_gaussians_than_clusters_break_density_clustering() {
        // Mertens et al. Fig. 5: with Q > K the 4-means histogram breaks down. Averaged over seeds, 8 Gaussians
        // give DC-4 a larger texel error than 2 do (same fragment count, 100).
        let dc = DcParams { clusters: 4 };
        let mean_error = |q: u32| {
            (1..=20u64)
                .map(|seed| {
                    let f = gaussian_mixture(q, 100 / q, 0.03, 0.05, seed);
                    texel_error(&dc, &f, DEFAULT_GRID_POINTS).unwrap().mean
                })
                .sum::<f32>()
                / 20.0
        };
        let (two, eight) = (mean_error(2), mean_error(8));
        assert!(eight > two, "Q=8: {eight}, Q=2: {two}");
    }

    #[test]
    fn typed_fragments_use_the_curve_parser() {
        let mut lab = LabSettings {
            source: LabSource::Typed,
            text: "depth,alpha\n0.5,0.25\n\n# note\n0.7,0.75\n".into(),
            ..Default::default()
        };
        let f = lab.fragments().unwrap();
        assert_eq!(f, [Fragment::new(0.5, 0.25), Fragment::new(0.7, 0.75)]);
        assert_eq!(lab.hair_alpha(&f), 0.5);
        lab.text = "0.5,0.25\n0.7;0.75\n".into();
        let e = lab.fragments().unwrap_err();
        assert!(e.contains("typed fragments:2"), "{e}");
        lab.text = "# depth,alpha\n".into();
        let e = lab.fragments().unwrap_err();
        assert!(e.contains("typed fragments: no fragments"), "{e}");
        // The default text: a comment, then rows.
        let default = LabSettings {
            source: LabSource::Typed,
            ..Default::default()
        };
        assert_eq!(default.fragments().unwrap().len(), 6);
    }
}
