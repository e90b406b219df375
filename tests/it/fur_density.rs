//! GPU = CPU for the volume pass of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur
//! rendering: combining volumetric fur with explicit hair strands", The Visual Computer, Table 1 step 2; spec
//! B.9 FT-U8): `shaders/fur/density.wgsl`'s volume read back against [`Volume::store`], and
//! `shaders/common/fur_noise.wgsl` alone against [`noise`] through a probe compute pass.
//!
//! Measured on lavapipe (printed by the tests): the PCG hash and the lattice hash bit-exact, the noise within
//! 1.2e-7; the volume's tangents within 2.4e-7 (the hash keys, the shell points' bits, agree everywhere: a
//! wrong key would move a top-layer tangent by ~0.1) and its densities within 8.1e-5, 11 of 577 k
//! sub-elements over 1e-5, all where the clump field is steepest (see [`DENSITY_TOL`]); the uniform volume
//! exact.

use glam::{IVec3, Vec3};
use hairlab::fur::mesh::FurMesh;
use hairlab::fur::noise;
use hairlab::fur::shell::{Levels, Shell, ShellParams};
use hairlab::fur::volume::{Volume, VolumeParams};
use hairlab::gpu::Gpu;
use hairlab::gpu::readback::copy_out;
use hairlab::render::fur::{density, shell_gpu};
use hairlab::rng::SplitMix64;
use hairlab::scene::fur_shapes as shapes;
use std::time::Instant;

/// GPU = CPU tolerance on each noise value.
const NOISE_TOL: f32 = 1e-6;
/// GPU = CPU tolerance on each tangent component.
const TANGENT_TOL: f32 = 1e-6;
/// GPU = CPU tolerance on each density. The clump field is steep: |∇N| ≤ 60 (`noise.rs`' continuity test) at
/// f = 400 per metre through the smoothstep's slope 1.5/(2ε) = 5, 1.2·10^5 per metre, so one f32 ulp of the
/// clump point at 5 cm (3.7·10^-9 m; `x + offset` rounds differently when the offset's sin/cos differ by an
/// ulp) moves ρ by up to 4.5·10^-4. Every sub-element must be within this, and at most [`STEEP_FRACTION`] of
/// them over [`TIGHT_TOL`].
const DENSITY_TOL: f32 = 1e-3;
const TIGHT_TOL: f32 = 1e-5;
const STEEP_FRACTION: f64 = 1e-4;

/// The probe: per point `(x, y, z, seed bits)` the noise's bits, `pcg(seed)` and `hash3(bits of the point, seed)`.
const PROBE: &str = r#"
alias Row = vec4<f32>;
alias Out = vec4<u32>;

fn probe(i: u32, p: Row) {
    let seed = bitcast<u32>(p.w);
    out[i] = vec4<u32>(
        bitcast<u32>(fur_simplex3(p.xyz, seed)),
        fur_pcg(seed),
        fur_hash3(bitcast<vec3<i32>>(p.xyz), seed),
        0u,
    );
}
"#;

/// Runs the probe on `points`; returns its output words.
fn probe(gpu: &Gpu, points: &[[f32; 4]]) -> Vec<[u32; 4]> {
    crate::common::run_probe_rows(gpu, ("common/fur_noise.wgsl", PROBE, "fur_density.probe"), points)
}

