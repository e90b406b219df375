//! The light transport of the fibres hair model (`render.hair_model = fibres`, [`super::HairModel`];
//! docs/truth.md, "The fibres model"): what reaches a strand point through the `n` strands in front of it
//! towards the light is not what `n` absorbers of opacity `α` pass (`(1 − α)ⁿ`) but what `n` fibres scatter
//! forward, `T_f = d_f ā_f(θ)ⁿ` (Zinke, Yuksel, Weber & Keyser 2008, §4.2), with `ā_f` and `d_f` of the fibre
//! the path tracer traces rather than chosen ones. The CPU model (the specification) of
//! `shaders/common/fibre_transport.wgsl`.
//!
//! - The count: the light passes store each fragment's coverage `c` of its light texel as its alpha, so any
//!   method's `V = Π (1 − c)` is the chance a light ray through the texel crosses no fibre (fibres placed
//!   independently), and `−ln V = Σ −ln(1 − c)` ([`count`]) the hair count: `Σ c`, the mean number of fibres
//!   crossed (what Unreal's deep opacity maps store), for fibres thin against the texel, more where one fibre
//!   covers most of it. (Storing `1 − e^(−c)` instead made `−ln V = Σ c` exact but let a fibre that covers its
//!   texel pass `e^(−1)` of the light: back-lit hair, where strands are as wide as the texels, took 2.0× the
//!   traced fibres' light at one event; docs/truth.md.)
//! - [`TABLE`]: `ā_f`, `ā_b` (Zinke's Eq. 6–7) of Chiang et al. 2016's BSDF (`pathtrace::bsdf`) with the
//!   real-time model's roughness, cuticle tilt and index, the energy it scatters into the half of the sphere
//!   past the fibre and towards the light, averaged over the offset `h`, on a grid of inclinations
//!   `sin θ = −1 + k/8` and absorptions `√σ_a = j · ROOT_SIGMA_MAX / 16` (`σ_a` per channel, from the colour
//!   as the path tracer's fibre takes it, `marschner::absorption`), interpolated bilinearly. Computed by
//!   `measure::fibre_slab::attenuation` at quadrature 128 (`cargo run --release --example
//!   fibre_transport_table -- 128`, 60 s on 2 cores); a test recomputes three rows at quadrature 64.
//! - [`DENSITY_FORWARD`], [`DENSITY_BACK`]: `d_f`, `d_b` fitted by `hairlab measure fibres` on slabs of the
//!   path tracer's fibres (docs/truth.md: `d_f` 0.92–0.94 on `default` and `blond` at 0° and 30°, `d_b`
//!   1.05–1.24), the middle of each range.

use glam::Vec3;

/// `d_f`: the share of `ā_f^n` that reaches depth `n` in a slab of the path tracer's fibres.
pub const DENSITY_FORWARD: f32 = 0.93;
/// `d_b`: the light the hair behind a point sends back, over Zinke's closed form `A_b`.
pub const DENSITY_BACK: f32 = 1.15;
/// The irradiance a light of unit `colour × intensity` gives a surface facing it under the fibres model: π, as
/// the meshes' Lambert (`albedo × light × N·L` = `albedo/π × π × light × N·L`) and the path tracer take it.
pub const IRRADIANCE: f32 = std::f32::consts::PI;
/// Nodes of [`TABLE`] in `sin θ` and in `√σ_a`.
pub const SIN_NODES: usize = 17;
pub const ABSORPTION_NODES: usize = 17;
/// `√σ_a` of [`TABLE`]'s last absorption node: above the darkest colour's (`√σ_a` = 1.17 at colour 10⁻³).
pub const ROOT_SIGMA_MAX: f32 = 1.2;

