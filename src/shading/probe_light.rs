//! The light a probe node holds and a fibre's response to it (`render.hair_model = fibres`; docs/truth.md, "The
//! probe's light by where it comes from"). The CPU model (the specification) of `shaders/common/probe_light.wgsl`.
//!
//! The traced probe (`pathtrace::probe`) keeps the light arriving at a point of the hair's skin from outside a
//! cone about the direction to the light ([`cone_cos`]): the light within it is the light forward-scattered
//! through the strands in front, which the eye pass takes per pixel from the method's hair count instead (Zinke
//! et al. 2008's global term, `shading::strand_lit`): a lattice node spread it over strands in front of which
//! the count differs (`back-lit` 1.18× the truth's mean with the cone in the probe, 1.04× so). Of the rest a node
//! keeps its integral over the sphere and the first two moments of its directions (luminance weighted), which a
//! fibre answers through its longitudinal response (`chiang::response_moments`): the moments along the fibre's
//! tangent, `m₁ = ⟨u⟩` and `m₂ = ⟨u²⟩` with `u = sin θ_i`, weight its Legendre moments
//! `K₀ + m₁ K₁ + (3 m₂ − 1) K₂`. The fibre's `M_p` sends light arriving at `θ_i` to `−θ_i`, so what the eye at
//! `θ_o` sees depends on how the light spreads along the fibre, which a mean cannot say.
//!
//! Every part is an integral over the sphere (radiance × solid angle), so nodes average and interpolate
//! linearly; the moments are kept as sums and divided at the read. Measured at the strand points under the
//! camera on `default` / `blond` / `back-lit`, against the light the path tracer's fibre sends to the eye there
//! (docs/truth.md): the fibre's albedo times the mean read 0.97 / 0.85 / 0.67 of it, 0.20–1.61 by height band;
//! this response, with the cone's light shaded there by the lobes for the light, 0.98 / 0.89 / 0.94, 0.83–1.22.
//! Through the image the reference's hair now reads 0.97 / 0.91 / 1.04 / 0.89 of the truth's mean on `default` /
//! `blond` / `back-lit` / `dense-coverage` ÷4 (0.95 / 0.88 / 0.97 / 0.89 with the albedo times the mean).

use glam::Vec3;

use super::hair_cover::{self, Cube};
use super::{chiang, mesh_bounce};

/// Rec. 709 luminance, the moments' weight.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// The cosine of the cone's half-angle about the direction to the light: the fibre's R lobe's longitudinal
/// standard deviation `√v₀`, twice the TT lobe's (15.0° for [`chiang::BETA_M`]); the light a strand in front
/// scatters forward lies within it. Through the image (the reference's hair mean over the truth's, docs/truth.md)
/// cones of 10°, 15° and 25° read 0.98 / 0.92 / 1.08 / 0.90, 0.97 / 0.91 / 1.04 / 0.89 and 0.92 / 0.87 / 0.94 /
/// 0.88 on `default` / `blond` / `back-lit` / `dense-coverage` ÷4.
pub fn cone_cos() -> f32 {
    chiang::FIBRE.variances()[0].sqrt().cos()
}

/// One probe node's light from outside the cone (integrals over the sphere, linear RGB or luminance), and the
/// hair's cover of the sky seen from the node, which lights a mesh with that light ([`mesh_probe_light`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ProbeLight {
    /// `∫ L dω`.
    pub rest: Vec3,
    /// `∫ lum(L) ω dω`.
    pub first: Vec3,
    /// `∫ lum(L) ω ωᵀ dω`: xx, yy, zz, xy, xz, yz.
    pub second: [f32; 6],
    /// The hair's cover of the six hemispheres about the axes ([`hair_cover::lattice`]).
    pub cover: Cube,
}

impl ProbeLight {
    /// Radiance `l` arriving alike from every direction.
    pub fn isotropic(l: Vec3) -> ProbeLight {
        let e = l * (4.0 * std::f32::consts::PI);
        let third = luminance(e) / 3.0;
        ProbeLight {
            rest: e,
            first: Vec3::ZERO,
            second: [third, third, third, 0.0, 0.0, 0.0],
            cover: Cube::default(),
        }
    }

    /// The mean radiance over the sphere (none from the cone).
    pub fn mean(&self) -> Vec3 {
        self.rest / (4.0 * std::f32::consts::PI)
    }

    /// Adds radiance `l` arriving from direction `w` (a unit vector) over solid angle `omega`.
    pub fn add_rest(&mut self, w: Vec3, l: Vec3, omega: f32) {
        self.rest += l * omega;
        let y = luminance(l) * omega;
        self.first += w * y;
        let s = [w.x * w.x, w.y * w.y, w.z * w.z, w.x * w.y, w.x * w.z, w.y * w.z];
        for (a, b) in self.second.iter_mut().zip(s) {
            *a += b * y;
        }
    }

