//! The strand shading models on the GPU: `shaders/common/marschner.wgsl`, composed by the project's shader
//! preprocessor, against its CPU model (`hairlab::shading::marschner`) through a probe compute pass; and the eye
//! pass under `render.shading = marschner` with every shadow method and every transparency technique.

use crate::common;
use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::render::Renderer;
use hairlab::render::transparency::registry as techniques;
use hairlab::rng::SplitMix64;
use hairlab::settings::Settings;
use hairlab::shading::{HairModel, ShadingModel, dual_scattering, fibre_transport, marschner};
use hairlab::visibility::count_from_visibility;

/// GPU = CPU tolerance on each lobe value `s`: `|s_gpu − s_cpu| ≤ ABS_TOL + REL_TOL · |s_cpu|`. The lobes
/// reach ~2 (TT's peak); the TRT lobe's `exp(17 cos φ − 16.78)` turns an ulp of `cos φ` into ~1e-6 relative,
/// and Vulkan allows `exp` 3 + 2|x| ulps. The model avoids `asin`, `sin` and `cos`, which Vulkan lets drift by
/// thousands of ulps (the Gaussians' widths and centres are literals, `cos θ_d` is taken through square roots).
/// Measured on lavapipe (printed by the test): max |Δ| = 7.2e-7, max relative 9.4e-7 over 4270 directions.
const ABS_TOL: f32 = 2e-6;
const REL_TOL: f32 = 1e-5;

/// The probe rows of the shading models' tests ([`probe_rows`]): a tangent, the directions to the light and the
/// eye, a colour (each a `vec4`, w unused); one `vec4` out per value.
pub(crate) const ROW: &str = r#"
struct Row {
    tangent: vec4<f32>,
    to_light: vec4<f32>,
    to_eye: vec4<f32>,
    colour: vec4<f32>,
}
alias Out = vec4<f32>;
"#;

/// Per probe: the lobes of [`marschner::lobes`] with the absorption of the colour, the summed shading and the
/// absorption itself.
const PROBE: &str = r#"

fn probe(i: u32, p: Row) {
    let sigma_a = marschner_absorption(p.colour.rgb);
    let s = marschner_lobes(p.tangent.xyz, p.to_light.xyz, p.to_eye.xyz, sigma_a);
    out[4u * i] = vec4<f32>(s.r, s.tt);
    out[4u * i + 1u] = vec4<f32>(s.trt, 0.0);
    out[4u * i + 2u] = vec4<f32>(marschner(p.tangent.xyz, p.to_light.xyz, p.to_eye.xyz, p.colour.rgb), 0.0);
    out[4u * i + 3u] = vec4<f32>(sigma_a, 0.0);
}
"#;

/// Runs the probe on `(tangent, to_light, to_eye, colour)` rows; returns 16 floats per row.
fn probe(gpu: &Gpu, rows: &[[Vec3; 4]]) -> Vec<[f32; 16]> {
    let packed: Vec<[f32; 4]> = rows.iter().flatten().map(|v| v.extend(0.0).to_array()).collect();
    let bytes = common::run_probe(
        gpu,
        ("common/marschner.wgsl", &format!("{ROW}{PROBE}"), "shading.probe"),
        bytemuck::cast_slice(&packed),
        rows.len(),
        64,
    );
    bytemuck::pod_collect_to_vec(&bytes)
}

/// The probe directions: 4096 random triples (tangent, light, eye) with random colours; the lobes' peaks in
/// the plane of incidence and straight behind (φ = 0 and π at the shifted specular angles, white, brown and
/// black hair); and the degenerate cases (light or eye along the tangent, light = eye, light = −eye).
pub(crate) fn probe_rows() -> Vec<[Vec3; 4]> {
    let mut rng = SplitMix64::new(17);
    let unit = |rng: &mut SplitMix64| {
        Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::Y)
    };
    let mut rows = Vec::new();
    for _ in 0..4096 {
        let (t, l, v) = (unit(&mut rng), unit(&mut rng), unit(&mut rng));
        let c = Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        rows.push([t, l, v, c]);
    }
    let dir = |theta: f32, phi: f32| Vec3::new(theta.cos() * phi.cos(), theta.cos() * phi.sin(), theta.sin());
    let colours = [Vec3::ONE, Vec3::new(0.30, 0.18, 0.09), Vec3::ZERO];
    for deg in (-80..=80).step_by(10) {
        let theta = (deg as f32).to_radians();
        for (p, phi) in [(0, 0.0), (1, std::f32::consts::PI), (2, 0.0)] {
            let theta_o = -theta + 2.0 * marschner::ALPHA[p];
            for c in colours {
                rows.push([Vec3::Z, dir(theta, 0.0), dir(theta_o, phi), c]);
            }
        }
    }
    for c in colours {
        for (l, v) in [
            (Vec3::Z, Vec3::X),
            (Vec3::X, -Vec3::Z),
            (Vec3::Z, Vec3::Z),
            (Vec3::X, Vec3::X),
            (Vec3::X, -Vec3::X),
            (dir(0.4, 1.0), dir(0.4, 1.0)),
            (dir(0.4, 1.0), -dir(0.4, 1.0)),
        ] {
            rows.push([Vec3::Z, l, v, c]);
        }
    }
    rows
}

