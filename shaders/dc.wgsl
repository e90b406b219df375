// Density Clustering (Mertens, Kautz, Bekaert & Van Reeth 2004, §3.2-3.3), the light passes of
// visibility::dc, expression for expression. Three geometry passes, each additive into the RGBA32F array
// dc_accum (clusters 4g..4g+3 in group g's RGBA), each followed by a compute step:
//   fs_kmeans     (targets: layer 2g sum b, layer 2g+1 sum b z, by nearest initial centre = sub-range of
//                  [near, far]) -> cs_means writes the means mu_j to dc_clusters layer 2g;
//   fs_variance   (layer 2g sum b, layer 2g+1 sum b (mu_j - z)^2, by nearest mean)
//                 -> cs_half_widths writes D_j = sqrt(3) sigma_j to dc_clusters layer 2g+1;
//   fs_histogram  (layer 2g: sum b per bin, off-bin fragments to the nearest mean) = the densities.
#include "common/frame.wgsl"
#include "common/light_vertex.wgsl"
#include "common/visibility.wgsl"
#include "methods/dc.wgsl"

// The shared light-depth maps: nearest and furthest fragment depth per texel (fs_kmeans, cs_means).
@group(1) @binding(3) var dc_near: texture_2d<f32>;
@group(1) @binding(4) var dc_far: texture_2d<f32>;
// dc_clusters as the compute steps write it.
@group(1) @binding(5) var dc_clusters_out: texture_storage_2d_array<rgba32float, write>;

@vertex
fn vs_main(v: LightVertexIn) -> LightFragment {
    return light_vertex(v);
}

// Pass 1 and 2 targets: location 2g is accum layer 2g (sum b), location 2g+1 layer 2g+1 (the weighted sum).
struct DcSums {
    @location(0) b0: vec4<f32>,
    @location(1) x0: vec4<f32>,
    @location(2) b1: vec4<f32>,
    @location(3) x1: vec4<f32>,
    @location(4) b2: vec4<f32>,
    @location(5) x2: vec4<f32>,
    @location(6) b3: vec4<f32>,
    @location(7) x3: vec4<f32>,
}

// Pass 3 targets: location g is accum layer 2g.
struct DcDensities {
    @location(0) b0: vec4<f32>,
    @location(1) b1: vec4<f32>,
    @location(2) b2: vec4<f32>,
    @location(3) b3: vec4<f32>,
}

// v in the channel of cluster j if j is in group g, else 0.
fn dc_one_hot(j: u32, g: u32, v: f32) -> vec4<f32> {
    let c = vec4<u32>(4u * g, 4u * g + 1u, 4u * g + 2u, 4u * g + 3u);
    return select(vec4<f32>(0.0), vec4<f32>(v), c == vec4<u32>(j));
}

fn dc_sums(j: u32, b: f32, x: f32) -> DcSums {
    return DcSums(
        dc_one_hot(j, 0u, b),
        dc_one_hot(j, 0u, x),
        dc_one_hot(j, 1u, b),
        dc_one_hot(j, 1u, x),
        dc_one_hot(j, 2u, b),
        dc_one_hot(j, 2u, x),
        dc_one_hot(j, 3u, b),
        dc_one_hot(j, 3u, x),
    );
}

// Pass 1: the nearest initial centre is the fragment's sub-range j of [near, far].
@fragment
fn fs_kmeans(f: LightFragment) -> DcSums {
    let texel = vec2<i32>(f.clip.xy);
    let near = textureLoad(dc_near, texel, 0).r;
    let far = textureLoad(dc_far, texel, 0).r;
    let z = fragment_depth(f.depth);
    let k = dc_uniforms.clusters;
    let j = slice_index(relative_depth(z, near, far) * f32(k), k);
    let b = optical_depth(f.alpha);
    return dc_sums(j, b, b * z);
}

// Pass 2: the nearest mean; b-weighted squared distance to it.
@fragment
fn fs_variance(f: LightFragment) -> DcSums {
    var c = dc_texel(vec2<i32>(f.clip.xy));
    let z = fragment_depth(f.depth);
    let j = dc_nearest(&c, z);
    let b = optical_depth(f.alpha);
    let d = c.mu[j] - z;
    return dc_sums(j, b, b * d * d);
}

// Pass 3: the first bin holding z, else the nearest mean.
@fragment
fn fs_histogram(f: LightFragment) -> DcDensities {
    var c = dc_texel(vec2<i32>(f.clip.xy));
    let z = fragment_depth(f.depth);
    var j = dc_uniforms.clusters;
    for (var i = 0u; i < dc_uniforms.clusters; i++) {
        let bin = dc_bin(&c, i);
        if bin.x <= z && z <= bin.y {
            j = i;
            break;
        }
    }
    if j == dc_uniforms.clusters {
        j = dc_nearest(&c, z);
    }
    let b = optical_depth(f.alpha);
    return DcDensities(dc_one_hot(j, 0u, b), dc_one_hot(j, 1u, b), dc_one_hot(j, 2u, b), dc_one_hot(j, 3u, b));
}

// After pass 1: mu_j = sum b z / sum b, or the initial centre c_j of an empty cluster.
@compute @workgroup_size(8, 8)
fn cs_means(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(dc_accum)) {
        return;
    }
    let texel = vec2<i32>(id.xy);
    let near = textureLoad(dc_near, texel, 0).r;
    let far = textureLoad(dc_far, texel, 0).r;
    let k = dc_uniforms.clusters;
    for (var g = 0u; g < dc_groups(); g++) {
        let sum_b = textureLoad(dc_accum, texel, i32(2u * g), 0);
        let sum_bz = textureLoad(dc_accum, texel, i32(2u * g + 1u), 0);
        let j = vec4<f32>(f32(4u * g), f32(4u * g + 1u), f32(4u * g + 2u), f32(4u * g + 3u));
        let centre = near + (far - near) * ((j + 0.5) / f32(k));
        textureStore(dc_clusters_out, texel, i32(2u * g), select(centre, sum_bz / sum_b, sum_b > vec4<f32>(0.0)));
    }
}

// After pass 2: D_j = sqrt(3) sigma_j, sigma_j^2 = sum b (mu_j - z)^2 / sum b (0 for an empty cluster).
@compute @workgroup_size(8, 8)
fn cs_half_widths(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(dc_accum)) {
        return;
    }
    let texel = vec2<i32>(id.xy);
    for (var g = 0u; g < dc_groups(); g++) {
        let sum_b = textureLoad(dc_accum, texel, i32(2u * g), 0);
        let sum_bdd = textureLoad(dc_accum, texel, i32(2u * g + 1u), 0);
        let variance = select(vec4<f32>(0.0), sum_bdd / sum_b, sum_b > vec4<f32>(0.0));
        textureStore(dc_clusters_out, texel, i32(2u * g + 1u), 1.7320508 * sqrt(variance));
    }
}