    /// `⟨u⟩` and `⟨u²⟩` of the rest's directions along `tangent` (`u = tangent · ω`); an isotropic `0, ⅓` where
    /// the rest holds no light.
    pub fn moments_along(&self, tangent: Vec3) -> (f32, f32) {
        let y = luminance(self.rest);
        if y <= 0.0 {
            return (0.0, 1.0 / 3.0);
        }
        let [xx, yy, zz, xy, xz, yz] = self.second;
        let t = tangent;
        let quad = xx * t.x * t.x
            + yy * t.y * t.y
            + zz * t.z * t.z
            + 2.0 * (xy * t.x * t.y + xz * t.x * t.z + yz * t.y * t.z);
        (self.first.dot(t) / y, quad / y)
    }

    /// What a fibre of absorption `sigma_a` along `tangent` sends towards `to_eye` of this light
    /// (`chiang::response_lookup` of `table`), never negative.
    pub fn response(&self, table: &[f32], tangent: Vec3, to_eye: Vec3, sigma_a: Vec3) -> Vec3 {
        let (m1, m2) = self.moments_along(tangent);
        let sin_o = tangent.dot(to_eye).clamp(-1.0, 1.0);
        let [k0, k1, k2] = chiang::response_lookup(table, sin_o, sigma_a.max(Vec3::ZERO).map(f32::sqrt));
        self.rest * (k0 + k1 * m1 + k2 * (3.0 * m2 - 1.0)).max(Vec3::ZERO)
    }
}

/// What the eye pass adds to a hair point of `colour` along `tangent` from the probe `grid` at `at`
/// (`hair_ambient_light` in `shaders/common/mesh_bounce.wgsl`): under the traced probe
/// ([`mesh_bounce::Probe::Traced`]) the fibre's response to the light by the directions it arrives from
/// ([`ProbeLight::response`]); under the voxel probe the fibre's albedo times the mean
/// ([`mesh_bounce::hair_response`]).
pub fn probe_response(
    grid: &mesh_bounce::Grid<ProbeLight>,
    probe: mesh_bounce::Probe,
    at: Vec3,
    tangent: Vec3,
    to_eye: Vec3,
    colour: Vec3,
) -> Vec3 {
    let light = grid.at(at);
    match probe {
        mesh_bounce::Probe::Traced => light.response(
            chiang::table(),
            tangent,
            to_eye,
            super::marschner::absorption(colour),
        ),
        mesh_bounce::Probe::Voxels => mesh_bounce::hair_response(colour) * light.mean(),
    }
}

/// What a Lambertian mesh point of albedo `albedo` at `at`, its unit normal `normal` turned towards the eye,
/// sends to the eye of the light the hair around it scatters (`mesh_probe_light` in
/// `shaders/common/mesh_bounce.wgsl`), the hair's colour `colour`: the hair leaves with one fibre's albedo times
/// the light arriving around it in the probe (`hair_response(colour) ×` the mean, the voxel probe's own
/// response) and fills the part of the point's hemisphere the node's cover says ([`hair_cover::hemisphere`]).
/// The scalp seen between strands is lit so, as the path tracer's is, where with the light map's direct light
/// alone it was black; a floor beneath hanging hair takes what the little hair it sees sends. The lattice spans
/// the strands, so the light fades to nothing over one node spacing outside its bounds ([`fade`]) rather than
/// holding its edge.
pub fn mesh_probe_light(
    grid: &mesh_bounce::Grid<ProbeLight>,
    at: Vec3,
    normal: Vec3,
    albedo: Vec3,
    colour: Vec3,
) -> Vec3 {
    let node = grid.at(at);
    albedo
        * mesh_bounce::hair_response(colour)
        * node.mean()
        * hair_cover::hemisphere(node.cover, normal)
        * fade(grid, at)
}

/// 1 inside `grid`'s bounds, falling linearly to 0 at one node spacing outside them (by the distance to the box).
pub fn fade<T>(grid: &mesh_bounce::Grid<T>, at: Vec3) -> f32 {
    let spacing = ((grid.max - grid.min) / (mesh_bounce::NODES - 1) as f32).max(Vec3::splat(1e-6));
    let outside = ((grid.min - at).max(at - grid.max).max(Vec3::ZERO)) / spacing;
    (1.0 - outside.length()).max(0.0)
}