/// `[k][j] = [ā_f, ā_b]` at `sin θ = −1 + k/8` ([`quadrature_sin`]), `√σ_a = j · ROOT_SIGMA_MAX / 16`
/// (quadrature 128).
#[rustfmt::skip]
pub const TABLE: [[[f32; 2]; ABSORPTION_NODES]; SIN_NODES] = [
    [[0.417797, 0.583445], [0.410936, 0.576200], [0.393066, 0.557367], [0.369711, 0.532957], [0.345570, 0.508288], [0.323282, 0.486529], [0.303825, 0.468945], [0.287294, 0.455604], [0.273459, 0.445979], [0.262031, 0.439323], [0.252743, 0.434887], [0.245350, 0.432019], [0.239611, 0.430210], [0.235281, 0.429087], [0.232111, 0.428397], [0.229862, 0.427975], [0.228317, 0.427717]],
    [[0.761112, 0.238955], [0.751760, 0.235143], [0.724592, 0.224364], [0.682061, 0.208343], [0.627700, 0.189357], [0.565576, 0.169681], [0.499799, 0.151167], [0.434123, 0.135029], [0.371674, 0.121829], [0.314789, 0.111594], [0.264963, 0.104009], [0.222896, 0.098591], [0.188599, 0.094829], [0.161567, 0.092272], [0.140946, 0.090556], [0.125711, 0.089416], [0.114802, 0.088662]],
    [[0.842299, 0.157732], [0.832500, 0.155305], [0.803887, 0.148394], [0.758684, 0.138001], [0.700212, 0.125484], [0.632464, 0.112263], [0.559648, 0.099555], [0.485782, 0.088226], [0.414362, 0.078745], [0.348148, 0.071229], [0.289051, 0.065542], [0.238141, 0.061403], [0.195724, 0.058487], [0.161498, 0.056480], [0.134721, 0.055121], [0.114392, 0.054210], [0.099404, 0.053601]],
    [[0.874205, 0.125822], [0.864498, 0.123972], [0.836091, 0.118686], [0.791026, 0.110684], [0.732397, 0.100962], [0.663983, 0.090581], [0.589839, 0.080484], [0.513917, 0.071366], [0.439736, 0.063635], [0.370161, 0.057430], [0.307268, 0.052684], [0.252323, 0.049201], [0.205839, 0.046735], [0.167700, 0.045037], [0.137317, 0.043891], [0.113796, 0.043129], [0.096086, 0.042624]],
    [[0.889028, 0.111003], [0.879514, 0.109437], [0.851639, 0.104954], [0.807304, 0.098137], [0.749416, 0.089806], [0.681556, 0.080845], [0.607608, 0.072054], [0.531401, 0.064044], [0.456403, 0.057189], [0.385488, 0.051636], [0.320803, 0.047352], [0.263728, 0.044188], [0.214912, 0.041938], [0.174379, 0.040387], [0.141669, 0.039345], [0.115988, 0.038658], [0.096359, 0.038208]],
    [[0.896514, 0.103516], [0.887183, 0.102104], [0.859819, 0.098056], [0.816226, 0.091882], [0.759169, 0.084305], [0.692076, 0.076113], [0.618689, 0.068029], [0.542730, 0.060613], [0.467601, 0.054222], [0.396160, 0.049008], [0.330584, 0.044959], [0.272318, 0.041950], [0.222100, 0.039800], [0.180053, 0.038316], [0.145811, 0.037320], [0.118661, 0.036665], [0.097688, 0.036241]],
    [[0.900403, 0.099626], [0.891210, 0.098301], [0.864236, 0.094494], [0.821218, 0.088678], [0.764827, 0.081521], [0.698384, 0.073756], [0.625531, 0.066061], [0.549907, 0.058971], [0.474863, 0.052830], [0.403236, 0.047796], [0.337215, 0.043866], [0.278281, 0.040932], [0.227230, 0.038828], [0.184246, 0.037371], [0.149029, 0.036393], [0.120924, 0.035751], [0.099059, 0.035337]],
    [[0.902297, 0.097738], [0.893188, 0.096457], [0.866453, 0.092774], [0.823790, 0.087142], [0.767816, 0.080199], [0.701789, 0.072652], [0.629291, 0.065156], [0.553914, 0.058231], [0.478972, 0.052216], [0.407292, 0.047269], [0.341064, 0.043395], [0.281790, 0.040495], [0.230293, 0.038410], [0.186798, 0.036964], [0.151037, 0.035991], [0.122391, 0.035353], [0.100016, 0.034943]],
    [[0.902862, 0.097172], [0.893781, 0.095904], [0.867126, 0.092260], [0.824583, 0.086685], [0.768750, 0.079809], [0.702865, 0.072329], [0.630491, 0.064894], [0.555202, 0.058019], [0.480303, 0.052042], [0.408613, 0.047121], [0.342326, 0.043265], [0.282947, 0.040374], [0.231310, 0.038294], [0.187651, 0.036850], [0.151717, 0.035879], [0.122896, 0.035242], [0.100354, 0.034832]],
    [[0.902305, 0.097738], [0.893196, 0.096456], [0.866461, 0.092774], [0.823797, 0.087142], [0.767823, 0.080199], [0.701795, 0.072652], [0.629297, 0.065156], [0.553918, 0.058231], [0.478977, 0.052215], [0.407295, 0.047268], [0.341067, 0.043395], [0.281792, 0.040495], [0.230295, 0.038410], [0.186799, 0.036964], [0.151038, 0.035991], [0.122392, 0.035353], [0.100016, 0.034943]],
    [[0.900415, 0.099627], [0.891222, 0.098301], [0.864248, 0.094494], [0.821229, 0.088679], [0.764838, 0.081521], [0.698394, 0.073756], [0.625540, 0.066061], [0.549915, 0.058971], [0.474869, 0.052831], [0.403241, 0.047796], [0.337219, 0.043866], [0.278285, 0.040932], [0.227232, 0.038828], [0.184249, 0.037371], [0.149031, 0.036393], [0.120925, 0.035751], [0.099060, 0.035337]],
    [[0.896498, 0.103516], [0.887167, 0.102104], [0.859804, 0.098056], [0.816211, 0.091882], [0.759155, 0.084305], [0.692063, 0.076113], [0.618678, 0.068029], [0.542720, 0.060613], [0.467593, 0.054222], [0.396153, 0.049008], [0.330579, 0.044959], [0.272314, 0.041950], [0.222097, 0.039800], [0.180051, 0.038316], [0.145809, 0.037320], [0.118660, 0.036665], [0.097687, 0.036241]],
    [[0.889016, 0.111003], [0.879503, 0.109437], [0.851628, 0.104954], [0.807294, 0.098137], [0.749407, 0.089806], [0.681548, 0.080845], [0.607600, 0.072054], [0.531394, 0.064044], [0.456397, 0.057189], [0.385483, 0.051636], [0.320800, 0.047352], [0.263725, 0.044188], [0.214910, 0.041938], [0.174378, 0.040387], [0.141668, 0.039346], [0.115988, 0.038658], [0.096358, 0.038208]],
    [[0.874209, 0.125820], [0.864502, 0.123970], [0.836095, 0.118684], [0.791029, 0.110683], [0.732400, 0.100961], [0.663986, 0.090581], [0.589842, 0.080483], [0.513919, 0.071365], [0.439738, 0.063635], [0.370163, 0.057430], [0.307270, 0.052684], [0.252324, 0.049201], [0.205840, 0.046735], [0.167700, 0.045037], [0.137318, 0.043891], [0.113796, 0.043129], [0.096086, 0.042624]],
    [[0.842290, 0.157722], [0.832491, 0.155295], [0.803879, 0.148386], [0.758677, 0.137993], [0.700205, 0.125478], [0.632458, 0.112257], [0.559643, 0.099551], [0.485777, 0.088223], [0.414358, 0.078743], [0.348145, 0.071228], [0.289049, 0.065541], [0.238139, 0.061403], [0.195723, 0.058486], [0.161497, 0.056480], [0.134721, 0.055121], [0.114392, 0.054210], [0.099404, 0.053602]],
    [[0.761121, 0.238914], [0.751769, 0.235104], [0.724601, 0.224327], [0.682070, 0.208311], [0.627708, 0.189331], [0.565584, 0.169661], [0.499806, 0.151153], [0.434129, 0.135020], [0.371679, 0.121822], [0.314793, 0.111591], [0.264967, 0.104008], [0.222899, 0.098590], [0.188602, 0.094830], [0.161569, 0.092273], [0.140948, 0.090558], [0.125713, 0.089417], [0.114804, 0.088663]],
    [[0.417211, 0.583988], [0.410363, 0.576745], [0.392534, 0.557918], [0.369241, 0.533518], [0.345182, 0.508861], [0.322986, 0.487117], [0.303627, 0.469548], [0.287192, 0.456221], [0.273449, 0.446608], [0.262102, 0.439964], [0.252884, 0.435537], [0.245549, 0.432677], [0.239856, 0.430874], [0.235560, 0.429756], [0.232416, 0.429069], [0.230186, 0.428649], [0.228653, 0.428393]],
];

