//! `hairlab measure fibres`: dual scattering's constants measured from the preset's fibre
//! (`measure/fibre_slab.rs`): the table of `ā_f(θ)`, `ā_b(θ)`, the slabs' forward and back light, and the fitted
//! `d_f`, `d_b`; `fibre_constants.csv` and `fibre_constants.json`, each written whole. Ctrl-C stops before the
//! next slab: the slabs measured are fitted, printed and written, and the run fails saying so (exit code 130).

use anyhow::Result;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;

use crate::measure::fibre_slab::{self, FibreConstants, Options};
use crate::settings::Settings;

#[derive(Args, Debug, Clone)]
pub struct MeasureFibresArgs {
    /// Preset: built-in name, `presets/<name>.toml`, or a path (its `render.hair_color` is the fibre's colour).
    #[arg(long, default_value = "default")]
    pub preset: String,
    /// Override any preset value, e.g. `--set render.hair_color=[0.8,0.62,0.38]` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Light particles per slab.
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub particles: u64,
    /// Slab depths in mean fibres crossed (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16,32")]
    pub depths: Vec<f32>,
    /// The light's inclinations to the fibres for the slabs, degrees (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0,30",
        allow_hyphen_values = true
    )]
    pub angles: Vec<f32>,
    /// The share of a slab's cross-section the fibres cover (0 < packing ≤ 0.4).
    #[arg(long, default_value_t = 0.25)]
    pub packing: f32,
    /// Quadrature points N of the attenuation table (N × N × 2N, and 2N for the convergence).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(2..=512))]
    pub quadrature: u32,
    /// Draws of the sampled albedo per inclination.
    #[arg(long, default_value_t = 200_000)]
    pub albedo_samples: u64,
    /// Folder for `fibre_constants.csv` and `fibre_constants.json` (created).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub fn run(a: &MeasureFibresArgs) -> Result<()> {
    let settings = Settings::load_preset(&a.preset, &a.set)?;
    if let Some(dir) = &a.out {
        crate::bench::prepare_out_dir(dir)?;
    }
    let options = Options {
        quadrature: a.quadrature as usize,
        albedo_samples: a.albedo_samples,
        angles_deg: a.angles.clone(),
        depths: a.depths.clone(),
        packing: a.packing,
        particles: a.particles,
        ..Options::default()
    };
    let mut bar = super::progress::TerminalProgress::new();
    let m = fibre_slab::measure(settings.render.hair_color, &options, &mut bar)?;
    drop(bar);
    print!("{}", report(&a.preset, &m));
    let wrote = match &a.out {
        Some(dir) => {
            let csv = dir.join("fibre_constants.csv");
            crate::io::write_atomic(
                &csv,
                crate::io::csv_text("fibre_constants.csv", m.rows())?.as_bytes(),
            )?;
            let json = dir.join("fibre_constants.json");
            crate::io::write_atomic(&json, serde_json::to_string_pretty(&m)?.as_bytes())?;
            println!("wrote {}\nwrote {}", csv.display(), json.display());
            Some(csv)
        }
        None => None,
    };
    if !m.complete {
        return Err(crate::cli::interrupt::InterruptedAt {
            done: m.slabs.len() as u64,
            unit: "slabs".to_string(),
            wrote,
        }
        .into());
    }
    Ok(())
}

fn rgb(v: [f64; 3]) -> String {
    format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2])
}

fn largest(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max)
}

