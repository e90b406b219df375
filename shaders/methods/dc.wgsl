// Shadow method "dc": Density Clustering lookup (Mertens, Kautz, Bekaert & Van Reeth 2004, §3.2): K depth
// clusters per texel, each a histogram bin of uniform density, so the optical depth T(z) is piecewise linear
// (visibility::dc::visibility, expression for expression). shaders/dc.wgsl includes this file: its histogram
// pass uses the same bins (dc_bin) and reads the clusters through the same functions.
//
// Maps (RGBA32F array textures, clusters 4g..4g+3 in group g's RGBA):
//   dc_clusters: layer 2g the means mu_j, layer 2g+1 the half-widths D_j (before the overlap rule);
//   dc_accum:    the light passes' additive target; after the histogram pass, layer 2g holds the densities.

#include "common/visibility.wgsl"
#include "common/dc_uniforms.wgsl"

@group(1) @binding(0) var dc_clusters: texture_2d_array<f32>;
@group(1) @binding(1) var dc_accum: texture_2d_array<f32>;
@group(1) @binding(2) var<uniform> dc_uniforms: DcUniforms;

// One texel's clusters: means and half-widths (entries from K on are unused).
struct DcTexel {
    mu: array<f32, 16>,
    d: array<f32, 16>,
}

fn dc_groups() -> u32 {
    return (dc_uniforms.clusters + 3u) / 4u;
}

fn dc_texel(texel: vec2<i32>) -> DcTexel {
    var c: DcTexel;
    for (var g = 0u; g < dc_groups(); g++) {
        let mu = textureLoad(dc_clusters, texel, i32(2u * g), 0);
        let d = textureLoad(dc_clusters, texel, i32(2u * g + 1u), 0);
        for (var i = 0u; i < 4u; i++) {
            c.mu[4u * g + i] = mu[i];
            c.d[4u * g + i] = d[i];
        }
    }
    return c;
}

// Index of the mean nearest to z, the lowest on ties (visibility::dc::nearest).
fn dc_nearest(c: ptr<function, DcTexel>, z: f32) -> u32 {
    var best = 0u;
    for (var j = 1u; j < dc_uniforms.clusters; j++) {
        if abs(z - (*c).mu[j]) < abs(z - (*c).mu[best]) {
            best = j;
        }
    }
    return best;
}

// The edge bins j and j+1 share when their raw extents overlap (x = 1), clamped between the two means
// (visibility::dc::shared_edge).
fn dc_shared_edge(c: ptr<function, DcTexel>, j: u32) -> vec2<f32> {
    let right = (*c).mu[j] + (*c).d[j];
    let left = (*c).mu[j + 1u] - (*c).d[j + 1u];
    let edge = min(max((right + left) * 0.5, (*c).mu[j]), (*c).mu[j + 1u]);
    return vec2<f32>(select(0.0, 1.0, right > left), edge);
}

// Bin j as (L_j, R_j): mu_j -+ D_j, each edge replaced by the shared edge where the bin overlaps its
// neighbour (visibility::dc::bin).
fn dc_bin(c: ptr<function, DcTexel>, j: u32) -> vec2<f32> {
    var lo = (*c).mu[j] - (*c).d[j];
    var hi = (*c).mu[j] + (*c).d[j];
    if j > 0u {
        let e = dc_shared_edge(c, j - 1u);
        if e.x > 0.0 {
            lo = e.y;
        }
    }
    if j + 1u < dc_uniforms.clusters {
        let e = dc_shared_edge(c, j);
        if e.x > 0.0 {
            hi = e.y;
        }
    }
    return vec2<f32>(lo, hi);
}

fn dc_density(texel: vec2<i32>, j: u32) -> f32 {
    return textureLoad(dc_accum, texel, i32(2u * (j / 4u)), 0)[j % 4u];
}

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    var c = dc_texel(texel);
    var t = 0.0;
    for (var j = 0u; j < dc_uniforms.clusters; j++) {
        let bin = dc_bin(&c, j);
        let lo = bin.x;
        let hi = bin.y;
        let ramp = clamp(relative_depth(z, lo, hi), 0.0, 1.0);
        t += dc_density(texel, j) * ramp;
    }
    return transmittance(t);
}
