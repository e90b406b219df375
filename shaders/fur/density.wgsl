// The volume pass of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering:
// combining volumetric fur with explicit hair strands", The Visual Computer, Table 1 step 2: "a compute shader
// to generate the volumetric data set based on simplex noise"; spec B.3 #11–13): one invocation per
// sub-element writes its `(τ.xyz, ρ)`, `Volume::sample` ported line for line, in global-index order (eq. 3
// decision, `Shell::split_global`). The per-layer heights `w` and `w^γ` are the CPU's own values (a table), so
// that the shell point whose f32 bits key the hashes is the CPU's wherever the products and sums round alike.
#include "common/fur_face.wgsl"
#include "common/fur_noise.wgsl"

// Mirrors `render::fur::density::FurDensityUniforms` (a test compares the layouts).
struct FurDensityUniforms {
    // The clump field (`Clumps`): frequency f, threshold θ, half width ε, jitter J (γ is in the height table).
    frequency: f32,
    threshold: f32,
    softness: f32,
    jitter: f32,
    // Density control v_d, f_d; length control v_ℓ, f_ℓ.
    density_variation: f32,
    density_frequency: f32,
    length_variation: f32,
    length_frequency: f32,
    // Tangent randomisation J_t.
    tangent_jitter: f32,
    // 1 with the clump field, 0 without (C = 1).
    clumps: u32,
    // Faces, and sub-elements in all.
    faces: u32,
    sub_elements: u32,
    // Invocations per dispatch row (global index = id.y · row + id.x).
    row: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> density: FurDensityUniforms;
@group(0) @binding(1) var<storage, read> faces: array<FurFace>;
// Per face its corners' smoothed vertex normals N_k (w unused).
@group(0) @binding(2) var<storage, read> normals: array<array<vec4<f32>, 3>>;
// Per layer (w, w^γ): w = (i_l + ½)/n_l, and w^γ as `f32::powf` gives it (0 without clumps).
@group(0) @binding(3) var<storage, read> heights: array<vec2<f32>>;
// Per sub-element (global index): (τ.xyz, ρ).
@group(0) @binding(4) var<storage, read_write> volume: array<vec4<f32>>;

// `volume.rs`' seeds.
const SEED_CLUMPS: u32 = 0x1f123bb5u;
const SEED_DENSITY: u32 = 0x5d7a91c3u;
const SEED_LENGTH: u32 = 0x9e3779b9u;
const SEED_JITTER: u32 = 0x2545f491u;
const SEED_TANGENT: u32 = 0x6c8e9cf5u;
const TAU: f32 = 6.283185307179586;
// 2^−24, exact.
const INV_2_24: f32 = 1.0 / 16777216.0;

// `volume::smoothstep` (Hermite, written out: the builtin's edge cases are the driver's).
fn fur_smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    let t = clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// glam's `Vec3::normalize`: v · (1/|v|).
fn fur_normalize(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / sqrt(fur_dot(v, v)));
}

// `volume::random_unit`: a unit vector from hash h (z and the azimuth from two hashes).
fn random_unit(h: u32) -> vec3<f32> {
    let a = fur_pcg(h);
    let b = fur_pcg(a);
    let z = 2.0 * f32(a >> 8u) * INV_2_24 - 1.0;
    let phi = TAU * f32(b >> 8u) * INV_2_24;
    let r = sqrt(max(1.0 - z * z, 0.0));
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// `index::SubTriangle::from_index(i, d).centroid(d)`: the barycentrics of local sub-triangle i's centroid.
fn centroid(i: u32, d: u32) -> vec3<f32> {
    let n = 1 << d;
    // ⌊√i⌋ for i < 4^10, from the f32 root then corrected.
    var root = u32(sqrt(f32(i)));
    if root * root > i {
        root -= 1u;
    }
    if (root + 1u) * (root + 1u) <= i {
        root += 1u;
    }
    let i0 = i32(root);
    let r = i32(i) - i0 * i0 - i0;
    let up = (r + i0) % 2 == 0;
    let sum = select(2 * n - 1 - i0, 2 * n - 2 - i0, up);
    let ix = vec3<i32>(i0, (sum + r) / 2, (sum - r) / 2);
    let cell = vec3<f32>(vec3<i32>(n - 1) - ix);
    let off = select(2.0 / 3.0, 1.0 / 3.0, up);
    // ÷ 2^d as a product by 2^−d built from its bits: exact, as the CPU's division.
    return (cell + vec3<f32>(off)) * bitcast<f32>((127u - d) << 23u);
}

// `Shell::split_global`: the face of global index g, the last whose offset is ≤ g.
fn face_of(g: u32) -> u32 {
    var lo = 0u;
    var hi = density.faces;
    while hi - lo > 1u {
        let mid = (lo + hi) / 2u;
        if faces[mid].offset <= g {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

@compute @workgroup_size(256)
fn cs_volume(@builtin(global_invocation_id) id: vec3<u32>) {
    let g = id.y * density.row + id.x;
    if g >= density.sub_elements {
        return;
    }
    let f = face_of(g);
    let face = faces[f];
    let d = face.level;
    let r = g - face.offset;
    let layer = r >> (2u * d);
    let local = r & ((1u << (2u * d)) - 1u);
    let lambda = centroid(local, d);
    let h = heights[layer];
    let w = h.x;
    let b = array<vec3<f32>, 3>(face.base[0].xyz, face.base[1].xyz, face.base[2].xyz);
    let t = array<vec3<f32>, 3>(face.top[0].xyz, face.top[1].xyz, face.top[2].xyz);
    let x = lambda[0] * b[0] + lambda[1] * b[1] + lambda[2] * b[2];
    // `Shell::point`: Σ λ_k lerp(P_k, T_k, w), glam's lerp P·(1 − w) + T·w, summed from zero.
    var point = vec3<f32>(0.0);
    var smoothed = vec3<f32>(0.0);
    let nk = normals[f];
    for (var k = 0u; k < 3u; k++) {
        point += lambda[k] * (b[k] * (1.0 - w) + t[k] * w);
        smoothed += lambda[k] * nk[k].xyz;
    }
    let key = bitcast<vec3<i32>>(point);
    let length = 1.0 - density.length_variation
        * (0.5 + 0.5 * fur_simplex3(x * density.length_frequency, SEED_LENGTH));
    let n = fur_normalize(smoothed);
    let tangent = fur_normalize(n + w * density.tangent_jitter * random_unit(fur_hash3(key, SEED_TANGENT)));
    if w > length {
        volume[g] = vec4<f32>(tangent, 0.0);
        return;
    }
    let control = 1.0 - density.density_variation
        * (0.5 + 0.5 * fur_simplex3(x * density.density_frequency, SEED_DENSITY));
    var clumps = 1.0;
    if density.clumps != 0u {
        let offset = h.y * density.jitter * random_unit(fur_hash3(key, SEED_JITTER));
        let v = fur_simplex3((x + offset) * density.frequency, SEED_CLUMPS);
        clumps = fur_smoothstep(density.threshold - density.softness, density.threshold + density.softness, v);
    }
    volume[g] = vec4<f32>(tangent, control * clumps);
}