/// `sin θ` of node `k`.
pub fn node_sin(k: usize) -> f32 {
    -1.0 + k as f32 / 8.0
}

/// `σ_a` of node `j`.
pub fn node_sigma(j: usize) -> f32 {
    let r = j as f32 * ROOT_SIGMA_MAX / (ABSORPTION_NODES - 1) as f32;
    r * r
}

/// The inclination [`TABLE`]'s node `k` is computed at: [`node_sin`], the end nodes at `±END_SIN` (at `±1` the
/// light runs along the fibre and the BSDF's frame degenerates).
pub fn quadrature_sin(k: usize) -> f32 {
    node_sin(k).clamp(-END_SIN, END_SIN)
}

/// `|sin θ|` the end nodes of [`TABLE`] are computed at.
pub const END_SIN: f32 = 0.995;

/// [`TABLE`] computed by `attenuation(sin θ, σ_a per channel) → (ā_f, ā_b)` at [`quadrature_sin`], three
/// absorption nodes a call.
pub fn quadrature_table(
    attenuation: impl Fn(f32, Vec3) -> (Vec3, Vec3),
) -> [[[f32; 2]; ABSORPTION_NODES]; SIN_NODES] {
    let mut table = [[[0.0; 2]; ABSORPTION_NODES]; SIN_NODES];
    for (k, row) in table.iter_mut().enumerate() {
        for first in (0..ABSORPTION_NODES).step_by(3) {
            let j = |c: usize| (first + c).min(ABSORPTION_NODES - 1);
            let sigma = Vec3::new(node_sigma(j(0)), node_sigma(j(1)), node_sigma(j(2)));
            let (f, b) = attenuation(quadrature_sin(k), sigma);
            for c in 0..3 {
                row[j(c)] = [f[c], b[c]];
            }
        }
    }
    table
}

