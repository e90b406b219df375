// The shell pass of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
// volumetric fur with explicit hair strands", The Visual Computer, §3.2; spec B.5): the shell's entry
// triangles (B.3 #6) are rasterised, and each fragment marches its pixel's eye ray through the prisms. A port
// of `src/fur/march.rs`, function for function: `prism_locate` is `Shell::locate`, `walk` is `march::locate`,
// `light_transmittance` and `march_group` are the march (one call per group of k steps, so that the count
// and the fill entry share it), `kajiya_kay` is `common/kajiya_kay.wgsl` = `shading::kajiya_kay`.
// `fs_count` adds the fragments it would emit to its pixel's count (and the total) and the march's statistics
// to `stats`; `fs_fill` appends them to the eye lists as `EyeNode`s of kind 1 (SHELL) or 2 (VIRTUAL).
#include "common/frame.wgsl"
#include "common/eye_node.wgsl"
#include "common/mesh_depth.wgsl"
#include "common/kajiya_kay.wgsl"
#include "common/visibility.wgsl"
#include "common/fur_face.wgsl"

// Mirrors `render::fur::shell_gpu::FurShellUniforms` (a test compares the layouts).
struct FurShellUniforms {
    // Unit vector towards the light, and the extinction σ_0 per world unit at ρ = 1.
    to_light: vec3<f32>,
    sigma: f32,
    // The light's radiance, and the step Δs.
    light: vec3<f32>,
    step: f32,
    // Undercoat colour (Kajiya–Kay base), and the light-march step Δs_l.
    colour: vec3<f32>,
    light_step: f32,
    max_steps: u32,
    // Hop cap per step H_max.
    hops: u32,
    epsilon_t: f32,
    light_steps: u32,
    // Steps per emitted fragment: k (virtual fragments) or 0xffffffff (one shell fragment).
    group: u32,
    // EyeNode kind of the emitted fragments: 1 SHELL, 2 VIRTUAL.
    kind: u32,
    // Layers per prism n_l.
    layers: u32,
    pad0: u32,
}

// One entry triangle: its prism, and which of its triangles it is (0: the top; 1 + 2e + s: half s of the wall
// on boundary edge e), as `march::entry_triangles`.
struct FurEntryTriangle {
    face: u32,
    which: u32,
}

@group(1) @binding(0) var<uniform> fur: FurShellUniforms;
@group(1) @binding(1) var<storage, read> faces: array<FurFace>;
@group(1) @binding(2) var<storage, read> triangles: array<FurEntryTriangle>;
// Per sub-element (global index, eq. 3): (τ.xyz, ρ), `Volume::store`.
@group(1) @binding(3) var<storage, read> volume: array<vec4<f32>>;
// Pairs (low, high) of 64-bit counters: rays, steps, hops, light steps, lost, capped, light lost.
@group(1) @binding(4) var<storage, read_write> stats: array<atomic<u32>, 14>;

// Count pass: per-pixel counts, the total at [W·H].
@group(2) @binding(0) var<storage, read_write> counts: array<atomic<u32>>;
// Fill pass: the eye lists; counters [0] nodes used, [1] fragments that did not fit.
@group(2) @binding(1) var<storage, read_write> heads: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read_write> nodes: array<EyeNode>;
@group(2) @binding(3) var<storage, read_write> counters: array<atomic<u32>>;
@group(2) @binding(4) var mesh_depth: texture_depth_2d;

const NONE: u32 = 0xffffffffu;
// `march::SIDE_TOLERANCE`, `shell::NEWTON_STEPS`.
const SIDE_TOLERANCE: f32 = 1e-6;
const NEWTON_STEPS: u32 = 8u;
// `march::Stop`.
const STOP_BASE: u32 = 0u;
const STOP_TOP: u32 = 1u;
const STOP_BOUNDARY: u32 = 2u;
const STOP_LOST: u32 = 3u;
const STOP_TRANSMITTANCE: u32 = 4u;
const STOP_MAX_STEPS: u32 = 5u;
// `walk` found the point inside a prism.
const INSIDE: u32 = 6u;
// The largest finite f32: `x <= MAX_F32` is false for ±∞ and NaN.
const MAX_F32: f32 = 3.40282347e38;

