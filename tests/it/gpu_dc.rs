//! Density Clustering on the GPU (`hairlab::methods::dc`) against the CPU model `visibility::dc`, fed each
//! texel's exact fragment list from the reference A-buffer: K = 1..16 (one and several RGBA groups, partial
//! groups), map resolutions 1 to 2048, hair alphas from nearly clear to opaque; memory, passes, the size limit.
//!
//! The model is discontinuous in the last bits of its inputs, so no f32 implementation that sums in another
//! order or rounds `log`, `/` and `sqrt` differently (Vulkan allows 2.5 ULP for `/`) can match it bit for bit
//! everywhere: a fragment on a decision boundary (sub-range edge of pass 1, equidistant means in pass 2, bin
//! edge in pass 3) may go to the neighbouring cluster, and a cluster of fragments at one depth gets a bin a few
//! ULPs wide (`sum b z / sum b` is not exactly `z` in f32) whose value at that very depth is a coin toss. The
//! comparison therefore classifies each sample:
//! - in an ill-conditioned texel (a fragment changes cluster or bin when moved by [`EPSILON`]): at most one
//!   sample in a thousand of the map may differ by more than [`TOLERANCE`] (measured: up to 22 of 232,906);
//! - at a step (the CPU's `V` changes by more than the tolerance across `z -+ EPSILON`): `V_gpu` must lie within
//!   the CPU's `V` over `z -+ EPSILON`, and at most half of these samples beyond the tolerance (measured: 0 to
//!   27 %; a wrong step convention would put nearly all of them there);
//! - everywhere else: `|ΔV| <= TOLERANCE` (measured: at most 6.7e-4, mostly below 6e-5).

use crate::common;

use hairlab::gpu::{Gpu, GpuError};
use hairlab::methods::{ParamValues, registry};
use hairlab::render::{FrameInput, Renderer};
use hairlab::settings::Settings;
use hairlab::visibility::dc::{self, DcTexel};
use hairlab::visibility::{DcParams, Fragment, depth_range, metrics, relative_depth, slice_index};

/// The sums are the CPU's f32 sums in another order (additive blending), and `log`, `exp`, the divisions and
/// `sqrt` round differently on the GPU: far below this wherever the model is continuous.
const TOLERANCE: f32 = 1e-3;
/// Depth margin of the conditioning test: 17 to 34 f32 ULPs of depths in [0.25, 1), above the GPU's rounding
/// of the means (a few ULPs from the division and the order of the sums).
const EPSILON: f32 = 1e-6;

const CLUSTERS: [f32; 7] = [1.0, 2.0, 3.0, 4.0, 5.0, 8.0, 16.0];

/// Index of the mean nearest to `z`, the lowest on ties (the model's rule).
fn nearest(means: &[f32], z: f32) -> usize {
    (0..means.len()).fold(0, |best, j| {
        if (z - means[j]).abs() < (z - means[best]).abs() {
            j
        } else {
            best
        }
    })
}

/// The three cluster decisions the model takes for a fragment at `z`: initial centre, nearest mean, bin.
fn decisions(k: usize, near: f32, far: f32, texel: &DcTexel, bins: &[(f32, f32)], z: f32) -> [usize; 3] {
    let bin = bins
        .iter()
        .position(|&(lo, hi)| lo <= z && z <= hi)
        .unwrap_or_else(|| nearest(&texel.means, z));
    [
        slice_index(relative_depth(z, near, far) * k as f32, k),
        nearest(&texel.means, z),
        bin,
    ]
}

/// Whether a fragment of the texel changes cluster or bin when moved by [`EPSILON`]. The initial centre of a
/// fragment at the texel's nearest or furthest depth is exact (relative depth 0 or 1, with `near` and `far`
/// the exact min and max), so only the others are moved for pass 1.
fn ill_conditioned(params: &DcParams, fragments: &[Fragment], texel: &DcTexel) -> bool {
    let (near, far) = depth_range(fragments);
    let bins = dc::bins(&texel.means, &texel.half_widths);
    let k = params.cluster_count();
    fragments.iter().any(|f| {
        let at = |z| decisions(k, near, far, texel, &bins, z);
        let d = at(f.depth);
        let skip = usize::from(f.depth == near || f.depth == far);
        [at(f.depth - EPSILON), at(f.depth + EPSILON)]
            .iter()
            .any(|m| m[skip..] != d[skip..])
    })
}

