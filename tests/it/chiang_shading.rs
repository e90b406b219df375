//! The Chiang shading model on the GPU (`shaders/common/chiang.wgsl`, the table bound as the scene group binds
//! it) against its CPU model (`hairlab::shading::chiang`), lobe by lobe, through a probe compute pass.

use crate::common;
use crate::shading::{ROW, assert_gpu_equals_cpu, probe_rows};
use hairlab::gpu::Gpu;
use hairlab::shading::{chiang, marschner};

/// GPU = CPU tolerance on each value `s`: `|s_gpu − s_cpu| ≤ ABS_TOL + REL_TOL · |s_cpu|`. The table lookup is
/// the same f32 arithmetic on both sides; `M_p` is f64 on the CPU (the path tracer's) and f32 on the GPU, where
/// `exp(a − b − 1/v)` for TT's `1/v ≈ 59` turns an ulp of the exponent into ~4e-6 relative, and the azimuth is
/// the same polynomial on both sides (`chiang::acos`). Measured on lavapipe (printed by the test): max |Δ| =
/// 1.1e-5 at a value of 3.4, max relative 5.6e-6 over 4270 directions.
const ABS_TOL: f32 = 2e-6;
const REL_TOL: f32 = 2e-5;

/// Per probe: the four lobes of [`chiang::lobes_with`] and their sum, [`chiang::chiang`].
const PROBE: &str = r#"

fn probe(i: u32, r: Row) {
    let sigma_a = marschner_absorption(r.colour.rgb);
    let sin_i = clamp(dot(r.tangent.xyz, r.to_light.xyz), -1.0, 1.0);
    let sin_o = clamp(dot(r.tangent.xyz, r.to_eye.xyz), -1.0, 1.0);
    let cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    let cos_o = sqrt(max(1.0 - sin_o * sin_o, 0.0));
    let lp = r.to_light.xyz - sin_i * r.tangent.xyz;
    let vp = r.to_eye.xyz - sin_o * r.tangent.xyz;
    let phi = chiang_acos(clamp(dot(lp, vp) / sqrt(max(dot(lp, lp) * dot(vp, vp), 1e-12)), -1.0, 1.0));
    let root_sigma = sqrt(max(sigma_a, vec3<f32>(0.0)));
    let cell = chiang_cell(phi, cos_o);
    for (var p = 0u; p < 4u; p++) {
        let o = chiang_tilted(p, sin_o, cos_o);
        let m = chiang_mp(cos_i, o.y, sin_i, o.x, chiang_header(p));
        out[5u * i + p] = vec4<f32>(m * chiang_lobe(p, cell, root_sigma), 0.0);
    }
    out[5u * i + 4u] = vec4<f32>(chiang(r.tangent.xyz, r.to_light.xyz, r.to_eye.xyz, r.colour.rgb), 0.0);
}
"#;

#[test]
fn wgsl_chiang_equals_the_cpu_model() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let rows = probe_rows();
    let packed: Vec<[f32; 4]> = rows.iter().flatten().map(|v| v.extend(0.0).to_array()).collect();
    let bytes = common::run_probe(
        &gpu,
        ("common/chiang.wgsl", &format!("{ROW}{PROBE}"), "chiang.probe"),
        bytemuck::cast_slice(&packed),
        rows.len(),
        5 * 16,
    );
    let out: Vec<[f32; 20]> = bytemuck::pod_collect_to_vec(&bytes);
    let table = chiang::table();
    let peak = assert_gpu_equals_cpu("chiang", &rows, (ABS_TOL, REL_TOL), |r| {
        let [t, l, v, c] = rows[r];
        let lobes = chiang::lobes_with(table, t, l, v, marschner::absorption(c));
        let sum = chiang::chiang(t, l, v, c);
        let expected = lobes
            .into_iter()
            .chain([sum])
            .flat_map(|e| e.to_array())
            .collect();
        let got = (0..5).flat_map(|k| out[r][4 * k..4 * k + 3].to_vec()).collect();
        (got, expected)
    });
    assert!(peak > 1.0, "no probe reached the TT peak: {peak}");
}