/// Checks each probe row's GPU values against the CPU model's, `values(row)` giving both in the same order: both
/// finite, `|gpu − cpu| ≤ abs_tol + rel_tol · |cpu|`. Prints the largest absolute and relative (values > 1e-3)
/// differences under `name` and returns the largest CPU value.
pub(crate) fn assert_gpu_equals_cpu(
    name: &str,
    rows: &[[Vec3; 4]],
    (abs_tol, rel_tol): (f32, f32),
    values: impl Fn(usize) -> (Vec<f32>, Vec<f32>),
) -> f32 {
    let (mut worst_rel, mut worst_abs, mut peak) = (0.0f32, 0.0f32, 0.0f32);
    for (r, row) in rows.iter().enumerate() {
        let (got, expected) = values(r);
        assert_eq!(got.len(), expected.len());
        for (k, (g, e)) in got.into_iter().zip(expected).enumerate() {
            assert!(
                g.is_finite() && e.is_finite(),
                "{name}: row {row:?} value {k}: GPU {g}, CPU {e}"
            );
            let d = (g - e).abs();
            assert!(
                d <= abs_tol + rel_tol * e.abs(),
                "{name}: row {row:?} value {k}: GPU {g}, CPU {e}"
            );
            worst_abs = worst_abs.max(d);
            if e.abs() > 1e-3 {
                worst_rel = worst_rel.max(d / e.abs());
            }
            peak = peak.max(e);
        }
    }
    println!(
        "{name} GPU = CPU: {} directions, max |Δ| = {worst_abs:.2e}, max relative (values > 1e-3) = \
         {worst_rel:.2e}, largest value {peak:.3}",
        rows.len()
    );
    peak
}

#[test]
fn wgsl_marschner_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let rows = probe_rows();
    let out = probe(&gpu, &rows);
    let peak = assert_gpu_equals_cpu("marschner", &rows, (ABS_TOL, REL_TOL), |r| {
        let [t, l, v, c] = rows[r];
        let o = &out[r];
        let sigma = marschner::absorption(c);
        let s = marschner::lobes(t, l, v, sigma);
        let sum = marschner::marschner(t, l, v, c);
        let expected = vec![
            s.r, s.tt.x, s.tt.y, s.tt.z, s.trt.x, s.trt.y, s.trt.z, sum.x, sum.y, sum.z, sigma.x, sigma.y,
            sigma.z,
        ];
        let got = vec![
            o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[8], o[9], o[10], o[12], o[13], o[14],
        ];
        (got, expected)
    });
    assert!(peak > 1.0, "no probe reached the TT peak: {peak}");
}

/// Per probe: [`dual_scattering::dual_scattering`] at a visibility and a hair count, and
/// [`count_from_visibility`] of that visibility at the probe's alpha; then the global forward scattering alone
/// ([`dual_scattering::Terms::forward_scattered`]).
const DUAL_PROBE: &str = r#"
struct Row {
    tangent: vec4<f32>,
    to_light: vec4<f32>,
    to_eye: vec4<f32>,
    colour: vec4<f32>,
    // visibility, count, alpha, hair model.
    lit: vec4<f32>,
}
alias Out = vec4<f32>;

fn probe(i: u32, p: Row) {
    let f = dual_scattering(u32(p.lit.w), p.tangent.xyz, p.to_light.xyz, p.to_eye.xyz, p.colour.rgb, p.lit.x, p.lit.y);
    out[2u * i] = vec4<f32>(f, count_from_visibility(p.lit.x, p.lit.z));
    let t = dual_scattering_terms(u32(p.lit.w), p.tangent.xyz, p.to_light.xyz, p.to_eye.xyz, p.colour.rgb, p.lit.x, p.lit.y);
    out[2u * i + 1u] = vec4<f32>(dual_scattering_forward(t), 0.0);
}
"#;

