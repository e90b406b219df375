//! Prints `shading::fibre_transport::TABLE`: `ā_f`, `ā_b` of hairlab's fibre (Chiang et al. 2016's BSDF with
//! the real-time model's roughness, tilt and index) on the table's grid of inclinations and absorptions, by
//! `measure::fibre_slab::attenuation` at the quadrature given (default 128).
//! `cargo run --release --example fibre_transport_table -- 128`

use glam::Vec3;
use hairlab::measure::fibre_slab::{Fixed, attenuation};
use hairlab::pathtrace::bsdf::FibreParams;
use hairlab::shading::{fibre_transport, marschner};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(128);
    let table = fibre_transport::quadrature_table(|sin_i, sigma_a: Vec3| {
        let fibre =
            FibreParams::with_absorption(sigma_a, marschner::BETA_R, marschner::BETA_N, marschner::ALPHA_R);
        let h = attenuation(&fibre, sin_i, n, Fixed::Light);
        (h.forward.as_vec3(), h.backward.as_vec3())
    });
    println!("// quadrature {n}");
    for row in &table {
        let cells: Vec<String> = row.iter().map(|[f, b]| format!("[{f:.6}, {b:.6}]")).collect();
        println!("    [{}],", cells.join(", "));
    }
}
