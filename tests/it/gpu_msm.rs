//! Moment shadow maps on the GPU (`hairlab::methods::msm`) against the CPU model `visibility::msm`, fed each
//! texel's exact fragment list from the reference A-buffer: 4 and 6 moments, moment biases from MBOIT's f32
//! values up to 1e-2, overestimation 0 to 1, map resolutions 1 to 2048, hair alphas from nearly clear to
//! opaque; memory and passes.
//!
//! The moment problem is ill-conditioned: at MBOIT's f32 biases the Hankel matrix of a texel whose fragments
//! sit at one or two depths is singular to within a few f32 ULPs, so the GPU's sums in another order (additive
//! blending) and its own rounding of `/`, `sqrt`, `atan2`, `cos` and `sin` can move `V` by far more than
//! rounding. The comparison therefore classifies each sample by the CPU model's own sensitivity: a sample is
//! ill-conditioned when the CPU's `V` moves by more than [`TOLERANCE`] under [`ULPS`]-ULP changes of the
//! stored moments or a reversed summation order. Well-conditioned samples must agree within [`TOLERANCE`];
//! ill-conditioned ones must lie within [`TOLERANCE`] of the CPU's range under those changes, with a stated
//! share allowed outside it (measured and given per test).

use crate::common;

use hairlab::gpu::Gpu;
use hairlab::methods::{ParamValues, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::visibility::msm::{self, MsmParams, MsmTexel};
use hairlab::visibility::{Fragment, metrics};

/// Far above the rounding of a well-conditioned texel (measured: at most 1e-4 there).
const TOLERANCE: f32 = 1e-3;
/// Moment perturbation of the conditioning test, in ULPs of each stored moment.
const ULPS: i32 = 4;

/// `v` moved by `k` ULPs.
fn ulps(v: f32, k: i32) -> f32 {
    (0..k.abs()).fold(v, |v, _| if k > 0 { v.next_up() } else { v.next_down() })
}

/// The texel with its moments perturbed: `b_0` kept (the GPU sums it exactly like the CPU up to order), each
/// moment `b_j` moved by `sign_j × ULPS`.
fn perturbed(t: &MsmTexel, signs: [i32; 7]) -> MsmTexel {
    let mut p = *t;
    for (b, sign) in p.b.iter_mut().zip(signs) {
        *b = ulps(*b, sign * ULPS);
    }
    p
}

/// The CPU's `V` at `z` over the texel as built and its perturbations: `(min, V, max)`.
fn cpu_range(params: &MsmParams, frags: &[Fragment], z: f32) -> (f32, f32, f32) {
    let t = msm::build(params, frags);
    let reversed: Vec<Fragment> = frags.iter().rev().copied().collect();
    let mut texels = vec![msm::build(params, &reversed)];
    for signs in [
        [1, 1, 1, 1, 1, 1, 1],
        [-1, -1, -1, -1, -1, -1, -1],
        [1, -1, 1, -1, 1, -1, 1],
        [-1, 1, -1, 1, -1, 1, -1],
        [0, 1, 0, -1, 0, 1, 0],
        [0, 0, 1, 0, -1, 0, 1],
    ] {
        texels.push(perturbed(&t, signs));
    }
    let v = msm::visibility(params, &t, z);
    let moved = texels.iter().map(|p| msm::visibility(params, p, z));
    let shifted = [-ULPS, -1, 1, ULPS].map(|k| msm::visibility(params, &t, ulps(z, k)));
    moved
        .chain(shifted)
        .fold((v, v, v), |(lo, v, hi), w| (lo.min(w), v, hi.max(w)))
}

/// GPU against CPU over the occupied texels of one map.
#[derive(Default, Debug)]
struct Comparison {
    samples: usize,
    /// Largest |ΔV| at well-conditioned samples.
    worst: f32,
    /// Ill-conditioned samples; those beyond the tolerance; those outside the CPU's range by more than it.
    ill: usize,
    ill_off: usize,
    ill_outside: usize,
    ill_worst: f32,
}

impl Comparison {
    fn report(&self, what: &str) {
        eprintln!(
            "msm {what}: {} samples; max |ΔV| {:e} where well-conditioned; {} ill-conditioned ({:.2} %), {} \
             beyond {TOLERANCE:e} (max {:e}), {} outside the CPU's range",
            self.samples,
            self.worst,
            self.ill,
            100.0 * self.ill as f64 / self.samples.max(1) as f64,
            self.ill_off,
            self.ill_worst,
            self.ill_outside,
        );
    }

    /// Asserts the classification: well-conditioned samples within the tolerance, at most `outside` of the
    /// samples outside the CPU's range.
    fn check(&self, what: &str, outside: f64) {
        self.report(what);
        assert!(self.worst <= TOLERANCE, "{what}: max |ΔV| = {}", self.worst);
        assert!(
            self.ill_outside as f64 <= outside * self.samples as f64,
            "{what}: {} of {} samples outside the CPU's range",
            self.ill_outside,
            self.samples
        );
    }
}

fn settings(strands: u32, resolution: u32, hair_alpha: f32) -> Settings {
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = strands;
    s.scene.generator.segments = 10;
    s.render.map_resolution = resolution;
    s.render.hair_alpha = hair_alpha;
    s
}

fn frame<'a>(s: &'a Settings, params: &'a ParamValues) -> FrameInput<'a> {
    crate::common::light_frame(s, registry::find("msm").unwrap(), params)
}

fn values(moments: u32, bias: f32, overestimation: f32) -> ParamValues {
    ParamValues::from([
        ("moments".to_string(), if moments == 6 { 1.0 } else { 0.0 }),
        ("bias".to_string(), bias),
        ("overestimation".to_string(), overestimation),
    ])
}

/// Renders `strands` strands from the light at `resolution`² and compares GPU and CPU at every fragment depth
/// and a 16-point grid of every occupied texel. Fails on any V not finite or outside `[exp(-b_0), 1]`.
fn compare(gpu: &Gpu, strands: u32, resolution: u32, hair_alpha: f32, params: MsmParams) -> Comparison {
    let mut s = settings(strands, resolution, hair_alpha);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let v = values(params.moments, params.bias, params.overestimation);
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let method = registry::find("msm").unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    r.render_light(&frame(&s, &v)).unwrap();
    let (mut samples, mut expected, mut floors) = (Vec::new(), Vec::new(), Vec::new());
    for (t, list) in lists.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        let frags: Vec<Fragment> = list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
        let floor = (-msm::build(&params, &frags).b[0]).exp();
        let (x, y) = ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
        for z in metrics::sample_depths(&frags, 16) {
            samples.push([x, y, z]);
            expected.push(cpu_range(&params, &frags, z));
            floors.push(floor);
        }
    }
    let got = r.evaluate(method, &samples).unwrap();
    let mut c = Comparison {
        samples: samples.len(),
        ..Comparison::default()
    };
    for ((&g, &(lo, at, hi)), &floor) in got.iter().zip(&expected).zip(&floors) {
        // The floor in f32 (the GPU's b_0 is the same sum in another order; it flushes denormals to 0).
        assert!(
            g.is_finite() && g <= 1.0 && g + f32::MIN_POSITIVE >= floor * (1.0 - 1e-5),
            "V {g} outside [{floor}, 1]"
        );
        let d = (g - at).abs();
        if hi - lo > TOLERANCE {
            c.ill += 1;
            if d > TOLERANCE {
                c.ill_off += 1;
                c.ill_worst = c.ill_worst.max(d);
            }
            if g < lo - TOLERANCE || g > hi + TOLERANCE {
                c.ill_outside += 1;
            }
        } else {
            c.worst = c.worst.max(d);
        }
    }
    c
}