/// GPU = CPU: dual scattering and its global forward scattering alone on the Marschner probe directions and
/// colours, each at a hair count and the
/// visibility of that many strands of alpha 0.35 (`n` = 0, 0.5, 1, 3, 10, 40, cycling), under both hair models
/// (the fibres model's table and densities; the count checked under absorbers), with the same tolerance
/// form as the lobes (`|Δ| ≤ 2e-6 + 1e-5 |F|`: the table lookup and `pow(ā_f, n)` add a few ulps to the
/// lobes' own); and the count read back from that visibility within `1e-5 + 1e-5 n`. Measured on lavapipe
/// (printed by the test): max |Δ| = 5.96e-7, max relative 9.56e-6 over 8540 probes; max |Δn| = 3.81e-6.
#[test]
fn wgsl_dual_scattering_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let alpha = 0.35f32;
    let counts = [0.0f32, 0.5, 1.0, 3.0, 10.0, 40.0];
    let rows: Vec<([Vec3; 4], [f32; 4])> = HairModel::ALL
        .iter()
        .flat_map(|model| {
            probe_rows().into_iter().enumerate().map(move |(k, row)| {
                let n = counts[k % counts.len()];
                (row, [(1.0 - alpha).powf(n), n, alpha, model.uniform() as f32])
            })
        })
        .collect();
    let packed: Vec<[f32; 4]> = rows
        .iter()
        .flat_map(|(dirs, lit)| dirs.iter().map(|v| v.extend(0.0).to_array()).chain([*lit]))
        .collect();
    let bytes = common::run_probe(
        &gpu,
        ("common/dual_scattering.wgsl", DUAL_PROBE, "dual_scattering.probe"),
        bytemuck::cast_slice(&packed),
        rows.len(),
        32,
    );
    let out: Vec<[f32; 8]> = bytemuck::pod_collect_to_vec(&bytes);
    let (mut worst_abs, mut worst_rel, mut worst_count, mut peak) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for ((dirs, lit), o) in rows.iter().zip(&out) {
        let [t, l, v, c] = *dirs;
        let model = HairModel::ALL[lit[3] as usize];
        let f = dual_scattering::dual_scattering(model, t, l, v, c, lit[0], lit[1]);
        let g = dual_scattering::terms(model, t, l, v, c, lit[0], lit[1]).forward_scattered();
        let pairs = (0..3)
            .map(|k| (o[k], f[k]))
            .chain((0..3).map(|k| (o[4 + k], g[k])));
        for (k, (g, e)) in pairs.enumerate() {
            assert!(
                g.is_finite() && e.is_finite(),
                "{dirs:?} {lit:?}: GPU {g}, CPU {e}"
            );
            let d = (g - e).abs();
            assert!(
                d <= ABS_TOL + REL_TOL * e.abs(),
                "{dirs:?} {lit:?} channel {k}: GPU {g}, CPU {e}"
            );
            worst_abs = worst_abs.max(d);
            if e.abs() > 1e-3 {
                worst_rel = worst_rel.max(d / e.abs());
            }
            peak = peak.max(e);
        }
        let n = count_from_visibility(lit[0], lit[2]);
        let d = (o[3] - n).abs();
        assert!(d <= 1e-5 + 1e-5 * n, "{lit:?}: GPU count {}, CPU {n}", o[3]);
        assert!((n - lit[1]).abs() <= 1e-3 * lit[1].max(1.0), "{lit:?}: count {n}");
        worst_count = worst_count.max(d);
    }
    println!(
        "dual scattering GPU = CPU: {} probes, max |Δ| = {worst_abs:.2e}, max relative (values > 1e-3) = \
         {worst_rel:.2e}, largest value {peak:.3}; count max |Δ| = {worst_count:.2e}",
        rows.len()
    );
    assert!(peak > 1.0, "no probe reached the TT peak: {peak}");
}

