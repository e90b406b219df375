// The f32 expressions every method shares with its CPU model, the GPU twins of `visibility::optical_depth`,
// `relative_depth`, `slice_index`, `lerp_up` and `transmittance` (design.md; the Rust docs name each expression).

// Optical depth b = -ln(1 - alpha), alpha clamped below 1.
fn optical_depth(alpha: f32) -> f32 {
    return -log(1.0 - clamp(alpha, 0.0, 1.0 - 1e-6));
}

// Relative depth t of z inside the texel range [near, far] (0 at near, 1 at far), unclamped; the step
// t = 0 for z <= near, 1 beyond, when far <= near.
fn relative_depth(z: f32, near: f32, far: f32) -> f32 {
    return select(select(0.0, 1.0, z > near), (z - near) / (far - near), far > near);
}

// Index of the slice x = t * n falls in, for n uniform slices: min(floor(x), n - 1), 0 for negative x.
fn slice_index(x: f32, n: u32) -> u32 {
    return min(u32(max(floor(x), 0.0)), n - 1u);
}

// Linear interpolation between two accumulated optical depths a <= b, capped at b.
fn lerp_up(a: f32, b: f32, f: f32) -> f32 {
    return min(a + (b - a) * f, b);
}

// Visibility from accumulated optical depth: V = exp(-omega).
fn transmittance(omega: f32) -> f32 {
    return exp(-omega);
}

// Hair count: the strands of opacity `hair_alpha` in front of a point of visibility `v`, -ln V / b(alpha), with
// V floored at the smallest normal f32 and 0 for b = 0 (`visibility::count_from_visibility`).
fn count_from_visibility(v: f32, hair_alpha: f32) -> f32 {
    let b = optical_depth(hair_alpha);
    return select(0.0, max(-log(max(v, 1.17549435e-38)), 0.0) / b, b > 0.0);
}
