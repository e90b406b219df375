// One substep of the strand simulation (src/motion/sim.rs is its specification): one thread per strand, walking
// its points in the CPU model's order — Verlet with damping, root pin, global shape, local shape, collision
// (motion/collide.wgsl: the head ellipsoid or a mesh's distance grid), follow-the-leader with re-collision, and the velocity correction. The substep's time-dependent
// values (root frame, sweep, wind per strand phase class, damping factor) are computed on the CPU by the same
// functions the CPU model calls, and arrive in `p`.

#include "motion/collide.wgsl"

// Strands fall into this many wind classes by index (`WIND_CLASSES` in src/motion/sim.rs; the Params layout test
// holds the two equal).
const WIND_CLASSES: u32 = 20u;

struct Params {
    head_rot: vec4<f32>,     // root frame rotation (quaternion xyzw)
    pivot: vec4<f32>,        // xyz: pivot; w: h²
    sweep: vec4<f32>,        // xyz: translation of the swept strands; w: Verlet decay exp(−d·h·60)
    stiffness: vec4<f32>,    // gravity, local ks = 0.5·min(k, 0.95), global stiffness, global range
    damping: vec4<f32>,      // x: ftl_damping
    counts: vec4<u32>,       // x: strands, y: first swept strand
    wind: array<vec4<f32>, WIND_CLASSES>,
};

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> rest: array<f32>;
@group(0) @binding(2) var<storage, read> rest_len: array<f32>;
@group(0) @binding(3) var<storage, read> strands: array<u32>;
@group(0) @binding(4) var<storage, read_write> x: array<f32>;
@group(0) @binding(5) var<storage, read_write> prev: array<f32>;
@group(0) @binding(6) var<storage, read_write> q: array<f32>;
@group(0) @binding(7) var<storage, read_write> corr: array<f32>;

const COLLISION_ROUNDS: u32 = 16u;

fn ld(a: u32) -> vec3<f32> { return vec3<f32>(rest[3u * a], rest[3u * a + 1u], rest[3u * a + 2u]); }
fn lx(a: u32) -> vec3<f32> { return vec3<f32>(x[3u * a], x[3u * a + 1u], x[3u * a + 2u]); }
fn lp(a: u32) -> vec3<f32> { return vec3<f32>(prev[3u * a], prev[3u * a + 1u], prev[3u * a + 2u]); }
fn lq(a: u32) -> vec3<f32> { return vec3<f32>(q[3u * a], q[3u * a + 1u], q[3u * a + 2u]); }
fn lc(a: u32) -> vec3<f32> { return vec3<f32>(corr[3u * a], corr[3u * a + 1u], corr[3u * a + 2u]); }
fn sx(a: u32, v: vec3<f32>) { x[3u * a] = v.x; x[3u * a + 1u] = v.y; x[3u * a + 2u] = v.z; }
fn sp(a: u32, v: vec3<f32>) { prev[3u * a] = v.x; prev[3u * a + 1u] = v.y; prev[3u * a + 2u] = v.z; }
fn sq(a: u32, v: vec3<f32>) { q[3u * a] = v.x; q[3u * a + 1u] = v.y; q[3u * a + 2u] = v.z; }
fn sc(a: u32, v: vec3<f32>) { corr[3u * a] = v.x; corr[3u * a + 1u] = v.y; corr[3u * a + 2u] = v.z; }

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 0.0) { return v * (1.0 / l); }
    return vec3<f32>(0.0);
}

// Quaternion times vector (glam's formula).
fn qrot(r: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = r.xyz;
    let b2 = dot(b, b);
    return v * (r.w * r.w - b2) + b * (dot(v, b) * 2.0) + cross(b, v) * (r.w * 2.0);
}

fn qmul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
        a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
        a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}

fn qnormalize(a: vec4<f32>) -> vec4<f32> { return a * (1.0 / length(a)); }

// The shortest arc from unit `f` to unit `t` (glam's from_rotation_arc).
fn arc(f: vec3<f32>, t: vec3<f32>) -> vec4<f32> {
    let one_minus_eps = 1.0 - 2.0 * 1.1920929e-7;
    let d = dot(f, t);
    if (d > one_minus_eps) { return vec4<f32>(0.0, 0.0, 0.0, 1.0); }
    if (d < -one_minus_eps) {
        let s = select(-1.0, 1.0, f.z >= 0.0);
        let a = -1.0 / (s + f.z);
        let b = f.x * f.y * a;
        let axis = vec3<f32>(b, s + f.y * f.y * a, -f.y);
        return vec4<f32>(axis, 0.0);
    }
    let c = cross(f, t);
    return qnormalize(vec4<f32>(c, 1.0 + d));
}