/// A capture's premultiplied hair colour `H` as luminance (Rec. 709 weights), per hair pixel (coverage > 0).
fn hair_luminance(capture: &[[f32; 4]]) -> Vec<f32> {
    capture
        .iter()
        .filter(|p| p[3] > 0.0)
        .map(|p| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
        .collect()
}

/// Renders `s` under both shading models with the method and technique of `s`; checks that the Marschner
/// capture is finite and not black, that coverage is the same (the shading model changes colour only), and that
/// the colour differs from Kajiya-Kay's in at least a quarter of the hair pixels (those in a shadow keep only
/// the ambient term, the same under both: 41 % to 61 % differ on the test scenes). Returns the two
/// captures' hair luminances.
fn both_models(gpu: &Gpu, s: &Settings, what: &str) -> (Vec<f32>, Vec<f32>) {
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(gpu, &scene, s.render.map_resolution).unwrap();
    let method = registry::find(&s.method.name).unwrap();
    let capture = |r: &mut Renderer, model: ShadingModel| {
        let mut s = s.clone();
        s.render.shading = model;
        r.render_capture(&common::frame_input(&s, method)).unwrap()
    };
    let kk = capture(&mut r, ShadingModel::KajiyaKay);
    let m = capture(&mut r, ShadingModel::Marschner);
    assert!(
        m.iter().flatten().all(|v| v.is_finite()),
        "{what}: a Marschner pixel is not finite"
    );
    let covered = m.iter().filter(|p| p[3] > 0.0).count();
    assert!(covered > 100, "{what}: only {covered} hair pixels");
    let lit = m.iter().filter(|p| p[0] + p[1] + p[2] > 1e-2).count();
    assert!(
        lit * 2 > covered,
        "{what}: {lit} of {covered} hair pixels lit under Marschner"
    );
    let coverage = kk
        .iter()
        .zip(&m)
        .map(|(a, b)| (a[3] - b[3]).abs())
        .fold(0.0f32, f32::max);
    assert!(coverage <= 1e-6, "{what}: coverage changed by {coverage}");
    let changed = kk
        .iter()
        .zip(&m)
        .filter(|(a, b)| (0..3).any(|i| (a[i] - b[i]).abs() > 1e-2))
        .count();
    println!("{what}: {changed} of {covered} hair pixels differ");
    assert!(
        changed * 4 >= covered,
        "{what}: only {changed} of {covered} hair pixels differ from Kajiya-Kay"
    );
    (hair_luminance(&kk), hair_luminance(&m))
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len().max(1) as f32
}

fn max(v: &[f32]) -> f32 {
    v.iter().copied().fold(0.0, f32::max)
}

/// The back-lit preset shrunk to a test scene: 7200 segments, 96×72.
fn small_back_lit() -> Settings {
    let mut s = crate::common::measured_preset(
        "back-lit",
        &[
            "scene.generator.strands=600".into(),
            "scene.generator.segments=12".into(),
            "render.width=96".into(),
            "render.height=72".into(),
            "render.map_resolution=128".into(),
        ],
    );
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    s
}

/// Every shadow method (at its defaults, under the preset's technique) renders under `marschner`.
#[test]
fn every_shadow_method_renders_under_marschner() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let base = small_back_lit();
    for method in registry::all() {
        let mut s = base.clone();
        s.method.name = method.name().into();
        s.method.params.clear();
        both_models(&gpu, &s, method.name());
    }
}

/// Every transparency technique (at its defaults, under the preset's shadow method) renders under
/// `marschner`.
#[test]
fn every_transparency_technique_renders_under_marschner() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let base = small_back_lit();
    for technique in techniques::all() {
        let mut s = base.clone();
        s.transparency.name = technique.name().into();
        s.transparency.params.clear();
        both_models(&gpu, &s, technique.name());
    }
}

