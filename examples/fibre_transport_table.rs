//! Prints `shading::fibre_transport::TABLE`: `ā_f`, `ā_b` of hairlab's fibre (Chiang et al. 2016's BSDF with
//! the real-time model's lobe widths, tilt and index, `pathtrace::bsdf::fibre_absorbing`) on the table's grid
//! of inclinations and absorptions, by `measure::fibre_slab::attenuation` at the quadrature given (default 128).
//! `cargo run --release --example fibre_transport_table -- 128`

use glam::Vec3;
use hairlab::measure::fibre_slab::{Fixed, attenuation};
use hairlab::pathtrace::bsdf::fibre_absorbing;
use hairlab::shading::fibre_transport;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(128);
    let table = fibre_transport::quadrature_table(|sin_i, sigma_a: Vec3| {
        let h = attenuation(&fibre_absorbing(sigma_a), sin_i, n, Fixed::Light);
        (h.forward.as_vec3(), h.backward.as_vec3())
    });
    println!("// quadrature {n}");
    for row in &table {
        let cells: Vec<String> = row.iter().map(|[f, b]| format!("[{f:.6}, {b:.6}]")).collect();
        println!("    [{}],", cells.join(", "));
    }
}
