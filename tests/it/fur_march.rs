//! The CPU shell ray march (spec B.5, B.9 FT-U6; FC-2, FC-6): a homogeneous slab against `exp(−σ·path)`
//! by hand, the light march and the base mesh's shadow by hand, the `ε_T` cut-off's error bound, virtual
//! fragments against the single shell fragment and the error of coarser groups against `k = 1`, convergence
//! as `Δs` halves, determinism under triangle permutation, the stop reasons on the paper's cylinder, and lost
//! rays on the head and the cylinder.

use glam::Vec3;
use hairlab::fur::march::{self, Emit, Fragment, MarchParams, MarchStats, Stop, composite, entry};
use hairlab::fur::mesh::FurMesh;
use hairlab::fur::shell::{Levels, Shell, ShellParams};
use hairlab::fur::volume::{Volume, VolumeParams};
use hairlab::rng::SplitMix64;
use hairlab::scene::Mesh;
use hairlab::scene::fur_shapes as shapes;
use hairlab::scene::generate::{GenKind, GenParams, generate};

/// A flat `n × n` grid of quads on z = 0, `size` wide, wound towards +z.
fn grid(n: u32, size: f32) -> Mesh {
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            positions.push(Vec3::new(j as f32, i as f32, 0.0) * (size / n as f32));
        }
    }
    let v = |i: u32, j: u32| i * (n + 1) + j;
    let mut indices = Vec::new();
    for i in 0..n {
        for j in 0..n {
            indices.extend_from_slice(&[
                v(i, j),
                v(i, j + 1),
                v(i + 1, j + 1),
                v(i, j),
                v(i + 1, j + 1),
                v(i + 1, j),
            ]);
        }
    }
    Mesh {
        normals: vec![Vec3::Z; positions.len()],
        positions,
        indices,
        color: Vec3::ONE,
    }
}

fn slab(height: f32) -> Shell {
    let m = FurMesh::build("slab", &grid(8, 1.0)).unwrap();
    Shell::build(
        m,
        &ShellParams {
            height,
            layers: 4,
            cell: None,
            levels: Levels::Uniform(2),
        },
    )
    .unwrap()
}

fn cylinder_shell(mesh: &Mesh) -> Shell {
    Shell::build(
        FurMesh::build("fur-cylinder", mesh).unwrap(),
        &ShellParams::default(),
    )
    .unwrap()
}

fn uniform() -> Volume {
    Volume {
        params: VolumeParams::uniform(),
    }
}

fn fur() -> Volume {
    Volume {
        params: VolumeParams::default(),
    }
}

/// Premultiplied colour and alpha of fragments composited alone over black.
fn over(f: &[Fragment]) -> (Vec3, f32) {
    composite(f, Vec3::ZERO)
}

/// A camera ray from `radius` around `centre` to a random point inside a random prism, with its entry.
fn random_ray(s: &Shell, centre: Vec3, radius: f32, rng: &mut SplitMix64) -> Option<(Vec3, Vec3, f32, u32)> {
    let f = rng.int(0, s.mesh.faces.len() - 1);
    let (u, v) = (rng.unit(), rng.unit());
    let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
    let target = s.point(f, [1.0 - u - v, u, v], rng.range(0.05, 0.95));
    let dir = Vec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
    let o = centre + radius * dir;
    let r = (target - o).normalize();
    entry(s, o, r).map(|(t, face)| (o, r, t, face))
}

#[test]
fn fur_march_a_constant_slab_transmits_exp_minus_sigma_path() {
    let h = 0.1;
    let s = slab(h);
    let sigma = 10.0;
    for (dir, n) in [(Vec3::NEG_Z, 20u32), (Vec3::new(0.3, 0.2, -1.0).normalize(), 40)] {
        let path = h / -dir.z;
        let o = Vec3::new(0.43, 0.57, 0.0) - 2.0 * dir;
        let (t0, face) = entry(&s, o, dir).expect("the ray enters the slab's top");
        assert!((t0 - (2.0 - path)).abs() < 1e-5, "t0 {t0}");
        let p = MarchParams {
            sigma,
            step: path / n as f32,
            epsilon_t: 0.0,
            light_steps: 0,
            to_light: Vec3::new(1.0, 0.0, 1.0).normalize(),
            ..MarchParams::for_shell(&s)
        };
        let m = march::march(&s, &uniform(), &p, o, dir, t0, face);
        let expect = (-sigma * path).exp();
        assert_eq!((m.stop, m.steps), (Stop::Base, n));
        assert!(
            (m.transmittance - expect).abs() < 1e-5,
            "T {} vs {expect}",
            m.transmittance
        );
        assert_eq!(m.fragments.len(), 1);
        let f = m.fragments[0];
        assert_eq!(f.t, t0);
        assert!((f.alpha - (1.0 - expect)).abs() < 1e-5, "α {}", f.alpha);
        // A homogeneous medium has one phase value φ, so c = L/α = φ. For the vertical ray τ = e = +z and
        // l at 45°: Kajiya–Kay gives 0.75·sin 45°·base + 0.35·cos⁶⁰45° (3·10⁻¹⁰).
        if dir == Vec3::NEG_Z {
            let phi = p.colour * (0.75 * std::f32::consts::FRAC_1_SQRT_2);
            assert!(
                (f.colour - phi).abs().max_element() < 1e-5,
                "c {} vs {phi}",
                f.colour
            );
        }
    }
}