/// Back-lit, the transmitted lobe makes the hair at the silhouette glow brighter than anything Kajiya-Kay's
/// diffuse and cone terms reach (they do not depend on which side of the hair the light is): the brightest
/// Marschner pixel is over 1.5 times the brightest Kajiya-Kay pixel and at least 1 % of the hair pixels are
/// brighter than it (measured: 1.019 against 0.369, 79 of 1285 pixels). Front-lit (the default preset)
/// Marschner's single scattering is darker on average (measured mean luminance 0.0168 against 0.0421). Both
/// models see the same visibility (the preset's shadow method), so the comparison is the shading's alone.
#[test]
fn back_light_glows_only_under_marschner() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (kk, m) = both_models(&gpu, &small_back_lit(), "back-lit");
    let brightest = max(&kk);
    let glowing = m.iter().filter(|&&y| y > brightest).count();
    println!(
        "back-lit: hair luminance mean {:.4} / {:.4}, max {brightest:.4} / {:.4} (kajiya-kay / marschner); \
         {glowing} of {} marschner pixels above the kajiya-kay maximum",
        mean(&kk),
        mean(&m),
        max(&m),
        m.len()
    );
    assert!(max(&m) > 1.5 * brightest, "back-lit: {} vs {brightest}", max(&m));
    assert!(
        glowing * 100 >= m.len(),
        "back-lit: {glowing} of {} glow",
        m.len()
    );
    let mut front = common::small_settings(96, 72);
    let scene = front.scene.build().unwrap();
    front.camera.frame(&scene.framing_bounds());
    let (kk, m) = both_models(&gpu, &front, "front-lit");
    println!(
        "front-lit: hair luminance mean kajiya-kay {:.4}, marschner {:.4}",
        mean(&kk),
        mean(&m)
    );
    assert!(
        mean(&m) < mean(&kk),
        "front-lit: marschner {} vs kajiya-kay {}",
        mean(&m),
        mean(&kk)
    );
}

/// The eye pass under `dual-scattering`, with the reference's exact visibility (so its count is that of the exact
/// `V`): every term dual scattering adds to the Marschner lobes is non-negative, so no hair pixel is darker than
/// under `marschner` (beyond 1e-5 of rounding) and the hair as a whole is lighter (measured: mean hair
/// luminance 0.0965 → 0.0989 on this 600-strand back-lit scene); coverage is unchanged.
#[test]
fn dual_scattering_lightens_the_marschner_image() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = small_back_lit();
    s.method.name = registry::reference().name().into();
    s.method.params.clear();
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let method = registry::reference();
    let mut capture = |model: ShadingModel| {
        let mut s = s.clone();
        s.render.shading = model;
        r.render_capture(&common::frame_input(&s, method)).unwrap()
    };
    let m = capture(ShadingModel::Marschner);
    let ds = capture(ShadingModel::DualScattering);
    assert!(
        ds.iter().flatten().all(|v| v.is_finite()),
        "a dual-scattering pixel is not finite"
    );
    let mut darker = 0;
    for (a, b) in m.iter().zip(&ds) {
        assert!((a[3] - b[3]).abs() <= 1e-6, "coverage changed: {a:?} {b:?}");
        if (0..3).any(|i| b[i] < a[i] - 1e-5) {
            darker += 1;
        }
    }
    assert_eq!(darker, 0, "{darker} hair pixels darker under dual scattering");
    let (lm, lds) = (mean(&hair_luminance(&m)), mean(&hair_luminance(&ds)));
    println!("mean hair luminance: marschner {lm:.4}, dual scattering {lds:.4}");
    assert!(lds > lm * 1.01, "dual scattering {lds} vs marschner {lm}");
}

/// Per probe `(sin θ, σ_a r g b)` and `(n, V, ·, ·)`: `fibre_attenuation`, `fibre_transmittance` and
/// `fibre_arriving` of `shaders/common/fibre_transport.wgsl`.
const FIBRE_PROBE: &str = r#"
struct Row {
    angle: vec4<f32>,
    lit: vec4<f32>,
}
alias Out = vec4<f32>;

fn probe(i: u32, p: Row) {
    let a = fibre_attenuation(p.angle.x, p.angle.yzw);
    out[4u * i] = vec4<f32>(a.forward, fibre_count(p.lit.y));
    out[4u * i + 1u] = vec4<f32>(a.backward, 0.0);
    out[4u * i + 2u] = vec4<f32>(fibre_transmittance(p.angle.x, p.angle.yzw, p.lit.x), 0.0);
    out[4u * i + 3u] = vec4<f32>(fibre_arriving(p.lit.y, p.angle.x, p.angle.yzw, p.lit.x), 0.0);
}
"#;