/// The printed report: the table, the slabs, the fits.
pub fn report(preset: &str, m: &FibreConstants) -> String {
    let mut s = String::new();
    let n = m.quadrature;
    let _ = writeln!(
        s,
        "preset {preset}: hair colour {:?}, σ_a {:?} per radius; Chiang BSDF (render.hair_color → pathtrace::bsdf::fibre_params)",
        m.hair_color, m.sigma_a
    );
    let _ = writeln!(
        s,
        "\nā_f, ā_b (midpoint rule in γ = asin h, θ_i, φ_i; {0}×{0}×{1} points, |Δ| to {2}×{2}×{3}); albedo sampled ({4} draws, ± 1 s.e.)",
        2 * n,
        4 * n,
        n,
        2 * n,
        m.albedo_samples
    );
    let _ = writeln!(
        s,
        "{:>6} {:>7} | {:<22} | {:<22} | {:>8} | {:<22} | {:<24} | {:>8}",
        "θ°", "sin θ", "ā_f (r g b)", "ā_b", "|Δ| N→2N", "ā_f + ā_b", "sampled albedo", "eye/light ā_f − 1"
    );
    for t in &m.table {
        let sum: [f64; 3] = std::array::from_fn(|c| t.forward[c] + t.backward[c]);
        let delta = largest(t.forward, t.forward_n).max(largest(t.backward, t.backward_n));
        let gap = t.forward_eye.map_or("—".to_string(), |eye| {
            let g = (0..3)
                .map(|c| eye[c] / t.forward[c].max(1e-12) - 1.0)
                .fold(0.0, |a: f64, b| if b.abs() > a.abs() { b } else { a });
            format!("{g:+.4}")
        });
        let se = t.sampled_error.iter().copied().fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "{:>6.1} {:>7.3} | {} | {} | {:>8.1e} | {} | {} ±{:.4} | {:>8}",
            f64::from(t.sin_theta).asin().to_degrees(),
            t.sin_theta,
            rgb(t.forward),
            rgb(t.backward),
            delta,
            rgb(sum),
            rgb(t.sampled),
            se,
            gap
        );
    }
    let _ = writeln!(
        s,
        "\nslabs of parallel fibres (packing {}, period {} widths); n = mean fibres crossed; light particles",
        m.packing, m.period
    );
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>6} {:>7} | {:<20} {:>6} | {:<20} | {:<20} | {:<20} | {:<20}",
        "θ°",
        "n",
        "fibres",
        "depth",
        "T(n) forward",
        "± s.e.",
        "unscattered",
        format!("beyond {} events", crate::measure::fibre_slab::slab::TRUTH_DEPTH),
        "R(n) back",
        "R after > 1 event"
    );
    for r in &m.slabs {
        let t = &r.transport;
        let _ = writeln!(
            s,
            "{:>5.1} {:>6.2} {:>6} {:>7.1} | {} {:>6.4} | {} | {} | {} | {}",
            r.theta_deg,
            r.fibres_crossed,
            r.fibres,
            r.depth,
            rgb(t.forward),
            t.forward_error.iter().copied().fold(0.0, f64::max),
            rgb(t.forward_direct),
            rgb(t.forward_beyond_truth_depth),
            rgb(t.back),
            rgb(t.back_multiple)
        );
    }
    if let Some(r) = m.slabs.first() {
        let _ = writeln!(s, "({} particles a slab)", r.transport.samples);
    }
    let _ = writeln!(
        s,
        "\nfits (hairlab's dual scattering: T_f = d_f ā_f^n; back-scattering after > 1 event d_b A_b, A_b from ā_f, ā_b)"
    );
    for f in &m.fits {
        fits(&mut s, f.theta_deg, &f.fits);
    }
    let _ = writeln!(
        s,
        "in use: render.hair_model = fibres  d_f = {}, d_b = {} (shading::fibre_transport, from these fits)\n        \
         render.hair_model = absorber  d_f = {}, d_b = {} (shading::dual_scattering; Zinke et al. 2008 and Unity HDRP \
         use 0.7)",
        crate::shading::fibre_transport::DENSITY_FORWARD,
        crate::shading::fibre_transport::DENSITY_BACK,
        crate::shading::dual_scattering::DENSITY_FORWARD,
        crate::shading::dual_scattering::DENSITY_BACK
    );
    s
}

/// The fits at one inclination.
fn fits(s: &mut String, deg: f32, x: &crate::measure::fibre_slab::Fits) {
    let _ = writeln!(
        s,
        "θ = {deg:>4.1}°: ā_f {}  ā_b {}  A_b {}",
        rgb(x.forward),
        rgb(x.backward),
        rgb(x.back_energy)
    );
    match x.d_f {
        Some(f) => {
            let _ = writeln!(
                s,
                "  d_f = {:.3} (residual {:.3} of the light, over {} points × channels)",
                f.scale, f.residual, f.points
            );
        }
        None => s.push_str("  d_f: no slab\n"),
    }
    if let [Some(r), Some(g), Some(b)] = x.free {
        let _ = writeln!(
            s,
            "  free fit T = d a^n: d {:.3} {:.3} {:.3}, a {:.4} {:.4} {:.4} (residual {:.3} {:.3} {:.3})",
            r.d, g.d, b.d, r.a, g.a, b.a, r.residual, g.residual, b.residual
        );
    }
    match x.d_b {
        Some(f) => {
            let _ = writeln!(
                s,
                "  d_b = {:.3} (residual {:.3} of the light, over {} points × channels, the deeper half of the slabs)",
                f.scale, f.residual, f.points
            );
        }
        None => s.push_str("  d_b: no slab\n"),
    }
}