#[test]
fn fur_march_the_light_march_by_hand() {
    // Slab h = 0.1, ρ = 1, σ = 10, vertical eye ray, Δs = 0.01 (σΔs = 0.1), light straight up, Δs_l = 0.0125,
    // 8 light steps. τ = l = e = +z: Kajiya–Kay has no diffuse and a full specular cone, φ = 0.35 (grey).
    // Eye sample k sits (k + ½)Δs under the top; light sample j is inside while (j + ½)Δs_l < (k + ½)Δs
    // (never equal), so T_light,k = e^{−σ Δs_l n_k}, n_k = #{j < 8 : (j + ½)·1.25 < k + ½}.
    let s = slab(0.1);
    let o = Vec3::new(0.43, 0.57, 1.0);
    let (t0, face) = entry(&s, o, Vec3::NEG_Z).unwrap();
    let p = MarchParams {
        sigma: 10.0,
        step: 0.01,
        epsilon_t: 0.0,
        light_steps: 8,
        light_step: 0.0125,
        to_light: Vec3::Z,
        ..MarchParams::for_shell(&s)
    };
    let m = march::march(&s, &uniform(), &p, o, Vec3::NEG_Z, t0, face);
    let mut expect = 0.0f64;
    for k in 0..10 {
        let n = (0..8)
            .filter(|&j| (f64::from(j) + 0.5) * 1.25 < f64::from(k) + 0.5)
            .count();
        let t_light = (-10.0 * 0.0125 * n as f64).exp();
        expect += (-0.1 * f64::from(k)).exp() * (1.0 - (-0.1f64).exp()) * 0.35 * t_light;
    }
    assert_eq!((m.stop, m.steps), (Stop::Base, 10));
    let grey = Vec3::splat(expect as f32);
    assert!(
        (m.radiance - grey).abs().max_element() < 1e-6,
        "L {} vs {expect}",
        m.radiance
    );
    // Light from below at 45° (diffuse 0.75·sin 45° > 0): 16 light steps reach 0.2 along it, past every
    // sample's √2·(height) ≤ 0.141 to the base, so the base mesh shadows every sample: L = 0 while α stays
    // 1 − e^{−1}. Without the light march the same light shades the fur.
    let below = MarchParams {
        to_light: Vec3::new(1.0, 0.0, -1.0).normalize(),
        light_steps: 16,
        ..p
    };
    let m = march::march(&s, &uniform(), &below, o, Vec3::NEG_Z, t0, face);
    assert_eq!(m.radiance, Vec3::ZERO);
    let unshadowed = march::march(
        &s,
        &uniform(),
        &MarchParams {
            light_steps: 0,
            ..below
        },
        o,
        Vec3::NEG_Z,
        t0,
        face,
    );
    assert!(
        unshadowed.radiance.min_element() > 0.01,
        "{}",
        unshadowed.radiance
    );
    assert!((m.transmittance - (-1.0f32).exp()).abs() < 1e-6);
}