fn conj(a: vec4<f32>) -> vec4<f32> { return vec4<f32>(-a.xyz, a.w); }

fn pose_apply(v: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    return qrot(p.head_rot, v - p.pivot.xyz) + p.pivot.xyz + t;
}

fn head_inverse(v: vec3<f32>) -> vec3<f32> {
    return qrot(conj(p.head_rot), v - p.pivot.xyz) + p.pivot.xyz;
}

@compute @workgroup_size(64)
fn substep(@builtin(global_invocation_id) id: vec3<u32>) {
    let s = id.x;
    if (s >= p.counts.x) { return; }
    let first = strands[2u * s];
    let n = strands[2u * s + 1u];
    if (n == 0u) { return; }
    let hh = p.pivot.w;
    let decay = p.sweep.w;
    let ks = p.stiffness.y;
    var t = vec3<f32>(0.0);
    if (s >= p.counts.y) { t = p.sweep.xyz; }
    let wind = p.wind[s % WIND_CLASSES].xyz;
    let gravity = vec3<f32>(0.0, -p.stiffness.x, 0.0);
    // 1. Verlet.
    for (var i = 0u; i < n; i++) {
        var a = gravity;
        let xi = lx(first + i);
        if (i > 0u) {
            let seg = normalize_or_zero(xi - lx(first + i - 1u));
            a += wind - seg * dot(seg, wind);
        }
        sq(first + i, xi + (xi - lp(first + i)) * decay + a * hh);
    }
    // 2. Root.
    sq(first, pose_apply(ld(first), t));
    // 3. Global shape.
    if (p.stiffness.z > 0.0) {
        let reach = p.stiffness.w * f32(n);
        for (var i = 1u; i < n; i++) {
            if (f32(i) < reach) {
                let qi = lq(first + i);
                sq(first + i, qi + (pose_apply(ld(first + i), t) - qi) * p.stiffness.z);
            }
        }
    }
    // 4. Local shape.
    if (ks > 0.0) {
        var g = p.head_rot;
        for (var i = 0u; i + 1u < n; i++) {
            var qi = lq(first + i);
            var qn = lq(first + i + 1u);
            let tgt = qi + qrot(g, ld(first + i + 1u) - ld(first + i));
            let del = (tgt - qn) * ks;
            if (i > 0u) { qi = qi - del; sq(first + i, qi); }
            qn = qn + del;
            sq(first + i + 1u, qn);
            let f = normalize_or_zero(tgt - qi);
            let to = normalize_or_zero(qn - qi);
            if (any(f != vec3<f32>(0.0)) && any(to != vec3<f32>(0.0))) {
                g = qnormalize(qmul(arc(f, to), g));
            }
        }
    }
    let collide = collider_on();
    // 5. Collision.
    if (collide) {
        for (var i = 1u; i < n; i++) {
            let out = collide_push(head_inverse(lq(first + i)));
            if (out.w > 0.5) {
                sq(first + i, pose_apply(out.xyz, vec3<f32>(0.0)));
            }
        }
    }
    // 6. Follow the leader, re-colliding.
    sc(first, vec3<f32>(0.0));
    for (var i = 1u; i < n; i++) {
        let lead = lq(first + i - 1u);
        let L = rest_len[first + i];
        let fallback = pose_apply(ld(first + i), t) - pose_apply(ld(first + i - 1u), t);
        let qi = lq(first + i);
        var d = qi - lead;
        var len = length(d);
        var fixed = lead + fallback;
        if (len > 0.0) { fixed = lead + d * (L / len); }
        if (collide) {
            for (var r = 0u; r < COLLISION_ROUNDS; r++) {
                let out = collide_push(head_inverse(fixed));
                if (out.w < 0.5) { break; }
                let pushed = pose_apply(out.xyz, vec3<f32>(0.0));
                d = pushed - lead;
                len = length(d);
                if (len > 0.0) { fixed = lead + d * (L / len); } else { fixed = lead + fallback; }
            }
        }
        sc(first + i, fixed - qi);
        sq(first + i, fixed);
    }
    // 7. Velocity (DFTL) and the new state.
    for (var i = 0u; i < n; i++) {
        var next = vec3<f32>(0.0);
        if (i + 1u < n) { next = lc(first + i + 1u); }
        sp(first + i, lx(first + i) + next * p.damping.x);
        sx(first + i, lq(first + i));
    }
}
