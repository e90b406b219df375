//! `measure fibres` (`measure::fibre_slab`): the attenuations by quadrature against an independent sampled
//! estimate, the slab's transport (a light fibre passes more than a dark one, less light gets through a deeper
//! slab) and the fits on synthetic data. Small on purpose: the crate is not optimised in dev builds.

use glam::Vec3;
use hairlab::measure::fibre_slab::slab::{Slab, SlabSpec};
use hairlab::measure::fibre_slab::{
    Fixed, attenuation, back_energy, fit_exponential, fit_scale, sampled_albedo,
};
use hairlab::pathtrace::bsdf::fibre_params;

const DARK: [f32; 3] = [0.30, 0.18, 0.09];
const BLOND: [f32; 3] = [0.80, 0.62, 0.38];

/// ā_f + ā_b by the midpoint rule (40 × 40 × 80 points) equals the albedo by sampling `FibreBsdf::sample`
/// (100 000 draws, standard error ≤ 4e-4), and so does each hemisphere apart, within 0.003 per channel, for the
/// dark and the blond fibre at θ = −30°, 0°, 30° (measured: 0.0008 at most).
#[test]
fn quadrature_matches_sampled_albedo() {
    let mut worst = 0.0f64;
    for colour in [DARK, BLOND] {
        let fibre = fibre_params(colour);
        for s in [-0.5f32, 0.0, 0.5] {
            let q = attenuation(&fibre, s, 40, Fixed::Light);
            let (m, err) = sampled_albedo(&fibre, s, 100_000, 9);
            assert!(err.max_element() <= 4e-4, "{err}");
            for (a, b) in [
                (q.forward + q.backward, m.forward + m.backward),
                (q.forward, m.forward),
                (q.backward, m.backward),
            ] {
                let d = (a - b).abs().max_element();
                worst = worst.max(d);
                assert!(
                    d <= 0.003,
                    "colour {colour:?}, sin θ {s}: quadrature {a} vs sampled {b}"
                );
            }
        }
    }
    println!("quadrature vs sampled albedo: largest difference {worst:.4}");
}

fn slab(n: f32) -> Slab {
    Slab::new(&SlabSpec {
        fibres_crossed: n,
        packing: 0.25,
        period: 8.0,
        seed: 3,
    })
    .unwrap()
}

/// Through the same slab (n = 2) with the same particles (600), a white fibre (colour 0.95, the preset's
/// roughness) passes more light forward than the dark one in every channel, by more than 4 standard errors of
/// the difference; the white slab loses little (T + R ≥ 0.9).
#[test]
fn white_fibre_transmits_more_than_dark() {
    let s = slab(2.0);
    let white = s.trace(&fibre_params([0.95; 3]), 0.0, 600, 5);
    let dark = s.trace(&fibre_params(DARK), 0.0, 600, 5);
    let (tw, td) = (white.forward(), dark.forward());
    let margin = 4.0 * (white.forward_error() + dark.forward_error());
    println!("n = 2: white T {tw}, dark T {td}, 4 s.e. {margin}");
    assert!((tw - td).cmpgt(margin).all(), "white {tw} dark {td}");
    assert!((tw + white.back()).min_element() >= 0.9, "{tw} {}", white.back());
}

/// The blond slab's forward light falls with depth (n = 1, 3, 6; 1500 particles each), each step by more than
/// 3 standard errors in every channel, and the unscattered part falls to below 1 % by n = 6.
#[test]
fn forward_transmittance_falls_with_depth() {
    let fibre = fibre_params(BLOND);
    let t: Vec<_> = [1.0, 3.0, 6.0]
        .iter()
        .map(|&n| slab(n).trace(&fibre, 0.25, 1500, 7))
        .collect();
    for w in t.windows(2) {
        let margin = 3.0 * (w[0].forward_error() + w[1].forward_error());
        println!("T {} → {} (3 s.e. {margin})", w[0].forward(), w[1].forward());
        assert!((w[0].forward() - w[1].forward()).cmpgt(margin).all());
    }
    assert!(
        t[2].forward_part(0).max_element() < 0.01,
        "{}",
        t[2].forward_part(0)
    );
}