/// Moment counts, biases and overestimation weights: MBOIT's f32 settings, larger biases, both bounds.
const CONFIGS: [(u32, f32, f32); 8] = [
    (4, 5e-7, 0.25),
    (6, 5e-6, 0.25),
    (4, 5e-7, 0.0),
    (4, 5e-7, 1.0),
    (4, 1e-4, 0.25),
    (6, 1e-4, 0.25),
    (4, 1e-2, 0.25),
    (6, 1e-2, 1.0),
];

/// Measured at 64² and 256² (25,805 and 232,901 samples): well-conditioned samples within 7.1e-4 (most configs
/// within 3e-4); ill-conditioned 8.8-10.5 % of the samples at MBOIT's biases, 0-0.27 % at β = 1e-4, none at
/// 1e-2; outside the CPU's range at most 46 samples (0.02 %). (6 moments at β 5e-7, below MBOIT's 6-moment
/// value, is not checked: 13 % ill-conditioned and 1.8e-2 at well-conditioned samples.)
#[test]
fn msm_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (moments, bias, overestimation) in CONFIGS {
        for resolution in [64, 256] {
            let params = MsmParams {
                moments,
                bias,
                overestimation,
            };
            let c = compare(&gpu, 300, resolution, 0.35, params);
            assert!(c.samples > 20_000, "only {} samples", c.samples);
            let what = format!("{moments} moments, β {bias:e}, w {overestimation} at {resolution}²");
            c.check(&what, 1e-3);
            if bias >= 1e-4 {
                assert!(
                    c.ill * 100 <= c.samples,
                    "{what}: {} of {} samples ill-conditioned",
                    c.ill,
                    c.samples
                );
            }
        }
    }
}

/// Measured: well-conditioned samples within 5.0e-4 (at 2048², alpha 0.01), none outside the CPU's range.
#[test]
fn extreme_resolutions_and_alphas() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (strands, resolution) in common::EXTREME_SETUPS {
        for (moments, bias) in [(4, 5e-7), (6, 5e-6)] {
            for hair_alpha in [0.01, 0.35, 1.0] {
                let params = MsmParams {
                    moments,
                    bias,
                    overestimation: 0.25,
                };
                let c = compare(&gpu, strands, resolution, hair_alpha, params);
                assert!(c.samples > 10, "only {} samples", c.samples);
                c.check(
                    &format!("{moments} moments, {strands} strands at {resolution}², alpha {hair_alpha}"),
                    1e-3,
                );
            }
        }
    }
}

#[test]
fn memory_passes_and_resolution_changes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = settings(300, 64, 0.35);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(&gpu, &scene, 64).unwrap();
    let m = registry::find("msm").unwrap();
    // Two RGBA32F layers for 5 or 7 floats: 32 bytes per texel, 8 MiB at 512², one geometry pass.
    for (moments, resolution) in [(4, 512), (6, 512), (6, 64), (4, 128)] {
        s.render.map_resolution = resolution;
        let v = values(moments, 5e-7, 0.25);
        r.render(&frame(&s, &v)).unwrap();
        let g = r.method_gpu(m).unwrap();
        assert_eq!(g.memory_bytes(), resolution as u64 * resolution as u64 * 32);
        assert_eq!(g.shared_bytes(), 0);
        assert_eq!(g.geometry_passes(), 1);
        r.read_output().unwrap();
    }
}