/// FT-U8, the noise alone: 2^16 points over [−50, 50]³ (the clump field's range on a 10 cm mesh at f = 400
/// is ±20) under random seeds, and the lattice points near the origin.
#[test]
fn wgsl_noise_equals_the_cpu_noise() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let mut rng = SplitMix64::new(11);
    let mut points: Vec<[f32; 4]> = (0..1 << 16)
        .map(|_| {
            let p = [(); 3].map(|_| rng.range(-50.0, 50.0));
            let seed = (rng.next_u64() >> 32) as u32;
            [p[0], p[1], p[2], f32::from_bits(seed)]
        })
        .collect();
    for i in -2..=2 {
        for j in -2..=2 {
            points.push([i as f32, j as f32, (i - j) as f32, f32::from_bits(7)]);
        }
    }
    let out = probe(&gpu, &points);
    let mut worst = 0.0f32;
    for (p, o) in points.iter().zip(&out) {
        let (v, seed) = (Vec3::new(p[0], p[1], p[2]), p[3].to_bits());
        assert_eq!(o[1], noise::pcg(seed), "pcg({seed})");
        let key = IVec3::from_array([p[0], p[1], p[2]].map(|c| c.to_bits() as i32));
        assert_eq!(o[2], noise::hash3(key, seed), "hash3 at {v}");
        let gpu_value = f32::from_bits(o[0]);
        assert!(gpu_value.is_finite(), "noise at {v}: {gpu_value}");
        worst = worst.max((gpu_value - noise::simplex3(v, seed)).abs());
    }
    println!(
        "fur noise: {} points, hashes bit-exact, max |simplex GPU − CPU| = {worst:.2e}",
        points.len()
    );
    assert!(worst <= NOISE_TOL, "noise differs by {worst}");
}

/// The GPU volume of `shell` under `params` against [`Volume::store`]: (max |Δρ|, max |Δτ| component).
fn volume_difference(gpu: &Gpu, name: &str, shell: &Shell, params: VolumeParams) -> (f32, f32) {
    use wgpu::util::DeviceExt;
    let faces = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fur_density.faces"),
        contents: bytemuck::cast_slice(&shell_gpu::faces(shell)),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let buffer = density::compute_volume(gpu, shell, &faces, &params).unwrap();
    let stored: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &buffer).unwrap());
    let cpu = Volume { params }.store(shell);
    assert_eq!(stored.len(), cpu.len(), "{name}");
    let (mut density, mut tangent) = (0.0f32, 0.0f32);
    let (mut empty, mut bad, mut steep) = (0usize, Vec::new(), 0usize);
    for (g, (s, c)) in stored.iter().zip(&cpu).enumerate() {
        let dr = (s[3] - c.density).abs();
        let dt = (0..3).map(|k| (s[k] - c.tangent[k]).abs()).fold(0.0, f32::max);
        if !(dr <= DENSITY_TOL && dt <= TANGENT_TOL) {
            bad.push((g, *s, *c));
        }
        steep += usize::from(dr > TIGHT_TOL);
        density = density.max(dr);
        tangent = tangent.max(dt);
        empty += usize::from(c.density == 0.0);
    }
    println!(
        "{name}: {} sub-elements ({empty} empty on the CPU), levels {:?}..={:?}, max |Δρ| = {density:.2e} \
         ({steep} over {TIGHT_TOL:e}), max |Δτ| = {tangent:.2e}",
        cpu.len(),
        shell.levels.iter().min(),
        shell.levels.iter().max(),
    );
    assert!(
        bad.is_empty(),
        "{name}: {} sub-elements differ, first {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    assert!(
        steep as f64 <= STEEP_FRACTION * cpu.len() as f64,
        "{name}: {steep} densities differ by more than {TIGHT_TOL}"
    );
    (density, tangent)
}

fn small_shell(name: &str, mesh: &hairlab::scene::Mesh, levels: Levels) -> Shell {
    Shell::build(
        FurMesh::build(name, mesh).unwrap(),
        &ShellParams {
            layers: 4,
            levels,
            ..ShellParams::default()
        },
    )
    .unwrap()
}