struct ShellVertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) triangle: u32,
}

// The corners of entry triangle `tri`, counter-clockwise seen from outside its prism (`march::entry_corners`).
fn entry_corners(tri: FurEntryTriangle) -> array<vec3<f32>, 3> {
    let f = tri.face;
    if tri.which == 0u {
        return array<vec3<f32>, 3>(faces[f].top[0].xyz, faces[f].top[1].xyz, faces[f].top[2].xyz);
    }
    let e = (tri.which - 1u) / 2u;
    let i = (e + 1u) % 3u;
    let j = (e + 2u) % 3u;
    if (tri.which - 1u) % 2u == 0u {
        return array<vec3<f32>, 3>(faces[f].base[i].xyz, faces[f].base[j].xyz, faces[f].top[j].xyz);
    }
    return array<vec3<f32>, 3>(faces[f].base[i].xyz, faces[f].top[j].xyz, faces[f].top[i].xyz);
}

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> ShellVertexOut {
    var corners = entry_corners(triangles[index / 3u]);
    var out: ShellVertexOut;
    out.clip = frame.world_to_clip * vec4<f32>(corners[index % 3u], 1.0);
    out.triangle = index / 3u;
    return out;
}

// glam's `normalize`: v times the reciprocal of its length.
fn normalize_glam(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / sqrt(dot(v, v)));
}

// The unit eye ray through the centre of `pixel` (`shell_gpu::pixel_ray`): the direction whose clip x/w and
// y/w are the centre's NDC, the cross product of the two clip-space planes through the eye.
fn pixel_ray(pixel: vec2<u32>) -> vec3<f32> {
    let m = frame.world_to_clip;
    let ndc = vec2<f32>(
        (f32(pixel.x) + 0.5) / frame.viewport_size.x * 2.0 - 1.0,
        1.0 - (f32(pixel.y) + 0.5) / frame.viewport_size.y * 2.0,
    );
    let row_x = vec3<f32>(m[0].x, m[1].x, m[2].x);
    let row_y = vec3<f32>(m[0].y, m[1].y, m[2].y);
    let row_w = vec3<f32>(m[0].w, m[1].w, m[2].w);
    var d = cross(row_x - ndc.x * row_w, row_y - ndc.y * row_w);
    if dot(row_w, d) < 0.0 {
        d = -d;
    }
    return normalize_glam(d);
}

// `Location`: shell height and cross-section barycentrics.
struct Location {
    w: f32,
    lambda: vec3<f32>,
}