/// GPU against CPU over the occupied texels of one map.
#[derive(Default)]
struct Comparison {
    samples: usize,
    /// Largest |ΔV| where the CPU's V is continuous (varies by at most the tolerance over z -+ EPSILON) in a
    /// well-conditioned texel.
    worst: f32,
    /// Samples at steps (the CPU's V varies by more than the tolerance over z -+ EPSILON) of well-conditioned
    /// texels; those beyond the tolerance; their largest distance outside the CPU's V over z -+ EPSILON.
    steps: usize,
    steps_off: usize,
    steps_outside: f32,
    /// Ill-conditioned texels, out of the occupied ones.
    ill_texels: usize,
    texels: usize,
    /// Samples of ill-conditioned texels beyond the tolerance, and their largest |ΔV|.
    ill_off: usize,
    ill_worst: f32,
}

impl Comparison {
    fn check(&self, what: &str) {
        eprintln!(
            "dc {what}: {} samples; max |ΔV| = {:e} where V is continuous; {} of {} samples at steps beyond \
             {TOLERANCE:e}, {:e} outside the CPU's V over z -+ {EPSILON:e}; {} ill-conditioned texels of {}, \
             {} samples there beyond {TOLERANCE:e} (max |ΔV| {:e})",
            self.samples,
            self.worst,
            self.steps_off,
            self.steps,
            self.steps_outside,
            self.ill_texels,
            self.texels,
            self.ill_off,
            self.ill_worst
        );
        assert!(self.worst <= TOLERANCE, "{what}: max |ΔV| = {}", self.worst);
        assert!(
            self.steps_outside <= TOLERANCE,
            "{what}: V outside the CPU's V over z -+ {EPSILON} by {}",
            self.steps_outside
        );
        // The step a bin of ULP width makes at its fragments' depth falls on either side of that depth: not
        // systematically on the other side than the CPU's (which a wrong step convention would do).
        assert!(
            self.steps_off * 2 <= self.steps,
            "{what}: {} of {} samples at steps beyond the tolerance",
            self.steps_off,
            self.steps
        );
        assert!(
            self.ill_off * 1000 <= self.samples,
            "{what}: {} of {} samples of ill-conditioned texels beyond the tolerance",
            self.ill_off,
            self.samples
        );
    }
}

/// Settings of a scene of `strands` strands lit at `resolution`² with `hair_alpha`.
fn settings(strands: u32, resolution: u32, hair_alpha: f32) -> Settings {
    let mut s = common::small_settings(8, 8);
    s.scene.generator.strands = strands;
    s.scene.generator.segments = 10;
    s.render.map_resolution = resolution;
    s.render.hair_alpha = hair_alpha;
    s
}

fn frame<'a>(s: &'a Settings, name: &str, params: &'a ParamValues) -> FrameInput<'a> {
    crate::common::light_frame(s, registry::find(name).unwrap(), params)
}

/// Renders `strands` strands from the light at `resolution`² with `hair_alpha` and `clusters`, and compares
/// GPU and CPU at every fragment depth and a 16-point grid of every occupied texel (and depths around an empty
/// texel, if any). Fails on any V that is not finite or outside [0, 1].
fn compare(gpu: &Gpu, strands: u32, resolution: u32, hair_alpha: f32, clusters: f32) -> Comparison {
    let mut s = settings(strands, resolution, hair_alpha);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let values: ParamValues = [("clusters".to_string(), clusters)].into();
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let method = registry::find("dc").unwrap();
    let lists = r.reference_lists(&s.camera, &s.light, &s.render).unwrap();
    r.render_light(&frame(&s, "dc", &values)).unwrap();
    let params = DcParams {
        clusters: clusters as u32,
    };
    // Per sample: the CPU's V at z - EPSILON, z, z + EPSILON, and whether its texel is ill-conditioned.
    let (mut samples, mut expected, mut ill) = (Vec::new(), Vec::new(), Vec::new());
    let mut c = Comparison::default();
    for (t, list) in lists.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        let frags: Vec<Fragment> = list.iter().map(|f| Fragment::new(f.depth, f.alpha)).collect();
        let texel = dc::build(&params, &frags);
        let texel_ill = ill_conditioned(&params, &frags, &texel);
        c.texels += 1;
        c.ill_texels += usize::from(texel_ill);
        let (x, y) = ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
        for z in metrics::sample_depths(&frags, 16) {
            let v = |z| dc::visibility(&params, &texel, z);
            expected.push([v(z - EPSILON), v(z), v(z + EPSILON)]);
            samples.push([x, y, z]);
            ill.push(texel_ill);
        }
    }
    // An empty texel (no cluster holds any density) is lit at every depth.
    if let Some(t) = lists.iter().position(|l| l.is_empty()) {
        let (x, y) = ((t as u32 % resolution) as f32, (t as u32 / resolution) as f32);
        for z in [-1.0, 0.0, 0.5, 1.0, 2.0] {
            samples.push([x, y, z]);
            expected.push([1.0; 3]);
            ill.push(false);
        }
    }
    let got = r.evaluate(method, &samples).unwrap();
    assert!(
        got.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
        "V outside [0, 1] at {resolution}², alpha {hair_alpha}, K={clusters}"
    );
    c.samples = samples.len();
    for ((&g, [before, at, after]), ill) in got.iter().zip(&expected).zip(ill) {
        let d = (g - at).abs();
        if ill {
            if d > TOLERANCE {
                c.ill_off += 1;
                c.ill_worst = c.ill_worst.max(d);
            }
        } else if before - after > TOLERANCE {
            c.steps += 1;
            if d > TOLERANCE {
                c.steps_off += 1;
                // V is non-increasing in z: the CPU's V over z -+ EPSILON is [after, before].
                c.steps_outside = c.steps_outside.max(after - g).max(g - before);
            }
        } else {
            c.worst = c.worst.max(d);
        }
    }
    c
}