/// The fits recover known constants: `0.63 · 0.87^n` at n = 1, 2, 4, …, 32 gives `d = 0.63` (1e-9) with a zero
/// residual against the model `0.87^n`, and the free fit gives `d = 0.63`, `a = 0.87`; with ±2 % alternating
/// noise the scale stays within 1 % and the residual (a share of the light) lies in [0.015, 0.02] (the noise's
/// share, less what the scale absorbs). `A_b` at ā_f = 0.8, ā_b = 0.1 is
/// 0.1 · 0.64 / 0.36 + 0.001 · 0.64 / 0.36³ = 0.191495 (worked by hand).
#[test]
fn fit_recovers_known_constants() {
    let ns: Vec<f64> = (0..6).map(|k| f64::from(1 << k)).collect();
    let model = |n: f64| [0.87f64.powf(n), 0.8f64.powf(n), 0.6f64.powf(n)];
    let clean: Vec<([f64; 3], [f64; 3])> = ns
        .iter()
        .map(|&n| (model(n).map(|v| 0.63 * v), model(n)))
        .collect();
    let f = fit_scale(&clean).unwrap();
    assert!((f.scale - 0.63).abs() < 1e-9 && f.residual < 1e-9, "{f:?}");
    assert_eq!(f.points, 18);
    let e = fit_exponential(
        &ns.iter()
            .map(|&n| (n, 0.63 * 0.87f64.powf(n)))
            .collect::<Vec<_>>(),
    )
    .unwrap();
    assert!(
        (e.d - 0.63).abs() < 1e-9 && (e.a - 0.87).abs() < 1e-9 && e.residual < 1e-9,
        "{e:?}"
    );
    let noisy: Vec<([f64; 3], [f64; 3])> = clean
        .iter()
        .enumerate()
        .map(|(i, (m, model))| (m.map(|v| v * if i % 2 == 0 { 1.02 } else { 0.98 }), *model))
        .collect();
    let f = fit_scale(&noisy).unwrap();
    assert!((f.scale / 0.63 - 1.0).abs() < 0.01, "{f:?}");
    println!("noisy fit: {f:?}");
    assert!((0.015..=0.02).contains(&f.residual), "{f:?}");
    assert!(fit_scale(&[([1.0; 3], [0.0; 3])]).is_none());
    assert!((back_energy(0.8, 0.1) - 0.191495).abs() < 1e-6);
}

/// The slab crosses as many fibres as it says: straight rays at right angles through a generated slab meet on
/// average `n` fibres, measured by counting the unscattered light of a fibre that stops everything it meets
/// (opaque black: `T` is the share of lines that miss every fibre, which for non-overlapping fibres of the
/// stated count is below the Poisson `e^-n` and above 0).
#[test]
fn slab_depth_matches_its_count() {
    for n in [1.0f32, 2.0] {
        let s = slab(n);
        assert_eq!(s.fibres, (n * 8.0) as usize);
        assert!((s.fibres_crossed() - n).abs() < 1e-6);
        // N fibres of width 1 in a period of 8 at packing 0.25: depth N / (8 ρ), ρ = 0.25 · 4 / π.
        let rho = 0.25 * 4.0 / std::f32::consts::PI;
        assert!((s.depth - s.fibres as f32 / (8.0 * rho)).abs() < 1e-4);
        let black = hairlab::pathtrace::bsdf::FibreParams::from_colour(Vec3::splat(1e-3), 0.3, 0.3, 0.0);
        let t = s.trace(&black, 0.0, 2000, 11);
        let direct = t.forward_part(0).x;
        println!("n = {n}: unscattered {direct}, e^-n {}", (-n).exp());
        assert!(direct > 0.0 && direct < f64::from((-n).exp()) + 3.0 * t.forward_error().x);
    }
}