/// GPU = CPU: the fibres model's table lookup, transmittance and arriving light on 4096 random inclinations
/// (the nodes' ends included), absorptions `√σ_a` in [0, 1.3] (past the table's last node) and counts in
/// [0, 40], each at `V = e^-n`, within `|Δ| ≤ 2e-6 + 1e-5 |x|` (the lobes' tolerance: bilinear weights and `pow`
/// in f32); the count read back from `V` within `1e-5 + 1e-5 n`.
#[test]
fn wgsl_fibre_transport_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut rng = SplitMix64::new(23);
    let mut rows: Vec<[f32; 8]> = (0..4096)
        .map(|_| {
            let s = rng.range(-1.1, 1.1);
            let sigma: [f32; 3] = std::array::from_fn(|_| rng.range(0.0, 1.3).powi(2));
            let n = rng.range(0.0, 40.0);
            [s, sigma[0], sigma[1], sigma[2], n, (-n).exp(), 0.0, 0.0]
        })
        .collect();
    rows.extend([-1.0f32, 0.0, 1.0].map(|s| [s, 0.0, 0.09, 1.44, 0.0, 1.0, 0.0, 0.0]));
    let bytes = common::run_probe(
        &gpu,
        (
            "common/fibre_transport.wgsl",
            FIBRE_PROBE,
            "fibre_transport.probe",
        ),
        bytemuck::cast_slice(&rows),
        rows.len(),
        64,
    );
    let out: Vec<[f32; 16]> = bytemuck::pod_collect_to_vec(&bytes);
    let (mut worst, mut worst_count) = (0.0f32, 0.0f32);
    for (r, o) in rows.iter().zip(&out) {
        let sigma = Vec3::new(r[1], r[2], r[3]);
        let (af, ab) = fibre_transport::attenuation(r[0], sigma);
        let t = fibre_transport::transmittance(r[0], sigma, r[4]);
        let arriving = fibre_transport::arriving(r[5], r[0], sigma, r[4]);
        for (k, (cpu, at)) in [(af, 0), (ab, 4), (t, 8), (arriving, 12)].into_iter().enumerate() {
            for c in 0..3 {
                let (g, e) = (o[at + c], cpu[c]);
                let d = (g - e).abs();
                assert!(
                    d <= ABS_TOL + REL_TOL * e.abs(),
                    "{r:?} quantity {k} channel {c}: GPU {g}, CPU {e}"
                );
                worst = worst.max(d);
            }
        }
        let n = fibre_transport::count(r[5]);
        let d = (o[3] - n).abs();
        assert!(d <= 1e-5 + 1e-5 * n, "{r:?}: GPU count {}, CPU {n}", o[3]);
        worst_count = worst_count.max(d);
    }
    println!(
        "fibre transport GPU = CPU: {} probes, max |Δ| = {worst:.2e}; count max |Δ| = {worst_count:.2e}",
        rows.len()
    );
}

/// Per probe `(world xyz, ·)`, `(colour rgb, ·)`, `(tangent, ·)`, `(to eye, ·)`: `hair_ambient_light` of
/// `shaders/common/mesh_bounce.wgsl`, and `mesh_probe_light` of the same rows (the colour read as the mesh's
/// albedo, the tangent as its normal).
const BOUNCE_PROBE: &str = r#"
struct Row {
    world: vec4<f32>,
    colour: vec4<f32>,
    tangent: vec4<f32>,
    to_eye: vec4<f32>,
}
struct Out {
    hair: vec4<f32>,
    mesh: vec4<f32>,
}

fn probe(i: u32, p: Row) {
    out[i].hair = vec4<f32>(hair_ambient_light(p.colour.rgb, p.world.xyz, p.tangent.xyz, p.to_eye.xyz), 0.0);
    out[i].mesh = vec4<f32>(mesh_probe_light(p.world.xyz, p.tangent.xyz, p.colour.rgb), 0.0);
}
"#;