#[test]
fn fur_march_epsilon_t_stops_early_within_epsilon() {
    // Slab by hand: σΔs = 0.1, so T = e^{−0.1 n} first drops under 10⁻³ at n = 70 (e^{−6.9} = 1.008·10⁻³).
    let s = slab(0.1);
    let o = Vec3::new(0.43, 0.57, 1.0);
    let (t0, face) = entry(&s, o, Vec3::NEG_Z).unwrap();
    let p = MarchParams {
        sigma: 100.0,
        step: 0.001,
        light_steps: 0,
        ..MarchParams::for_shell(&s)
    };
    let m = march::march(&s, &uniform(), &p, o, Vec3::NEG_Z, t0, face);
    assert_eq!((m.stop, m.steps), (Stop::Transmittance, 70));
    // On the furred cylinder over random rays: the cut-off changes α and L by at most ε_T (times the largest
    // radiance a step can carry, (0.75·max colour + 0.35)·light).
    let s = cylinder_shell(&shapes::fur_cylinder());
    let mut rng = SplitMix64::new(11);
    let base = MarchParams {
        sigma: 40.0 / s.height,
        max_steps: 4096,
        ..MarchParams::for_shell(&s)
    };
    let bound = 0.75 * base.colour.max_element() + 0.35;
    let (mut early, mut worst_a, mut worst_l) = (0, 0.0f32, 0.0f32);
    for _ in 0..200 {
        let Some((o, r, t0, face)) = random_ray(&s, Vec3::new(0.0, 0.15, 0.0), 0.5, &mut rng) else {
            continue;
        };
        let cut = march::march(&s, &fur(), &base, o, r, t0, face);
        let full = march::march(
            &s,
            &fur(),
            &MarchParams {
                epsilon_t: 0.0,
                ..base
            },
            o,
            r,
            t0,
            face,
        );
        early += usize::from(cut.stop == Stop::Transmittance);
        let (a_cut, a_full) = (1.0 - cut.transmittance, 1.0 - full.transmittance);
        worst_a = worst_a.max(a_full - a_cut);
        worst_l = worst_l.max((full.radiance - cut.radiance).abs().max_element());
        assert!(cut.steps <= full.steps);
    }
    println!("ε_T = 1e-3: {early}/200 rays stopped early; worst Δα {worst_a:.3e}, worst ΔL {worst_l:.3e}");
    assert!(early > 20, "{early} rays stopped early");
    assert!((0.0..=base.epsilon_t).contains(&worst_a), "Δα {worst_a}");
    assert!(worst_l <= base.epsilon_t * bound, "ΔL {worst_l}");
}

#[test]
fn fur_march_fc2_virtual_fragments_equal_the_shell_fragment_and_converge_as_k_shrinks() {
    let s = cylinder_shell(&shapes::fur_cylinder());
    let mut rng = SplitMix64::new(7);
    let base = MarchParams {
        epsilon_t: 0.0,
        ..MarchParams::for_shell(&s)
    };
    let ks = [32u32, 16, 8, 4, 2];
    let mut err = [0.0f64; 5];
    let (mut rays, mut worst) = (0, 0.0f32);
    while rays < 150 {
        let Some((o, r, t0, face)) = random_ray(&s, Vec3::new(0.0, 0.15, 0.0), 0.5, &mut rng) else {
            continue;
        };
        let single = march::march(&s, &fur(), &base, o, r, t0, face);
        if single.fragments.is_empty() || single.steps < 8 {
            continue;
        }
        rays += 1;
        let (c1, a1) = over(&single.fragments);
        let virt = |k| {
            march::march(
                &s,
                &fur(),
                &MarchParams {
                    emit: Emit::Virtual(k),
                    ..base
                },
                o,
                r,
                t0,
                face,
            )
        };
        for k in [1, 2, 5, 17, base.max_steps] {
            let v = virt(k);
            assert!(v.fragments.len() as u32 <= v.steps.div_ceil(k), "k {k}");
            let (c, a) = over(&v.fragments);
            worst = worst.max((c - c1).abs().max_element()).max((a - a1).abs());
            assert!(
                (c - c1).abs().max_element() < 1e-5 && (a - a1).abs() < 1e-5,
                "k {k}: {c} {a} vs {c1} {a1}"
            );
        }
        // A guard-hair fragment somewhere inside the march, sorted in with the virtual fragments.
        let t_end = t0 + single.steps as f32 * base.step;
        let guard = Fragment {
            t: rng.range(t0, t_end),
            colour: Vec3::ONE,
            alpha: 0.5,
        };
        let with_guard = |k| {
            let mut f = virt(k).fragments;
            f.push(guard);
            over(&f).0
        };
        let reference = with_guard(1);
        for (e, &k) in err.iter_mut().zip(&ks) {
            *e += f64::from((with_guard(k) - reference).abs().max_element());
        }
    }
    let err = err.map(|e| e / rays as f64);
    println!("FC-2a: worst |virtual − shell| over k ∈ {{1, 2, 5, 17, 256}}: {worst:.2e} ({rays} rays)");
    println!(
        "FC-2b: mean max-channel error vs k = 1 with one guard fragment inside, k = {ks:?}: {:?}",
        sci(&err)
    );
    for i in 1..ks.len() {
        assert!(
            err[i] < err[i - 1],
            "k = {} error {} ≥ k = {} error {}",
            ks[i],
            err[i],
            ks[i - 1],
            err[i - 1]
        );
    }
    assert!(err[ks.len() - 1] > 0.0);
}

