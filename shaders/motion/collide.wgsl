// The strand simulation's collider (src/motion/pose.rs `Collider` and src/motion/sdf.rs are the specification),
// included by the simulation and follow passes, which bind it as group 1: the generator's head ellipsoid, or a
// signed distance grid of meshes (trilinear distance clamped to the grid, central differences one cell either
// side for the gradient), both in the head's rest frame.

struct ColliderParams {
    kind: vec4<u32>,     // x: 0 none, 1 ellipsoid, 2 distance grid; yzw: the grid's nodes per axis
    center: vec4<f32>,   // ellipsoid: centre; grid: origin (xyz), w: cell
    radii: vec4<f32>,    // ellipsoid: radii; grid: x the margin
};

@group(1) @binding(0) var<uniform> collider: ColliderParams;
@group(1) @binding(1) var<storage, read> sdf: array<f32>;

fn collider_on() -> bool { return collider.kind.x != 0u; }

fn sdf_node(i: u32, j: u32, k: u32) -> f32 {
    return sdf[i + collider.kind.y * (j + collider.kind.z * k)];
}

// As the CPU model writes it (not `mix`), so both round alike.
fn sdf_lerp(a: f32, b: f32, t: f32) -> f32 { return a + (b - a) * t; }

fn sdf_distance(p: vec3<f32>) -> f32 {
    let top = vec3<f32>(f32(collider.kind.y - 1u), f32(collider.kind.z - 1u), f32(collider.kind.w - 1u));
    let g = clamp((p - collider.center.xyz) / collider.center.w, vec3<f32>(0.0), top);
    let c = min(floor(g), top - vec3<f32>(1.0));
    let t = g - c;
    let i = u32(c.x);
    let j = u32(c.y);
    let k = u32(c.z);
    let x00 = sdf_lerp(sdf_node(i, j, k), sdf_node(i + 1u, j, k), t.x);
    let x10 = sdf_lerp(sdf_node(i, j + 1u, k), sdf_node(i + 1u, j + 1u, k), t.x);
    let x01 = sdf_lerp(sdf_node(i, j, k + 1u), sdf_node(i + 1u, j, k + 1u), t.x);
    let x11 = sdf_lerp(sdf_node(i, j + 1u, k + 1u), sdf_node(i + 1u, j + 1u, k + 1u), t.x);
    return sdf_lerp(sdf_lerp(x00, x10, t.y), sdf_lerp(x01, x11, t.y), t.z);
}

fn sdf_gradient(p: vec3<f32>) -> vec3<f32> {
    let h = collider.center.w;
    let dx = sdf_distance(p + vec3<f32>(h, 0.0, 0.0)) - sdf_distance(p - vec3<f32>(h, 0.0, 0.0));
    let dy = sdf_distance(p + vec3<f32>(0.0, h, 0.0)) - sdf_distance(p - vec3<f32>(0.0, h, 0.0));
    let dz = sdf_distance(p + vec3<f32>(0.0, 0.0, h)) - sdf_distance(p - vec3<f32>(0.0, 0.0, h));
    return vec3<f32>(dx, dy, dz) * (0.5 / h);
}

// `local` moved out of the collider (xyz) and w = 1, or `local` and w = 0 when it is not inside: the ellipsoid
// along the ray from its centre onto its surface, the grid along its gradient out to the margin.
fn collide_push(local: vec3<f32>) -> vec4<f32> {
    if (collider.kind.x == 1u) {
        let c = collider.center.xyz;
        let l = length((local - c) / collider.radii.xyz);
        if (l < 1.0 && l > 0.0) { return vec4<f32>(c + (local - c) / l, 1.0); }
    } else if (collider.kind.x == 2u) {
        let margin = collider.radii.x;
        let d = sdf_distance(local);
        if (d < margin) {
            let g = sdf_gradient(local);
            let l = length(g);
            if (l > 0.0) { return vec4<f32>(local + g * ((margin - d) / l), 1.0); }
        }
    }
    return vec4<f32>(local, 0.0);
}
