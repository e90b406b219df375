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
//! - [`TABLE`]: `ā_f`, `ā_b` (Zinke's Eq. 6–7) of Chiang et al. 2016's BSDF (`pathtrace::bsdf::fibre_absorbing`)
//!   with the real-time model's lobe widths, cuticle tilt and index, the energy it scatters into the half of the sphere
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
    [[0.417015, 0.583356], [0.410167, 0.576115], [0.392336, 0.557292], [0.369038, 0.532895], [0.344970, 0.508242], [0.322762, 0.486499], [0.303388, 0.468930], [0.286939, 0.455602], [0.273180, 0.445988], [0.261820, 0.439343], [0.252590, 0.434914], [0.245245, 0.432053], [0.239544, 0.430249], [0.235243, 0.429130], [0.232094, 0.428443], [0.229860, 0.428023], [0.228326, 0.427766]],
    [[0.761122, 0.238923], [0.751770, 0.235112], [0.724602, 0.224335], [0.682070, 0.208318], [0.627708, 0.189336], [0.565584, 0.169665], [0.499806, 0.151156], [0.434129, 0.135021], [0.371679, 0.121823], [0.314793, 0.111591], [0.264967, 0.104008], [0.222898, 0.098590], [0.188602, 0.094829], [0.161568, 0.092272], [0.140947, 0.090557], [0.125712, 0.089416], [0.114803, 0.088663]],
    [[0.842303, 0.157728], [0.832503, 0.155301], [0.803891, 0.148391], [0.758687, 0.137998], [0.700215, 0.125482], [0.632467, 0.112260], [0.559651, 0.099553], [0.485784, 0.088225], [0.414364, 0.078744], [0.348149, 0.071229], [0.289052, 0.065541], [0.238142, 0.061403], [0.195725, 0.058487], [0.161499, 0.056480], [0.134722, 0.055121], [0.114393, 0.054210], [0.099404, 0.053601]],
    [[0.874205, 0.125824], [0.864498, 0.123974], [0.836091, 0.118688], [0.791026, 0.110685], [0.732397, 0.100963], [0.663983, 0.090582], [0.589839, 0.080484], [0.513917, 0.071366], [0.439736, 0.063636], [0.370161, 0.057431], [0.307268, 0.052684], [0.252323, 0.049202], [0.205839, 0.046735], [0.167700, 0.045037], [0.137317, 0.043891], [0.113796, 0.043129], [0.096085, 0.042624]],
    [[0.889023, 0.111005], [0.879510, 0.109439], [0.851635, 0.104956], [0.807300, 0.098139], [0.749413, 0.089807], [0.681553, 0.080846], [0.607605, 0.072055], [0.531398, 0.064045], [0.456401, 0.057189], [0.385486, 0.051636], [0.320802, 0.047352], [0.263727, 0.044188], [0.214911, 0.041938], [0.174379, 0.040387], [0.141669, 0.039345], [0.115988, 0.038658], [0.096358, 0.038208]],
    [[0.896510, 0.103518], [0.887179, 0.102106], [0.859815, 0.098057], [0.816222, 0.091884], [0.759165, 0.084306], [0.692073, 0.076114], [0.618686, 0.068029], [0.542728, 0.060614], [0.467599, 0.054222], [0.396158, 0.049008], [0.330583, 0.044959], [0.272317, 0.041950], [0.222099, 0.039800], [0.180053, 0.038316], [0.145810, 0.037320], [0.118661, 0.036665], [0.097687, 0.036241]],
    [[0.900400, 0.099627], [0.891207, 0.098301], [0.864233, 0.094495], [0.821215, 0.088679], [0.764825, 0.081521], [0.698382, 0.073756], [0.625529, 0.066061], [0.549905, 0.058971], [0.474861, 0.052831], [0.403234, 0.047796], [0.337214, 0.043866], [0.278280, 0.040932], [0.227229, 0.038828], [0.184246, 0.037371], [0.149029, 0.036393], [0.120924, 0.035751], [0.099058, 0.035336]],
    [[0.902288, 0.097739], [0.893180, 0.096457], [0.866445, 0.092775], [0.823783, 0.087143], [0.767809, 0.080200], [0.701782, 0.072652], [0.629286, 0.065156], [0.553909, 0.058231], [0.478968, 0.052216], [0.407288, 0.047268], [0.341061, 0.043395], [0.281787, 0.040495], [0.230291, 0.038410], [0.186796, 0.036964], [0.151036, 0.035991], [0.122391, 0.035353], [0.100015, 0.034943]],
    [[0.902854, 0.097173], [0.893774, 0.095905], [0.867119, 0.092261], [0.824576, 0.086685], [0.768743, 0.079809], [0.702859, 0.072329], [0.630486, 0.064894], [0.555197, 0.058019], [0.480299, 0.052042], [0.408610, 0.047121], [0.342323, 0.043265], [0.282944, 0.040374], [0.231309, 0.038294], [0.187650, 0.036850], [0.151715, 0.035879], [0.122895, 0.035242], [0.100353, 0.034832]],
    [[0.902290, 0.097738], [0.893181, 0.096457], [0.866446, 0.092774], [0.823784, 0.087142], [0.767810, 0.080200], [0.701783, 0.072652], [0.629286, 0.065156], [0.553909, 0.058231], [0.478969, 0.052216], [0.407289, 0.047268], [0.341062, 0.043395], [0.281788, 0.040495], [0.230292, 0.038410], [0.186796, 0.036964], [0.151036, 0.035991], [0.122391, 0.035353], [0.100015, 0.034943]],
    [[0.900401, 0.099626], [0.891209, 0.098301], [0.864235, 0.094494], [0.821217, 0.088679], [0.764826, 0.081521], [0.698383, 0.073756], [0.625530, 0.066061], [0.549906, 0.058971], [0.474862, 0.052830], [0.403235, 0.047795], [0.337214, 0.043866], [0.278281, 0.040932], [0.227229, 0.038828], [0.184246, 0.037371], [0.149029, 0.036393], [0.120924, 0.035751], [0.099059, 0.035337]],
    [[0.896507, 0.103516], [0.887177, 0.102105], [0.859813, 0.098056], [0.816220, 0.091882], [0.759163, 0.084305], [0.692071, 0.076113], [0.618685, 0.068029], [0.542726, 0.060613], [0.467597, 0.054222], [0.396157, 0.049008], [0.330582, 0.044959], [0.272316, 0.041950], [0.222099, 0.039800], [0.180052, 0.038316], [0.145810, 0.037320], [0.118661, 0.036665], [0.097687, 0.036241]],
    [[0.889021, 0.111003], [0.879508, 0.109437], [0.851633, 0.104954], [0.807298, 0.098137], [0.749411, 0.089806], [0.681551, 0.080845], [0.607603, 0.072054], [0.531397, 0.064044], [0.456400, 0.057189], [0.385485, 0.051636], [0.320801, 0.047352], [0.263727, 0.044188], [0.214911, 0.041938], [0.174378, 0.040387], [0.141668, 0.039346], [0.115988, 0.038658], [0.096358, 0.038208]],
    [[0.874206, 0.125821], [0.864499, 0.123971], [0.836092, 0.118685], [0.791027, 0.110683], [0.732398, 0.100961], [0.663984, 0.090581], [0.589840, 0.080483], [0.513917, 0.071366], [0.439737, 0.063635], [0.370162, 0.057431], [0.307269, 0.052684], [0.252323, 0.049202], [0.205839, 0.046735], [0.167700, 0.045037], [0.137318, 0.043892], [0.113796, 0.043129], [0.096086, 0.042625]],
    [[0.842304, 0.157726], [0.832505, 0.155299], [0.803892, 0.148389], [0.758689, 0.137996], [0.700217, 0.125481], [0.632468, 0.112260], [0.559652, 0.099553], [0.485786, 0.088226], [0.414366, 0.078746], [0.348151, 0.071230], [0.289055, 0.065543], [0.238144, 0.061405], [0.195728, 0.058489], [0.161501, 0.056482], [0.134724, 0.055123], [0.114395, 0.054212], [0.099407, 0.053604]],
    [[0.761131, 0.238929], [0.751779, 0.235119], [0.724611, 0.224342], [0.682080, 0.208325], [0.627719, 0.189345], [0.565595, 0.169675], [0.499817, 0.151166], [0.434141, 0.135033], [0.371691, 0.121835], [0.314805, 0.111604], [0.264980, 0.104020], [0.222912, 0.098603], [0.188615, 0.094842], [0.161582, 0.092285], [0.140961, 0.090570], [0.125726, 0.089430], [0.114817, 0.088676]],
    [[0.416941, 0.583401], [0.410094, 0.576160], [0.392267, 0.557338], [0.368976, 0.532942], [0.344917, 0.508290], [0.322720, 0.486549], [0.303357, 0.468982], [0.286919, 0.455656], [0.273170, 0.446043], [0.261820, 0.439399], [0.252598, 0.434971], [0.245259, 0.432111], [0.239563, 0.430308], [0.235266, 0.429190], [0.232120, 0.428503], [0.229888, 0.428083], [0.228355, 0.427826]],
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
pub(crate) fn cell(x: f32, cells: usize) -> (usize, f32) {
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

/// The steepest depth slope [`own_strand_offset`] follows, in light texels of depth per texel along the map:
/// a segment within 14° of the light's direction reads the map 4 texels towards the light, no farther.
pub const OWN_STRAND_SLOPE_MAX: f32 = 4.0;

/// How far towards the light (world units) the eye pass reads the light map at a fibre point, so that the
/// strand's own fragments do not shadow it, as the traced fibre is not shadowed by its own segment: the
/// segment's fragment in the point's texel lies up to half a texel's diagonal from the point along the map and
/// the segment climbs `|t·l| / √(1 − (t·l)²)` texels of depth per texel there, so the read moves `texel` (the
/// world size of a light texel at the point) times `√½` that slope, capped at [`OWN_STRAND_SLOPE_MAX`].
/// `tangent` and `to_light` are unit vectors. Measured against leaving out the fragments of the point's segment
/// and its two neighbours exactly (a probe of the reference's lists): the reference's hair within 0.3–2.2 % of
/// it on `default`, `blond` and `back-lit` (docs/truth.md).
pub fn own_strand_offset(texel: f32, tangent: Vec3, to_light: Vec3) -> f32 {
    let c = tangent.dot(to_light).abs().min(1.0);
    let s = (1.0 - c * c).max(1e-6).sqrt();
    texel * (std::f32::consts::FRAC_1_SQRT_2 * c / s).min(OWN_STRAND_SLOPE_MAX)
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