// `Shell::locate`: the height w at which p lies in the plane of q(w) (Newton on the cubic from the
// perpendicular-distance estimate), then barycentrics in q(w).
fn prism_locate(p: vec3<f32>, f: u32) -> Location {
    let b0 = faces[f].base[0].xyz;
    let b1 = faces[f].base[1].xyz;
    let b2 = faces[f].base[2].xyz;
    let t0 = faces[f].top[0].xyz;
    let t1 = faces[f].top[1].xyz;
    let t2 = faces[f].top[2].xyz;
    let d0 = t0 - b0;
    let d1 = t1 - b1;
    let d2 = t2 - b2;
    let e1 = b1 - b0;
    let e2 = b2 - b0;
    let f1 = d1 - d0;
    let f2 = d2 - d0;
    let r = p - b0;
    let n0 = cross(e1, e2);
    let n1 = cross(e1, f2) + cross(f1, e2);
    let n2 = cross(f1, f2);
    let c0 = dot(r, n0);
    let c1 = dot(r, n1) - dot(d0, n0);
    let c2 = dot(r, n2) - dot(d0, n1);
    let c3 = -dot(d0, n2);
    // glam's normalize_or_zero.
    let top_raw = cross(t1 - t0, t2 - t0);
    let rcp = 1.0 / sqrt(dot(top_raw, top_raw));
    var top_n = vec3<f32>(0.0);
    if rcp <= MAX_F32 && rcp > 0.0 {
        top_n = top_raw * rcp;
    }
    let centre = (b0 + b1 + b2) / 3.0;
    let thickness = dot(t0 - centre, top_n);
    var w = 0.5;
    if thickness > 0.0 {
        w = 1.0 - dot(t0 - p, top_n) / thickness;
    }
    for (var i = 0u; i < NEWTON_STEPS; i++) {
        let g = ((c3 * w + c2) * w + c1) * w + c0;
        let dg = (3.0 * c3 * w + 2.0 * c2) * w + c1;
        if dg == 0.0 {
            break;
        }
        let s = g / dg;
        w -= s;
        if abs(s) < 1e-7 {
            break;
        }
    }
    // glam's lerp: a + (b − a)·w.
    let q0 = b0 + (t0 - b0) * w;
    let q1 = b1 + (t1 - b1) * w;
    let q2 = b2 + (t2 - b2) * w;
    let n = n0 + w * n1 + w * w * n2;
    let nn = dot(n, n);
    var at: Location;
    at.w = w;
    at.lambda = vec3<f32>(
        dot(cross(q1 - p, q2 - p), n) / nn,
        dot(cross(q2 - p, q0 - p), n) / nn,
        dot(cross(q0 - p, q1 - p), n) / nn,
    );
    return at;
}

// `Location::min_lambda`: the most negative barycentric's corner (the first on ties).
fn min_corner(l: vec3<f32>) -> u32 {
    var k = 0u;
    var m = l.x;
    if l.y < m {
        k = 1u;
        m = l.y;
    }
    if l.z < m {
        k = 2u;
    }
    return k;
}

struct Found {
    // INSIDE, or the `STOP_*` that ended the walk.
    result: u32,
    face: u32,
    at: Location,
    hops: u32,
}

// `march::locate`: x located from prism f, height first, then across the exit edge at most `max_hops` times.
fn walk(x: vec3<f32>, face: u32, max_hops: u32) -> Found {
    var out: Found;
    out.face = face;
    out.hops = 0u;
    for (var hop = 0u; hop <= max_hops; hop++) {
        out.at = prism_locate(x, out.face);
        if out.at.w < 0.0 {
            out.result = STOP_BASE;
            return out;
        }
        if out.at.w > 1.0 {
            out.result = STOP_TOP;
            return out;
        }
        let edge = min_corner(out.at.lambda);
        if out.at.lambda[edge] >= -SIDE_TOLERANCE {
            out.result = INSIDE;
            return out;
        }
        if hop == max_hops {
            break;
        }
        let g = faces[out.face].neighbours[edge];
        if g == NONE {
            out.result = STOP_BOUNDARY;
            return out;
        }
        out.face = g;
        out.hops += 1u;
    }
    out.result = STOP_LOST;
    return out;
}

// `index::layer_of`, `index::locate` (eqs. 1–2) and eq. 3 under dynamic resolution: the global index of
// location `at` in prism f.
fn sub_element(f: u32, at: Location) -> u32 {
    let layer = slice_index(at.w * f32(fur.layers), fur.layers);
    let d = faces[f].level;
    let n = 1u << d;
    let x = (vec3<f32>(1.0) - at.lambda) * f32(n);
    let i = vec3<i32>(vec3<u32>(slice_index(x.x, n), slice_index(x.y, n), slice_index(x.z, n)));
    let local = u32(i.x * (1 + i.x) + i.y - i.z);
    return faces[f].offset + layer * (1u << (2u * d)) + local;
}

// e^{-omega} as the CPU's correctly rounded exp gives it near 0: lavapipe's exp is an ulp off there
// (exp(-2e-8) = 1 - 2^-24 where the CPU's is 1), which would give steps through nearly empty sub-elements an
// alpha of 6e-8 and emit fragments the CPU does not. Below 2^-12 the Taylor polynomial 1 - omega(1 - omega/2)
// is exact to f32 (the next term is under 1e-11).
fn step_transmittance(omega: f32) -> f32 {
    if omega < 0.000244140625 {
        return 1.0 - omega * (1.0 - 0.5 * omega);
    }
    return transmittance(omega);
}