#[test]
fn dc_gpu_equals_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for k in CLUSTERS {
        for resolution in [64, 256] {
            let c = compare(&gpu, 300, resolution, 0.35, k);
            assert!(c.samples > 5000, "only {} samples", c.samples);
            c.check(&format!("K={k} at {resolution}²"));
        }
    }
}

#[test]
fn extreme_resolutions_alphas_and_cluster_counts() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (strands, resolution) in common::EXTREME_SETUPS {
        for clusters in [1.0, 16.0] {
            for hair_alpha in [0.01, 0.35, 1.0] {
                let c = compare(&gpu, strands, resolution, hair_alpha, clusters);
                assert!(c.samples > 10, "only {} samples", c.samples);
                c.check(&format!(
                    "K={clusters}, {strands} strands at {resolution}², alpha {hair_alpha}"
                ));
            }
        }
    }
}

fn render_light_at(gpu: &Gpu, resolution: u32, clusters: f32) -> (Renderer, Result<(), GpuError>) {
    let s = settings(20, resolution, 0.35);
    let scene = s.scene.build().unwrap();
    let mut r = Renderer::new(gpu, &scene, resolution).unwrap();
    let values: ParamValues = [("clusters".to_string(), clusters)].into();
    let result = r.render_light(&frame(&s, "dc", &values));
    (r, result)
}

#[test]
fn memory_and_geometry_passes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let dc = registry::find("dc").unwrap();
    // Two RGBA32F textures (accumulation, clusters) of 2 ceil(K / 4) layers: 64 bytes per texel per group of 4
    // clusters; 16 MiB at 512² for the paper's K = 4.
    for (k, groups) in [(1.0, 1), (4.0, 1), (5.0, 2), (16.0, 4)] {
        let (r, result) = render_light_at(&gpu, 512, k);
        result.unwrap();
        let m = r.method_gpu(dc).unwrap();
        assert_eq!(m.memory_bytes(), 512 * 512 * 64 * groups, "K={k}");
        assert_eq!(m.geometry_passes(), 3);
    }
}

#[test]
fn parameter_and_resolution_changes_reallocate_the_maps() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut s = settings(300, 64, 0.35);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    let mut r = Renderer::new(&gpu, &scene, 64).unwrap();
    let dc = registry::find("dc").unwrap();
    for (k, resolution) in [(16.0, 64), (3.0, 64), (3.0, 32), (8.0, 128)] {
        s.render.map_resolution = resolution;
        let values: ParamValues = [("clusters".to_string(), k)].into();
        // The full frame: the eye passes read the maps through the lookup.
        r.render(&frame(&s, "dc", &values)).unwrap();
        let groups = (k as u64).div_ceil(4);
        assert_eq!(
            r.method_gpu(dc).unwrap().memory_bytes(),
            resolution as u64 * resolution as u64 * 64 * groups
        );
        r.read_output().unwrap();
    }
}

#[test]
fn maps_beyond_the_size_limit_are_refused() {
    let Some(gpu) = Gpu::for_tests() else { return };
    // The largest map resolution hairlab allows with K = 16: 4096² × 16 layers × 16 bytes = 4 GiB.
    let (_r, result) = render_light_at(&gpu, 4096, 16.0);
    match result {
        Err(e @ GpuError::OverBudget { .. }) => {
            let GpuError::OverBudget {
                bytes,
                budget,
                ref what,
            } = e
            else {
                unreachable!()
            };
            assert_eq!(
                (bytes, budget),
                (4 << 30, hairlab::render::maps::MAP_BUDGET_BYTES)
            );
            assert!(what.contains("density clustering"), "{what}");
            assert!(e.to_string().contains("hairlab's light-map budget"), "{e}");
        }
        other => panic!("expected OverBudget, got {other:?}"),
    }
}