/// FT-U8: the cylinder's volume at the test size (4 layers, level ≤ 2), default and uniform parameters.
#[test]
fn gpu_volume_equals_the_cpu_store_on_the_cylinder() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let shell = small_shell(
        "fur-cylinder",
        &shapes::fur_cylinder(),
        Levels::Dynamic { max: 2 },
    );
    volume_difference(&gpu, "cylinder, default volume", &shell, VolumeParams::default());
    let (dr, dt) = volume_difference(&gpu, "cylinder, uniform volume", &shell, VolumeParams::uniform());
    assert_eq!(dr, 0.0, "ρ = 1 everywhere on both");
    assert!(dt <= TANGENT_TOL);
}

/// FT-U8 on mixed levels: the hat (faces of different areas) at levels 0..=3, and every layer count's
/// heights on a uniform level-1 shell of 7 layers (w not a dyadic fraction).
#[test]
fn gpu_volume_equals_the_cpu_store_on_mixed_levels() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let hat = small_shell("fur-hat", &shapes::fur_hat(), Levels::Dynamic { max: 3 });
    let levels: std::collections::BTreeSet<u32> = hat.levels.iter().copied().collect();
    assert!(levels.len() >= 2, "the hat's levels {levels:?} are mixed");
    volume_difference(&gpu, "hat, default volume", &hat, VolumeParams::default());
    let seven = Shell::build(
        FurMesh::build("cylinder", &shapes::cylinder(0.04, 0.1, 16, 4)).unwrap(),
        &ShellParams {
            layers: 7,
            levels: Levels::Uniform(1),
            ..ShellParams::default()
        },
    )
    .unwrap();
    volume_difference(&gpu, "7 layers, default volume", &seven, VolumeParams::default());
}

/// Table 1 row 2 on the `fur-cylinder` preset's shell: the GPU pass (wall time, submission to completion) vs
/// the CPU store, the CPU timed on every 64th sub-element and scaled; those sub-elements compared.
#[test]
fn the_preset_volume_on_the_gpu_and_its_time() {
    use hairlab::fur::settings::FurScene;
    let Some(gpu) = Gpu::for_tests() else { return };
    let s = crate::common::measured_preset("fur-cylinder", &[]);
    let scene = s.scene.build().unwrap();
    let fur = FurScene::build(&scene, &s.fur).unwrap().expect("fur is on");
    let shell = &fur.shell;
    use wgpu::util::DeviceExt;
    let faces = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fur_density.faces"),
        contents: bytemuck::cast_slice(&shell_gpu::faces(shell)),
        usage: wgpu::BufferUsages::STORAGE,
    });
    // Once to compile the pipeline, once timed.
    let mut times = Vec::new();
    let mut buffer = None;
    for _ in 0..2 {
        let start = Instant::now();
        buffer = Some(density::compute_volume(&gpu, shell, &faces, &fur.volume.params).unwrap());
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let stored: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&copy_out(&gpu, &buffer.unwrap()).unwrap());
    assert_eq!(stored.len() as u64, shell.sub_elements);
    let start = Instant::now();
    let (mut density, mut tangent) = (0.0f32, 0.0f32);
    let mut n = 0u64;
    for g in (0..shell.sub_elements).step_by(64) {
        let (f, layer, local) = shell.split_global(g);
        let c = fur.volume.sample(shell, f, layer, local);
        let s = stored[g as usize];
        density = density.max((s[3] - c.density).abs());
        tangent = tangent.max((0..3).map(|k| (s[k] - c.tangent[k]).abs()).fold(0.0, f32::max));
        n += 1;
    }
    let cpu_ms = start.elapsed().as_secs_f64() * 1e3 * shell.sub_elements as f64 / n as f64;
    println!(
        "fur-cylinder preset: {} sub-elements; GPU volume pass {:.0} ms (first, with pipeline creation) / {:.0} ms; \
         CPU store ≈ {cpu_ms:.0} ms (from {n}); over those max |Δρ| = {density:.2e}, max |Δτ| = {tangent:.2e}",
        shell.sub_elements, times[0], times[1]
    );
    assert!(
        density <= DENSITY_TOL && tangent <= TANGENT_TOL,
        "{density} {tangent}"
    );
}