// Light-march counters of one eye ray.
struct LightCounts {
    steps: u32,
    lost: u32,
}

// `march::light_transmittance`: T_light at x (in prism f), n_light mid-point samples towards the light.
fn light_transmittance(x: vec3<f32>, face: u32, lc: ptr<function, LightCounts>) -> f32 {
    var optical = 0.0;
    var f = face;
    for (var j = 0u; j < fur.light_steps; j++) {
        let y = x + (f32(j) + 0.5) * fur.light_step * fur.to_light;
        let found = walk(y, f, fur.hops);
        if found.result == INSIDE {
            f = found.face;
            (*lc).steps += 1u;
            optical += fur.sigma * volume[sub_element(f, found.at)].w * fur.light_step;
        } else if found.result == STOP_BASE {
            return 0.0;
        } else if found.result == STOP_LOST {
            (*lc).lost += 1u;
            break;
        } else {
            break;
        }
    }
    return step_transmittance(optical);
}

// `march::Acc`: a group being accumulated, or the whole march.
struct Acc {
    t: f32,
    transmittance: f32,
    radiance: vec3<f32>,
}

fn acc_new(t: f32) -> Acc {
    return Acc(t, 1.0, vec3<f32>(0.0));
}

// One eye ray's march in progress.
struct March {
    o: vec3<f32>,
    r: vec3<f32>,
    t0: f32,
    face: u32,
    // Steps taken so far (the next step's index).
    step: u32,
    ended: bool,
    stop: u32,
    whole: Acc,
    // The group `march_group` last completed.
    group: Acc,
    steps: u32,
    hops: u32,
    light: LightCounts,
}

fn march_new(o: vec3<f32>, r: vec3<f32>, t0: f32, face: u32) -> March {
    var m: March;
    m.o = o;
    m.r = r;
    m.t0 = t0;
    m.face = face;
    m.step = 0u;
    m.ended = false;
    m.stop = STOP_MAX_STEPS;
    m.whole = acc_new(t0);
    m.group = acc_new(t0);
    m.steps = 0u;
    m.hops = 0u;
    m.light = LightCounts(0u, 0u);
    return m;
}

// `march::march`, one group of k steps a call (k = 0xffffffff: the whole march in one group, whose
// accumulation is then bitwise the whole march's): false when the march had already ended; else the group
// is in m.group (its fragment is emitted when its alpha is > 0).
fn march_group(m: ptr<function, March>) -> bool {
    if (*m).ended {
        return false;
    }
    let first = (*m).step;
    (*m).group = acc_new((*m).t0 + f32(first) * fur.step);
    loop {
        if (*m).step >= fur.max_steps {
            (*m).ended = true;
            break;
        }
        if (*m).step - first >= fur.group {
            break;
        }
        let t = (*m).t0 + (f32((*m).step) + 0.5) * fur.step;
        let x = (*m).o + t * (*m).r;
        let found = walk(x, (*m).face, fur.hops);
        (*m).hops += found.hops;
        if found.result != INSIDE {
            (*m).stop = found.result;
            (*m).ended = true;
            break;
        }
        (*m).face = found.face;
        (*m).steps += 1u;
        let s = volume[sub_element(found.face, found.at)];
        let ts = step_transmittance(fur.sigma * s.w * fur.step);
        var light = (*m).light;
        let t_light = light_transmittance(x, found.face, &light);
        (*m).light = light;
        let phase = kajiya_kay(s.xyz, fur.to_light, -(*m).r, fur.colour);
        let lit = phase * fur.light * t_light;
        (*m).whole.radiance += (*m).whole.transmittance * (1.0 - ts) * lit;
        (*m).whole.transmittance *= ts;
        (*m).group.radiance += (*m).group.transmittance * (1.0 - ts) * lit;
        (*m).group.transmittance *= ts;
        (*m).step += 1u;
        if (*m).whole.transmittance < fur.epsilon_t {
            (*m).stop = STOP_TRANSMITTANCE;
            (*m).ended = true;
            break;
        }
    }
    return true;
}

