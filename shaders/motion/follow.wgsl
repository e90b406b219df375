// Guide-and-follow interpolation (src/motion/follow.rs is its specification): one thread per follower strand
// rebuilds its points as its rest shape carried by the root frame's pose plus the weighted deviation of its
// guides from their posed rest shapes at the same place along the strand, each segment then put back to its
// rest length from the root (follow the leader), after the guides' substeps; a point that lands inside the
// collider (motion/collide.wgsl) is pushed out and put back on its leader's sphere, as in the simulation.

#include "motion/collide.wgsl"

struct FollowParams {
    head_rot: vec4<f32>,     // root frame rotation (quaternion xyzw)
    pivot: vec4<f32>,        // xyz: pivot
    translation: vec4<f32>,  // xyz: the pose's translation
    counts: vec4<u32>,       // x: followers
};

const COLLISION_ROUNDS: u32 = 16u;

@group(0) @binding(0) var<uniform> p: FollowParams;
@group(0) @binding(1) var<storage, read> rest: array<f32>;
// Per follower: its (first, n) and its three guides' (first, n).
@group(0) @binding(2) var<storage, read> table: array<u32>;
// Per follower: the three guides' weights (and a pad).
@group(0) @binding(3) var<storage, read> weights: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> x: array<f32>;

fn ld(a: u32) -> vec3<f32> { return vec3<f32>(rest[3u * a], rest[3u * a + 1u], rest[3u * a + 2u]); }
fn lx(a: u32) -> vec3<f32> { return vec3<f32>(x[3u * a], x[3u * a + 1u], x[3u * a + 2u]); }
fn sx(a: u32, v: vec3<f32>) { x[3u * a] = v.x; x[3u * a + 1u] = v.y; x[3u * a + 2u] = v.z; }

// Quaternion times vector (glam's formula).
fn qrot(r: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = r.xyz;
    let b2 = dot(b, b);
    return v * (r.w * r.w - b2) + b * (dot(v, b) * 2.0) + cross(b, v) * (r.w * 2.0);
}

fn pose_apply(v: vec3<f32>) -> vec3<f32> {
    return qrot(p.head_rot, v - p.pivot.xyz) + p.pivot.xyz + p.translation.xyz;
}

fn pose_inverse(v: vec3<f32>) -> vec3<f32> {
    let r = p.head_rot;
    return qrot(vec4<f32>(-r.xyz, r.w), v - p.pivot.xyz - p.translation.xyz) + p.pivot.xyz;
}

// Point `to` put on the sphere of its leader at `lead` (segment `i` of a strand starting at `first`).
fn follow_leader(lead: vec3<f32>, to: vec3<f32>, first: u32, i: u32) -> vec3<f32> {
    let d = to - lead;
    let len = length(d);
    if (len > 0.0) {
        return lead + d * (length(ld(first + i) - ld(first + i - 1u)) / len);
    }
    return lead + (pose_apply(ld(first + i)) - pose_apply(ld(first + i - 1u)));
}

// A guide's deviation from its posed rest shape at parameter u (linear between its points).
fn deviation(first: u32, n: u32, u: f32) -> vec3<f32> {
    let at = u * f32(n - 1u);
    let j0 = min(u32(floor(at)), n - 1u);
    let j1 = min(j0 + 1u, n - 1u);
    let t = at - f32(j0);
    let d0 = lx(first + j0) - pose_apply(ld(first + j0));
    let d1 = lx(first + j1) - pose_apply(ld(first + j1));
    return d0 + (d1 - d0) * t;
}

@compute @workgroup_size(64)
fn follow(@builtin(global_invocation_id) id: vec3<u32>) {
    let f = id.x;
    if (f >= p.counts.x) { return; }
    let first = table[8u * f];
    let n = table[8u * f + 1u];
    let w = weights[f];
    for (var i = 0u; i < n; i++) {
        var u = 0.0;
        if (n > 1u) { u = f32(i) / f32(n - 1u); }
        var d = vec3<f32>(0.0);
        for (var g = 0u; g < 3u; g++) {
            let gn = table[8u * f + 3u + 2u * g];
            if (gn > 0u) {
                d += deviation(table[8u * f + 2u + 2u * g], gn, u) * w[g];
            }
        }
        var q = pose_apply(ld(first + i)) + d;
        if (i > 0u) {
            // Follow the leader: the segment back to its rest length, out of the head if it lands inside.
            let lead = lx(first + i - 1u);
            q = follow_leader(lead, q, first, i);
            if (collider_on()) {
                for (var r = 0u; r < COLLISION_ROUNDS; r++) {
                    let out = collide_push(pose_inverse(q));
                    if (out.w < 0.5) { break; }
                    q = follow_leader(lead, pose_apply(out.xyz), first, i);
                }
            }
        }
        sx(first + i, q);
    }
}