#[test]
fn fur_march_halving_the_step_converges() {
    let s = cylinder_shell(&shapes::fur_cylinder());
    let mut rng = SplitMix64::new(3);
    let base = MarchParams {
        epsilon_t: 0.0,
        max_steps: 1 << 20,
        light_steps: 4,
        ..MarchParams::for_shell(&s)
    };
    let steps = [1.0f32, 0.5, 0.25, 0.125].map(|f| base.step * f);
    let mut err = [0.0f64; 4];
    let mut rays = 0;
    while rays < 40 {
        let Some((o, r, t0, face)) = random_ray(&s, Vec3::new(0.0, 0.15, 0.0), 0.5, &mut rng) else {
            continue;
        };
        let run = |step: f32| march::march(&s, &fur(), &MarchParams { step, ..base }, o, r, t0, face);
        let reference = run(base.step / 64.0);
        if reference.stop != Stop::Base && reference.stop != Stop::Top && reference.stop != Stop::Boundary {
            panic!("reference stopped by {:?}", reference.stop);
        }
        rays += 1;
        for (e, &step) in err.iter_mut().zip(&steps) {
            let m = run(step);
            *e += f64::from((m.transmittance - reference.transmittance).abs())
                + f64::from((m.radiance - reference.radiance).abs().max_element());
        }
    }
    let err = err.map(|e| e / rays as f64);
    let orders: Vec<f64> = (1..4).map(|i| (err[i - 1] / err[i]).log2()).collect();
    println!(
        "Δs halving (Δs₀ = h/32, reference Δs₀/64): mean |ΔT| + |ΔL| = {:?}, orders {orders:.2?}",
        sci(&err)
    );
    for i in 1..4 {
        assert!(err[i] < err[i - 1], "error rose at Δs₀/{}: {err:?}", 1 << i);
    }
    let mean_order = orders.iter().sum::<f64>() / 3.0;
    assert!(mean_order > 0.5, "mean order {mean_order}");
}

fn sci(v: &[f64]) -> Vec<String> {
    v.iter().map(|e| format!("{e:.3e}")).collect()
}

/// `m` with its triangles in the order `order` (corners kept in place).
fn permuted(m: &Mesh, order: &[usize]) -> Mesh {
    let tris: Vec<&[u32]> = m.indices.chunks_exact(3).collect();
    Mesh {
        indices: order.iter().flat_map(|&t| tris[t].iter().copied()).collect(),
        ..m.clone()
    }
}

fn bits(m: &march::March) -> (Vec<[u32; 5]>, Stop, u32, u32) {
    let f = m
        .fragments
        .iter()
        .map(|f| {
            [
                f.t.to_bits(),
                f.colour.x.to_bits(),
                f.colour.y.to_bits(),
                f.colour.z.to_bits(),
                f.alpha.to_bits(),
            ]
        })
        .collect();
    (f, m.stop, m.steps, m.hops)
}

#[test]
fn fur_march_fc6_runs_and_permuted_triangles_are_bit_identical() {
    let mesh = shapes::fur_cylinder();
    let n = mesh.indices.len() / 3;
    let reverse: Vec<usize> = (0..n).rev().collect();
    let mut shuffle: Vec<usize> = (0..n).collect();
    let mut rng = SplitMix64::new(9);
    for i in (1..n).rev() {
        shuffle.swap(i, rng.int(0, i));
    }
    let a = cylinder_shell(&mesh);
    let mut compared = 0;
    for order in [reverse, shuffle] {
        let b = cylinder_shell(&permuted(&mesh, &order));
        for emit in [Emit::Shell, Emit::Virtual(4)] {
            let p = MarchParams {
                emit,
                ..MarchParams::for_shell(&a)
            };
            for _ in 0..30 {
                let Some((o, r, t0, fa)) = random_ray(&a, Vec3::new(0.0, 0.15, 0.0), 0.5, &mut rng) else {
                    continue;
                };
                let (tb, fb) = entry(&b, o, r).unwrap();
                assert_eq!(tb.to_bits(), t0.to_bits());
                let source = order[b.mesh.source_faces[fb as usize] as usize];
                assert_eq!(a.mesh.source_faces[fa as usize] as usize, source);
                let first = march::march(&a, &fur(), &p, o, r, t0, fa);
                assert_eq!(bits(&first), bits(&march::march(&a, &fur(), &p, o, r, t0, fa)));
                assert_eq!(bits(&first), bits(&march::march(&b, &fur(), &p, o, r, tb, fb)));
                compared += usize::from(!first.fragments.is_empty());
            }
        }
    }
    assert!(compared > 60, "{compared} rays with fragments");
}