// The entry of a rasterised shell fragment: its pixel, ray, entry distance t0 and prism, or `valid = false`.
struct Entry {
    valid: bool,
    pixel: u32,
    r: vec3<f32>,
    t0: f32,
    face: u32,
}

// The fragment's entry: the meshes' depth tested by hand first (storage is written), then t0 by the same
// Möller–Trumbore as `march::front_hit` on the rasterised triangle. A ray that sees the triangle edge-on or
// from behind (det ≤ 0: `front_hit` has no hit) or behind the eye has no entry; one that misses the triangle
// by rounding (the rasteriser's coverage and the exact barycentrics disagree at its edges) takes the plane's t.
fn shell_entry(in: ShellVertexOut) -> Entry {
    var e: Entry;
    e.valid = false;
    if hidden_by_mesh(mesh_depth, in.clip) {
        return e;
    }
    let pixel = vec2<u32>(in.clip.xy);
    let tri = triangles[in.triangle];
    let v = entry_corners(tri);
    let r = pixel_ray(pixel);
    let o = frame.eye_position;
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let pv = cross(r, e2);
    let det = dot(e1, pv);
    if det <= 0.0 {
        return e;
    }
    let inv = 1.0 / det;
    let s = o - v[0];
    let q = cross(s, e1);
    let t = dot(e2, q) * inv;
    if !(t > 0.0) {
        return e;
    }
    e.valid = true;
    e.pixel = pixel.y * u32(frame.viewport_size.x) + pixel.x;
    e.r = r;
    e.t0 = t;
    e.face = tri.face;
    return e;
}

// Adds `x` to the 64-bit counter `k` of `stats` (low word, carry into the high word).
fn add_stat(k: u32, x: u32) {
    if x == 0u {
        return;
    }
    let old = atomicAdd(&stats[2u * k], x);
    if old > 0xffffffffu - x {
        atomicAdd(&stats[2u * k + 1u], 1u);
    }
}

@fragment
fn fs_count(in: ShellVertexOut) {
    let e = shell_entry(in);
    if !e.valid {
        return;
    }
    var m = march_new(frame.eye_position, e.r, e.t0, e.face);
    var n = 0u;
    while march_group(&m) {
        if 1.0 - m.group.transmittance > 0.0 {
            n += 1u;
        }
    }
    add_stat(0u, 1u);
    add_stat(1u, m.steps);
    add_stat(2u, m.hops);
    add_stat(3u, m.light.steps);
    add_stat(4u, u32(m.stop == STOP_LOST));
    add_stat(5u, u32(m.stop == STOP_MAX_STEPS));
    add_stat(6u, m.light.lost);
    if n > 0u {
        atomicAdd(&counts[e.pixel], n);
        atomicAdd(&counts[arrayLength(&counts) - 1u], n);
    }
}

@fragment
fn fs_fill(in: ShellVertexOut) {
    let e = shell_entry(in);
    if !e.valid {
        return;
    }
    var m = march_new(frame.eye_position, e.r, e.t0, e.face);
    while march_group(&m) {
        let alpha = 1.0 - m.group.transmittance;
        if !(alpha > 0.0) {
            continue;
        }
        let i = atomicAdd(&counters[0], 1u);
        if i >= arrayLength(&nodes) {
            atomicAdd(&counters[1], 1u);
            continue;
        }
        let c = m.group.radiance / alpha;
        var node: EyeNode;
        node.depth = m.group.t / frame.camera_distance;
        node.segment = e.face;
        node.r = c.r;
        node.g = c.g;
        node.b = c.b;
        node.alpha = alpha;
        node.kind = fur.kind;
        node.next = atomicExchange(&heads[e.pixel], i + 1u);
        nodes[i] = node;
    }
}