/// `grid` with each node's cover taken from `cover` (a lattice on the same bounds, [`hair_cover::lattice`]).
pub fn covered(
    mut grid: mesh_bounce::Grid<ProbeLight>,
    cover: &mesh_bounce::Grid<Cube>,
) -> mesh_bounce::Grid<ProbeLight> {
    for (node, c) in grid.values.iter_mut().zip(&cover.values) {
        node.cover = *c;
    }
    grid
}

/// The radiances of `grid` as light arriving alike from every direction ([`ProbeLight::isotropic`]), as the eye
/// pass reads a probe.
pub fn isotropic(grid: &mesh_bounce::Grid) -> mesh_bounce::Grid<ProbeLight> {
    mesh_bounce::Grid {
        min: grid.min,
        max: grid.max,
        values: grid.values.map(ProbeLight::isotropic),
    }
}

/// The grid as the frame uniforms carry it (`frame.bounce_grid`): [`NODE_VECTORS`] vectors a node,
/// `(rest, s_xx)`, `(first, s_yy)`, `(s_zz, s_xy, s_xz, s_yz)`, the cover's `(+x, −x, +y, −y)` and
/// `(+z, −z, 0, 0)`.
pub fn packed(grid: &mesh_bounce::Grid<ProbeLight>) -> [[f32; 4]; PACKED] {
    std::array::from_fn(|k| {
        let n = &grid.values[k / NODE_VECTORS];
        let (s, c) = (n.second, n.cover.0);
        match k % NODE_VECTORS {
            0 => n.rest.extend(s[0]).to_array(),
            1 => n.first.extend(s[1]).to_array(),
            2 => [s[2], s[3], s[4], s[5]],
            3 => [c[0], c[1], c[2], c[3]],
            _ => [c[4], c[5], 0.0, 0.0],
        }
    })
}

/// Vectors a node of [`packed`].
pub const NODE_VECTORS: usize = 5;

/// Vectors of [`packed`].
pub const PACKED: usize = NODE_VECTORS * mesh_bounce::NODES * mesh_bounce::NODES * mesh_bounce::NODES;

impl std::ops::Add for ProbeLight {
    type Output = ProbeLight;
    fn add(self, o: ProbeLight) -> ProbeLight {
        ProbeLight {
            rest: self.rest + o.rest,
            first: self.first + o.first,
            second: std::array::from_fn(|k| self.second[k] + o.second[k]),
            cover: self.cover + o.cover,
        }
    }
}

impl std::ops::Sub for ProbeLight {
    type Output = ProbeLight;
    fn sub(self, o: ProbeLight) -> ProbeLight {
        self + o * -1.0
    }
}

impl std::ops::Mul<f32> for ProbeLight {
    type Output = ProbeLight;
    fn mul(self, w: f32) -> ProbeLight {
        ProbeLight {
            rest: self.rest * w,
            first: self.first * w,
            second: self.second.map(|s| s * w),
            cover: self.cover * w,
        }
    }
}