#[test]
fn fur_march_rays_leave_through_the_top_the_base_and_the_open_end() {
    let s = cylinder_shell(&shapes::fur_cylinder());
    let p = MarchParams {
        epsilon_t: 0.0,
        ..MarchParams::for_shell(&s)
    };
    let run = |o: Vec3, r: Vec3| {
        let r = r.normalize();
        let (t0, face) = entry(&s, o, r).expect("the ray enters the shell");
        (t0, march::march(&s, &fur(), &p, o, r, t0, face))
    };
    // Base radius 0.04, top 0.05. A chord at x = 0.045 stays in the shell and leaves through the top; at
    // y = 0.15 it runs exactly along ring 14's edges (the side tolerance keeps it from hopping to and fro).
    for y in [0.155, 0.15] {
        let (_, m) = run(Vec3::new(0.045, y, -1.0), Vec3::Z);
        assert_eq!((m.stop, m.hops > 0), (Stop::Top, true), "y {y}");
    }
    // Straight at the axis: through 0.01 of fur into the skin.
    let (t0, m) = run(Vec3::new(0.0, 0.15, -1.0), Vec3::Z);
    assert_eq!(m.stop, Stop::Base);
    assert!(
        (t0 - 0.95).abs() < 1e-4 && m.steps.abs_diff(32) <= 1,
        "t0 {t0}, {} steps",
        m.steps
    );
    // Entering the top near the end (y = 0.29) and heading out along the axis: across the open ring.
    let (_, m) = run(Vec3::new(0.07, 0.25, 0.001), Vec3::new(-1.0, 2.0, 0.0));
    assert_eq!(m.stop, Stop::Boundary);
    // Through the end's wall along the fur (0.3 long = 960 steps): the step cap, counted as capped.
    let (t0, m) = run(Vec3::new(0.045, 0.4, 0.001), Vec3::NEG_Y);
    assert!((t0 - 0.1).abs() < 1e-5, "t0 {t0}");
    assert_eq!((m.stop, m.steps), (Stop::MaxSteps, p.max_steps));
    let mut stats = MarchStats::default();
    stats.add(&m);
    assert_eq!(
        (stats.capped, stats.lost, stats.steps),
        (1, 0, u64::from(p.max_steps))
    );
}

fn head() -> Mesh {
    let p = GenParams {
        kind: GenKind::Head,
        strands: 10,
        segments: 2,
        clumps: 0,
        floor: false,
        ..GenParams::default()
    };
    generate(&p).unwrap().meshes.remove(0)
}

#[test]
fn fur_march_no_ray_is_lost_on_the_head_or_the_cylinder() {
    let head = FurMesh::build("head", &head()).unwrap();
    let (lo, hi) = head
        .positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), &p| {
            (l.min(p), h.max(p))
        });
    let head = Shell::build(
        head,
        &ShellParams {
            height: 0.01,
            layers: 8,
            cell: None,
            levels: Levels::Dynamic { max: 6 },
        },
    )
    .unwrap();
    let cases = [
        ("head", head, (lo + hi) / 2.0, (hi - lo).length()),
        (
            "fur-cylinder",
            cylinder_shell(&shapes::fur_cylinder()),
            Vec3::new(0.0, 0.15, 0.0),
            0.5,
        ),
    ];
    for (name, s, centre, radius) in cases {
        let mut rng = SplitMix64::new(21);
        let p = MarchParams {
            epsilon_t: 0.0,
            ..MarchParams::for_shell(&s)
        };
        let mut stats = MarchStats::default();
        let mut stops = std::collections::HashMap::new();
        for _ in 0..300 {
            let Some((o, r, t0, face)) = random_ray(&s, centre, radius, &mut rng) else {
                continue;
            };
            let m = march::march(&s, &fur(), &p, o, r, t0, face);
            *stops.entry(format!("{:?}", m.stop)).or_insert(0) += 1;
            stats.add(&m);
        }
        println!("{name}: {stats:?}, stops {stops:?}");
        assert!(
            stats.rays > 250 && stats.steps > 0 && stats.light_steps > 0,
            "{name}: {stats:?}"
        );
        assert_eq!((stats.lost, stats.light_lost), (0, 0), "{name}: {stats:?}");
    }
}