/// GPU = CPU: the light beyond one event of a hair fragment under both hair models: the absorber's
/// `colour × 0.08`, and the fibres model's response to its probe (`probe_light::probe_response`) under the
/// voxel probe (`hair_response(colour) ×` the mean) and the traced one (the fibre's response to the light's
/// moments along it), on a lattice of random nodes (each the light of 1–6 random directions and a random
/// cover), at 2048 random points inside, on and beyond the lattice with random colours, tangents and eyes,
/// within `|Δ| ≤ 2e-6 + 1e-5 |x|`; and a mesh point's light of the hair around it
/// (`probe_light::mesh_probe_light`: none under the absorber model, faded out beyond the lattice) at the same
/// points, the colours as albedos and the tangents as normals (the lattice's box and the one node spacing
/// beyond it hold at least 150 of the points lit, measured 215).
#[test]
fn wgsl_mesh_bounce_equals_the_cpu_model() {
    use hairlab::shading::hair_cover::Cube;
    use hairlab::shading::mesh_bounce::{Grid, NODES, Probe};
    use hairlab::shading::probe_light::{ProbeLight, mesh_probe_light, packed, probe_response};
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut rng = SplitMix64::new(31);
    let mut grid = Grid {
        min: Vec3::new(-0.2, 0.1, -0.3),
        max: Vec3::new(0.25, 0.6, 0.2),
        values: [ProbeLight::default(); NODES * NODES * NODES],
    };
    let unit = |rng: &mut SplitMix64| {
        Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::Y)
    };
    for v in &mut grid.values {
        for _ in 0..1 + (rng.unit() * 6.0) as usize {
            let l = Vec3::new(rng.range(0.0, 0.4), rng.range(0.0, 0.4), rng.range(0.0, 0.4));
            v.add_rest(unit(&mut rng), l, rng.range(0.1, 2.0));
        }
        v.cover = Cube(std::array::from_fn(|_| rng.unit()));
    }
    let rows: Vec<[f32; 16]> = (0..2048)
        .map(|_| {
            let p: [f32; 3] = std::array::from_fn(|_| rng.range(-0.5, 0.8));
            let c: [f32; 3] = std::array::from_fn(|_| rng.range(0.0, 1.0));
            let [t, e] = [unit(&mut rng), unit(&mut rng)];
            let mut r = [0.0; 16];
            r[..3].copy_from_slice(&p);
            r[4..7].copy_from_slice(&c);
            r[8..11].copy_from_slice(&t.to_array());
            r[12..15].copy_from_slice(&e.to_array());
            r
        })
        .collect();
    let mut frame: hairlab::render::uniforms::FrameUniforms = bytemuck::Zeroable::zeroed();
    frame.hair_ambient = 0.08;
    let hair_colour = Vec3::new(0.8, 0.6, 0.4);
    frame.hair_color = hair_colour.to_array();
    frame.bounce_max = grid.max.extend(0.0).to_array();
    frame.bounce_grid = packed(&grid);
    let v = |r: &[f32; 16], k: usize| Vec3::new(r[k], r[k + 1], r[k + 2]);
    let mut worst = 0.0f32;
    let cases: [(HairModel, Option<Probe>); 3] = [
        (HairModel::Absorber, None),
        (HairModel::Fibres, Some(Probe::Voxels)),
        (HairModel::Fibres, Some(Probe::Traced)),
    ];
    for (model, probe) in cases {
        frame.hair_model = model.uniform();
        let traced = probe == Some(Probe::Traced);
        frame.bounce_min = grid.min.extend(f32::from(u8::from(traced))).to_array();
        let bytes = common::run_probe_with_frame(
            &gpu,
            ("common/mesh_bounce.wgsl", BOUNCE_PROBE, "mesh_bounce.probe"),
            &frame,
            bytemuck::cast_slice(&rows),
            rows.len(),
            32,
        );
        let out: Vec<[[f32; 4]; 2]> = bytemuck::pod_collect_to_vec(&bytes);
        let mut lit_meshes = 0;
        for (r, [hair, mesh]) in rows.iter().zip(&out) {
            let (cpu_hair, cpu_mesh) = match probe {
                None => (v(r, 4) * 0.08, Vec3::ZERO),
                Some(probe) => (
                    probe_response(&grid, probe, v(r, 0), v(r, 8), v(r, 12), v(r, 4)),
                    mesh_probe_light(&grid, v(r, 0), v(r, 8), v(r, 4), hair_colour),
                ),
            };
            lit_meshes += usize::from(cpu_mesh.max_element() > 0.0);
            for (what, gpu, cpu) in [("hair", hair, cpu_hair), ("mesh", mesh, cpu_mesh)] {
                for k in 0..3 {
                    let d = (gpu[k] - cpu[k]).abs();
                    worst = worst.max(d);
                    assert!(
                        d <= ABS_TOL + REL_TOL * cpu[k].abs(),
                        "{what} {model:?} {probe:?} {r:?}: GPU {gpu:?}, CPU {cpu}"
                    );
                }
            }
        }
        println!("{model:?} {probe:?}: {lit_meshes} mesh points lit");
        assert!(
            probe.is_none() || lit_meshes >= 150,
            "{lit_meshes} mesh points lit"
        );
    }
    println!(
        "mesh bounce GPU = CPU: {} rows × 3 cases, max |Δ| = {worst:.2e}",
        rows.len()
    );
}