/// Cell and weight of `x` on nodes `0..=cells`: `(min(floor x, cells − 1), clamp(x − i, 0, 1))`, `x ≥ 0`.
fn cell(x: f32, cells: usize) -> (usize, f32) {
    let i = (x.max(0.0).floor() as usize).min(cells - 1);
    (i, (x - i as f32).clamp(0.0, 1.0))
}

/// `ā_f`, `ā_b` per channel at inclination `sin_i` (sine of the light's angle to the fibre's normal plane,
/// `tangent · to_light`) for absorption `sigma_a`.
pub fn attenuation(sin_i: f32, sigma_a: Vec3) -> (Vec3, Vec3) {
    let (k, f) = cell((sin_i.clamp(-1.0, 1.0) + 1.0) * 8.0, SIN_NODES - 1);
    let scale = (ABSORPTION_NODES - 1) as f32 / ROOT_SIGMA_MAX;
    let mut out = [Vec3::ZERO; 2];
    for c in 0..3 {
        let (j, g) = cell(sigma_a[c].max(0.0).sqrt() * scale, ABSORPTION_NODES - 1);
        for (h, o) in out.iter_mut().enumerate() {
            let lo = TABLE[k][j][h] + (TABLE[k][j + 1][h] - TABLE[k][j][h]) * g;
            let hi = TABLE[k + 1][j][h] + (TABLE[k + 1][j + 1][h] - TABLE[k + 1][j][h]) * g;
            o[c] = lo + (hi - lo) * f;
        }
    }
    (out[0], out[1])
}

/// The hair count a light-map visibility `v` stands for under the fibres model: `−ln V` (`V` floored at the
/// smallest normal f32), the number of fibres crossed (the mean, for fibres thin against the texel).
pub fn count(v: f32) -> f32 {
    (-v.max(f32::MIN_POSITIVE).ln()).max(0.0)
}

/// `T_f = d_f ā_f(θ)^n`: the light forward-scattered through `count` fibres, per channel.
pub fn transmittance(sin_i: f32, sigma_a: Vec3, count: f32) -> Vec3 {
    let (af, _) = attenuation(sin_i, sigma_a);
    let n = count.max(0.0);
    DENSITY_FORWARD * Vec3::new(af.x.powf(n), af.y.powf(n), af.z.powf(n))
}