/// `hairlab measure fibres` with tiny settings prints the table and the fits and writes both files: the CSV
/// has a row per figure (17 × 5 table rows: a_f, a_b at N and 2N and the sampled albedo, and the eye's a_f, a_b
/// at the 15 inclinations short of grazing; 5 per slab; A_b, d_f, d_b, free d and a), the JSON every slab. A bad
/// packing fails with one error naming it, before anything is measured.
#[test]
fn cli_writes_the_constants() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args = [
        "measure",
        "fibres",
        "--preset",
        "blond",
        "--quadrature",
        "4",
        "--albedo-samples",
        "200",
        "--particles",
        "100",
        "--depths",
        "1,2",
        "--angles",
        "0",
        "--out",
        out,
    ];
    let o = crate::common::cli::hairlab(&args);
    assert!(o.status.success(), "{}", crate::common::cli::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("d_f = ") && text.contains("d_b = "), "{text}");
    let csv = std::fs::read_to_string(dir.path().join("fibre_constants.csv")).unwrap();
    assert!(
        csv.starts_with("quantity,sin_theta,fibres_crossed,r,g,b,error,samples\n"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 1 + 17 * 5 + 15 * 2 + 2 * 5 + 5, "{csv}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("fibre_constants.json")).unwrap())
            .unwrap();
    assert_eq!(json["slabs"].as_array().unwrap().len(), 2);
    assert_eq!(json["complete"], true);
    let bad = crate::common::cli::hairlab(&["measure", "fibres", "--packing", "0.6"]);
    crate::common::cli::assert_fails(&bad, &["packing 0.6"]);
}

/// A progress that answers `false` once the first slab has begun stops the run after it: one slab measured,
/// fitted, `complete` false (the CLI's Ctrl-C answers its bar so).
#[test]
fn a_stop_keeps_the_slabs_measured() {
    use hairlab::measure::fibre_slab::{Options, measure};
    let o = Options {
        quadrature: 4,
        albedo_samples: 100,
        angles_deg: vec![0.0],
        depths: vec![1.0, 2.0, 4.0],
        particles: 50,
        ..Options::default()
    };
    let mut slabs_begun = 0;
    let mut stop = |label: &str, _: f32| {
        if label.starts_with("slab") {
            slabs_begun += 1;
        }
        slabs_begun <= 1
    };
    let m = measure(BLOND, &o, &mut stop).unwrap();
    assert_eq!(m.table.len(), 17);
    assert_eq!(m.slabs.len(), 1);
    assert!(!m.complete);
    assert!(m.fits[0].fits.d_f.is_some());
}

/// `shading::fibre_transport::TABLE` (quadrature 128) is `attenuation` on its grid: three rows recomputed at
/// quadrature 64 agree within 3e-4 (measured 64 against 128 over every interior node: 1.1e-4); and its bilinear
/// lookup between the nodes stays within 0.01 of the quadrature at the presets' own absorptions (`default`,
/// `blond`) and inclinations off the nodes.
#[test]
fn fibre_transport_table_is_the_quadrature() {
    use hairlab::pathtrace::bsdf::fibre_absorbing as fibre;
    use hairlab::shading::{fibre_transport, marschner};
    let mut worst = 0.0f32;
    for k in [3usize, 8, 13] {
        for first in (0..fibre_transport::ABSORPTION_NODES).step_by(3) {
            let j = |c: usize| (first + c).min(fibre_transport::ABSORPTION_NODES - 1);
            let sigma = Vec3::new(
                fibre_transport::node_sigma(j(0)),
                fibre_transport::node_sigma(j(1)),
                fibre_transport::node_sigma(j(2)),
            );
            let h = attenuation(
                &fibre(sigma),
                fibre_transport::quadrature_sin(k),
                64,
                Fixed::Light,
            );
            for c in 0..3 {
                let want = fibre_transport::TABLE[k][j(c)];
                for (got, w) in [(h.forward[c] as f32, want[0]), (h.backward[c] as f32, want[1])] {
                    worst = worst.max((got - w).abs());
                    assert!((got - w).abs() <= 3e-4, "node ({k}, {}): {got} vs {w}", j(c));
                }
            }
        }
    }
    let mut worst_lookup = 0.0f32;
    for colour in [DARK, BLOND] {
        let sigma = marschner::absorption(Vec3::from(colour));
        for s in [-0.3f32, 0.1, 0.45] {
            let h = attenuation(&fibre(sigma), s, 64, Fixed::Light);
            let (f, b) = fibre_transport::attenuation(s, sigma);
            let d = (f - h.forward.as_vec3())
                .abs()
                .max((b - h.backward.as_vec3()).abs())
                .max_element();
            worst_lookup = worst_lookup.max(d);
            assert!(
                d <= 0.01,
                "{colour:?} at sin θ {s}: lookup {f} {b}, quadrature {} {}",
                h.forward,
                h.backward
            );
        }
    }
    println!(
        "fibre transport table: rows at quadrature 64 within {worst:.1e}; lookup within {worst_lookup:.1e}"
    );
}