impl std::ops::Div<f32> for ProbeLight {
    type Output = ProbeLight;
    fn div(self, w: f32) -> ProbeLight {
        ProbeLight {
            rest: self.rest / w,
            first: self.first / w,
            second: self.second.map(|s| s / w),
            cover: self.cover / w,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Light added direction by direction over a Fibonacci sphere of 4096 directions reads the isotropic moments
    /// (`⟨u⟩` 0 within 1e-3, `⟨u²⟩` ⅓ within 1e-3 along any tangent); light from one direction `w` reads
    /// `⟨u⟩ = t·w`, `⟨u²⟩ = (t·w)²`; the moments survive the lattice's averaging (a mean of nodes is the node of
    /// the pooled light).
    #[test]
    fn the_moments_follow_the_light() {
        let n = 4096;
        let mut all = ProbeLight::default();
        for k in 0..n {
            all.add_rest(
                mesh_bounce::fibonacci(k, n),
                Vec3::new(0.3, 0.2, 0.1),
                4.0 * std::f32::consts::PI / n as f32,
            );
        }
        for t in [Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            let (m1, m2) = all.moments_along(t);
            assert!(m1.abs() < 1e-3 && (m2 - 1.0 / 3.0).abs() < 1e-3, "{m1} {m2}");
            let iso = ProbeLight::isotropic(Vec3::new(0.3, 0.2, 0.1)).moments_along(t);
            assert!(iso.0.abs() < 1e-6 && (iso.1 - 1.0 / 3.0).abs() < 1e-6, "{iso:?}");
        }
        let w = Vec3::new(0.6, 0.0, 0.8);
        let mut one = ProbeLight::default();
        one.add_rest(w, Vec3::ONE, 0.01);
        let t = Vec3::new(0.0, 0.6, 0.8);
        let (m1, m2) = one.moments_along(t);
        assert!(
            (m1 - 0.64).abs() < 1e-6 && (m2 - 0.64 * 0.64).abs() < 1e-6,
            "{m1} {m2}"
        );
        let mut other = ProbeLight::default();
        other.add_rest(-w, Vec3::ONE, 0.01);
        let (m1, m2) = ((one + other) / 2.0).moments_along(t);
        assert!(m1.abs() < 1e-6 && (m2 - 0.64 * 0.64).abs() < 1e-6, "{m1} {m2}");
    }

    /// A radiance lattice read as light arriving alike from every direction gives its radiance back as the mean,
    /// at nodes and between them (within 1e-6).
    #[test]
    fn an_isotropic_lattice_keeps_its_radiance() {
        let mut grid = mesh_bounce::Grid {
            min: Vec3::ZERO,
            max: Vec3::ONE,
            values: [Vec3::ZERO; mesh_bounce::NODES * mesh_bounce::NODES * mesh_bounce::NODES],
        };
        for (n, v) in grid.values.iter_mut().enumerate() {
            *v = Vec3::new((n % 7) as f32, 0.5, (n % 5) as f32 * 0.1);
        }
        let light = isotropic(&grid);
        for p in [Vec3::ZERO, Vec3::splat(0.3), Vec3::new(0.9, 0.1, 0.55)] {
            let d = (light.at(p).mean() - grid.at(p)).abs().max_element();
            assert!(d < 1e-6, "{p}: {d}");
        }
    }

    /// The response to spread light ([`chiang::response_lookup`] of [`chiang::table`]) is the path tracer's fibre's
    /// (`pathtrace::bsdf::FibreBsdf`, pbrt's `f · |cos|`) under light whose `u = sin θ_i` has the density
    /// `½ (1 + 3 m₁ u + 5/2 (3 m₂ − 1) P₂(u))` and a uniform azimuth (m₁ 0.25, m₂ 0.4, positive everywhere;
    /// and isotropic, m₁ 0, m₂ ⅓), integrated by the midpoint rule (128 `u` × 32 azimuths × 32 offsets `h`), at
    /// four eyes `sin θ_o` and two absorptions on the table's nodes. Bound: 1 % + 1e-4. Measured: 0.58 % at most.
    #[test]
    fn response_matches_the_bsdf() {
        use crate::pathtrace::bsdf::{FibreBsdf, fibre_absorbing};
        let table = chiang::table();
        let mut worst = 0.0f32;
        for i in [13, 32, 41, 58] {
            let sin_o = chiang::node_response_sin(i);
            let wo = Vec3::new(sin_o, 0.0, (1.0 - sin_o * sin_o).max(0.0).sqrt());
            for j in [3, 10] {
                let sigma = super::super::fibre_transport::node_sigma(j);
                let fibre = fibre_absorbing(Vec3::splat(sigma));
                let bsdfs: Vec<FibreBsdf> = (0..32)
                    .map(|m| FibreBsdf::new(&fibre, -1.0 + (m as f32 + 0.5) / 16.0))
                    .collect();
                let k = chiang::response_lookup(table, sin_o, Vec3::splat(sigma.sqrt()));
                for (m1, m2) in [(0.25f32, 0.4f32), (0.0, 1.0 / 3.0)] {
                    let mut want = 0.0f32;
                    for a in 0..128 {
                        let u = -1.0 + (a as f32 + 0.5) / 64.0;
                        let density =
                            0.5 * (1.0 + 3.0 * m1 * u + 2.5 * (3.0 * m2 - 1.0) * 0.5 * (3.0 * u * u - 1.0));
                        let c = (1.0 - u * u).max(0.0).sqrt();
                        for b in 0..32 {
                            let phi = (b as f32 + 0.5) / 32.0 * std::f32::consts::TAU;
                            let wi = Vec3::new(u, c * phi.cos(), c * phi.sin());
                            let f: f32 =
                                bsdfs.iter().map(|x| x.eval(wo, wi).x * wi.z.abs()).sum::<f32>() / 32.0;
                            want += f * density / 64.0 / 32.0;
                        }
                    }
                    let got = (k[0] + k[1] * m1 + k[2] * (3.0 * m2 - 1.0)).x;
                    let d = (got - want).abs();
                    worst = worst.max(d / want);
                    assert!(
                        d <= 0.01 * want + 1e-4,
                        "sin θ_o {sin_o}, σ {sigma}, m {m1} {m2}: table {got}, BSDF {want}"
                    );
                }
            }
        }
        println!("response against the BSDF: max relative {worst:.4}");
    }
}