/// What reaches a point with visibility `v` and hair count `count` towards the light, for the models that
/// shade one scattering event (Kajiya-Kay, Marschner): the direct light `V`, or the forward-scattered `T_f`
/// where more (beyond the first strand).
pub fn arriving(v: f32, sin_i: f32, sigma_a: Vec3, count: f32) -> Vec3 {
    Vec3::splat(v.clamp(0.0, 1.0)).max(transmittance(sin_i, sigma_a, count))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `shaders/common/fibre_transport.wgsl` holds [`TABLE`]'s literals and the same constants.
    #[test]
    fn wgsl_table_is_the_cpu_table() {
        let src = crate::shaders::compose("common/fibre_transport.wgsl", None).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let constant = |name: &str| {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("{name} missing"));
            c.init
        };
        let compose = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
            naga::Expression::Compose { ref components, .. } => components.clone(),
            ref e => panic!("not a composite literal: {e:?}"),
        };
        let literal = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v,
            ref e => panic!("not an f32 literal: {e:?}"),
        };
        let wgsl: Vec<Vec<[f32; 2]>> = compose(constant("FIBRE_TABLE"))
            .into_iter()
            .map(|row| {
                compose(row)
                    .into_iter()
                    .map(|cell| {
                        let c = compose(cell);
                        [literal(c[0]), literal(c[1])]
                    })
                    .collect()
            })
            .collect();
        let cpu: Vec<Vec<[f32; 2]>> = TABLE.iter().map(|r| r.to_vec()).collect();
        assert_eq!(wgsl, cpu);
        assert_eq!(literal(constant("FIBRE_DENSITY_FORWARD")), DENSITY_FORWARD);
        assert_eq!(literal(constant("FIBRE_DENSITY_BACK")), DENSITY_BACK);
        assert_eq!(literal(constant("FIBRE_ROOT_SIGMA_MAX")), ROOT_SIGMA_MAX);
        assert_eq!(literal(constant("FIBRE_IRRADIANCE")), IRRADIANCE);
    }

    /// On the nodes the lookup returns the table's values; between two nodes it stays between them; beyond the
    /// grid it holds the edge.
    #[test]
    fn lookup_interpolates_the_nodes() {
        for k in [0, 5, 8, 16] {
            for j in [0, 7, 16] {
                let (f, b) = attenuation(node_sin(k), Vec3::splat(node_sigma(j)));
                assert!(
                    (f.x - TABLE[k][j][0]).abs() <= 1e-6,
                    "({k}, {j}): {f} vs {:?}",
                    TABLE[k][j]
                );
                assert!(
                    (b.y - TABLE[k][j][1]).abs() <= 1e-6,
                    "({k}, {j}): {b} vs {:?}",
                    TABLE[k][j]
                );
            }
        }
        let mid = (node_sigma(3).sqrt() + node_sigma(4).sqrt()) * 0.5;
        let (f, _) = attenuation(0.0, Vec3::splat(mid * mid));
        let (lo, hi) = (TABLE[8][4][0], TABLE[8][3][0]);
        assert!(f.x > lo && f.x < hi, "{} outside ({lo}, {hi})", f.x);
        assert_eq!(
            attenuation(2.0, Vec3::splat(9.0)),
            attenuation(1.0, Vec3::splat(ROOT_SIGMA_MAX.powi(2)))
        );
    }

    /// Darker fibres pass less forward at every inclination, and the white fibre's two halves hold its whole
    /// albedo (Chiang et al.'s BSDF conserves energy: `ā_f + ā_b` within 0.5 % of 1 at `σ_a = 0` off grazing).
    #[test]
    fn table_is_monotone_in_absorption_and_white_conserves_energy() {
        for (k, row) in TABLE.iter().enumerate() {
            for j in 1..ABSORPTION_NODES {
                assert!(
                    row[j][0] < row[j - 1][0],
                    "node ({k}, {j}): {} ≥ {}",
                    row[j][0],
                    row[j - 1][0]
                );
            }
            if (1..SIN_NODES - 1).contains(&k) {
                let albedo = row[0][0] + row[0][1];
                assert!((albedo - 1.0).abs() <= 5e-3, "node {k}: white albedo {albedo}");
            }
        }
    }
}
