// 3D simplex noise of the fur's volume (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering:
// combining volumetric fur with explicit hair strands", The Visual Computer; spec B.3 #12): `src/fur/noise.rs`
// ported line for line. Gustavson's simplex noise with lattice gradients from the integer PCG hash (Jarzynski
// & Olano 2020), no mod-289 permutation; kernel radius 0.5, the 12 cube-edge gradients, ×76. Every product and
// sum is written in the CPU's order (glam's dot is (x·x' + y·y') + z·z'), so that the two differ only where
// a compiler fuses a multiply and an add.

const FUR_NOISE_F3: f32 = 1.0 / 3.0;
const FUR_NOISE_G3: f32 = 1.0 / 6.0;
const FUR_NOISE_SCALE: f32 = 76.0;
const FUR_NOISE_GRADIENTS: array<vec3<f32>, 12> = array<vec3<f32>, 12>(
    vec3<f32>(1.0, 1.0, 0.0),
    vec3<f32>(-1.0, 1.0, 0.0),
    vec3<f32>(1.0, -1.0, 0.0),
    vec3<f32>(-1.0, -1.0, 0.0),
    vec3<f32>(1.0, 0.0, 1.0),
    vec3<f32>(-1.0, 0.0, 1.0),
    vec3<f32>(1.0, 0.0, -1.0),
    vec3<f32>(-1.0, 0.0, -1.0),
    vec3<f32>(0.0, 1.0, 1.0),
    vec3<f32>(0.0, -1.0, 1.0),
    vec3<f32>(0.0, 1.0, -1.0),
    vec3<f32>(0.0, -1.0, -1.0),
);

// `noise::pcg`: the PCG hash of one 32-bit word (u32 arithmetic wraps as Rust's wrapping_*).
fn fur_pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// `noise::hash3`: the hash of lattice point `i` under `seed`.
fn fur_hash3(i: vec3<i32>, seed: u32) -> u32 {
    return fur_pcg(fur_pcg(fur_pcg(bitcast<u32>(i.x) ^ seed) + bitcast<u32>(i.y)) + bitcast<u32>(i.z));
}

// glam's `Vec3::dot`, in its order.
fn fur_dot(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// `noise::simplex3`: simplex noise at `p` for `seed`, in [−1, 1].
fn fur_simplex3(p: vec3<f32>, seed: u32) -> f32 {
    let cell = floor(p + vec3<f32>((p.x + p.y + p.z) * FUR_NOISE_F3));
    let base = vec3<i32>(cell);
    let x0 = p - (cell - vec3<f32>((cell.x + cell.y + cell.z) * FUR_NOISE_G3));
    // The simplex of x0 in its skewed cube: the axes ranked by x0's components.
    var i1: vec3<i32>;
    var i2: vec3<i32>;
    if x0.x >= x0.y {
        if x0.y >= x0.z {
            i1 = vec3<i32>(1, 0, 0);
            i2 = vec3<i32>(1, 1, 0);
        } else if x0.x >= x0.z {
            i1 = vec3<i32>(1, 0, 0);
            i2 = vec3<i32>(1, 0, 1);
        } else {
            i1 = vec3<i32>(0, 0, 1);
            i2 = vec3<i32>(1, 0, 1);
        }
    } else if x0.y < x0.z {
        i1 = vec3<i32>(0, 0, 1);
        i2 = vec3<i32>(0, 1, 1);
    } else if x0.x < x0.z {
        i1 = vec3<i32>(0, 1, 0);
        i2 = vec3<i32>(0, 1, 1);
    } else {
        i1 = vec3<i32>(0, 1, 0);
        i2 = vec3<i32>(1, 1, 0);
    }
    let corners = array<vec3<i32>, 4>(vec3<i32>(0), i1, i2, vec3<i32>(1));
    var sum = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let c = corners[k];
        let x = x0 - vec3<f32>(c) + vec3<f32>(f32(k) * FUR_NOISE_G3);
        let m = max(0.5 - fur_dot(x, x), 0.0);
        let g = FUR_NOISE_GRADIENTS[fur_hash3(base + c, seed) % 12u];
        sum += m * m * m * m * fur_dot(g, x);
    }
    return FUR_NOISE_SCALE * sum;
}
