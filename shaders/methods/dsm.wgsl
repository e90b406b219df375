// Shadow method "dsm" (compressed deep shadow maps, Lokovic & Veach 2000 §4): the texel's piecewise-linear
// visibility, its vertices (z, V) written by shaders/dsm.wgsl. Lookup as visibility::dsm::visibility, with these
// exact expressions: V = v_0 before the first vertex, v_last behind the last, otherwise on the segment ending at
// the first vertex k with z_k >= z, capped at v_k and 0.
#include "common/dsm_uniforms.wgsl"

// Per texel: (offset of its first vertex, vertex count).
@group(1) @binding(0) var<storage, read> dsm_headers: array<vec2<u32>>;
@group(1) @binding(1) var<storage, read> dsm_vertices: array<vec2<f32>>;
@group(1) @binding(2) var<uniform> dsm: DsmUniforms;

// Vertex count that marks a texel the compressor could not place (never with a buffer sized this frame).
const DSM_OVERFLOW: u32 = 0xffffffffu;

fn visibility_at(texel: vec2<i32>, z: f32) -> f32 {
    let h = dsm_headers[u32(texel.y) * dsm.resolution + u32(texel.x)];
    if h.y == DSM_OVERFLOW {
        // Outside [0, 1]: an error the tests see, never a silent difference.
        return -1.0;
    }
    if h.y == 0u {
        return 1.0;
    }
    var lo = 0u;
    var hi = h.y;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if dsm_vertices[h.x + mid].x < z {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if lo == 0u {
        return dsm_vertices[h.x].y;
    }
    if lo == h.y {
        return max(dsm_vertices[h.x + h.y - 1u].y, 0.0);
    }
    let p0 = dsm_vertices[h.x + lo - 1u];
    let p1 = dsm_vertices[h.x + lo];
    return max(max(p0.y + (p1.y - p0.y) * ((z - p0.x) / (p1.x - p0.x)), p1.y), 0.0);
}
