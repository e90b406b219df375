// A triangle covering the whole viewport, from the vertex index alone (draw 3 vertices, no buffers): the vertex
// stage of every full-screen pass, `vs_main` (src/render/eye/pipelines.rs, `fullscreen`).
fn fullscreen_position(i: u32) -> vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(i);
}
