//! A small equirectangular environment map the user loads (`fur.env_map`), as the HDR map Andersen et al. 2016
//! §5 sample their guard hairs' 16 directional lights from; [`super::environment`]'s procedural sky is used
//! without one. Radiance `.hdr` files are read as they are; PNG texels are taken as sRGB and linearised. Texel
//! `(i, j)` of a `2h × h` map covers the polar angle `θ ∈ [π j/h, π (j+1)/h]` from `+y` and the azimuth
//! `φ ∈ [2π i/2h, 2π (i+1)/2h]` from `+x` towards `+z` (`ω = (sin θ cos φ, cos θ, sin θ sin φ)`).
//!
//! The map shapes the light, the scene's light sets its strength: radiance `L(ω) = E m(ω) / ∫ lum(m) dω`
//! (`E` the scene light's radiance, `lum` the channel mean), so a grey map's lights carry exactly the single
//! light's energy, as the sky's do. N lights cut the whole sphere into the sky's strata (rows of equal `ω_y` range
//! and equal azimuth range, [`super::environment`]); each texel falls, by its centre, in one stratum, whose light
//! sits at the radiance-weighted mean direction of its texels and carries their `∫ L dω` (median-cut style,
//! Debevec 2005). Every texel counts once, so the lights sum to the map's integral exactly.

use super::environment::{EnvLight, row_counts};
use glam::{DVec3, Vec3};
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

/// Widest map accepted (a small map: the lights average it).
pub const MAX_WIDTH: u32 = 4096;

/// Why a map cannot be used; the message names the key and the file.
#[derive(Debug, thiserror::Error)]
#[error("fur.env_map = {}: {message}", path.display())]
pub struct EnvMapError {
    pub path: PathBuf,
    pub message: String,
}

/// An equirectangular map in linear radiance (relative: [`EnvMap::lights`] scales it).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl EnvMap {
    /// Reads `path` (`.hdr`, or PNG as sRGB).
    pub fn load(path: &Path) -> Result<EnvMap, EnvMapError> {
        let bad = |message: String| EnvMapError {
            path: path.to_path_buf(),
            message,
        };
        let image = image::open(path).map_err(|e| bad(format!("cannot read the image: {e}")))?;
        let srgb = !matches!(
            image,
            image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
        );
        let rgb = image.to_rgb32f();
        let texels = rgb
            .pixels()
            .map(|p| {
                let [r, g, b] = p.0;
                if srgb {
                    Vec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
                } else {
                    Vec3::new(r, g, b)
                }
            })
            .collect();
        EnvMap::from_texels(rgb.width(), rgb.height(), texels).map_err(bad)
    }

    /// A map of `width × height` texels, row by row from the `+y` pole; refused unless `width = 2 height`, at
    /// most [`MAX_WIDTH`] wide, every value finite and ≥ 0 and some light in it.
    pub fn from_texels(width: u32, height: u32, texels: Vec<Vec3>) -> Result<EnvMap, String> {
        if height == 0 || width != 2 * height {
            return Err(format!(
                "{width}×{height} texels: an equirectangular map is twice as wide as it is high"
            ));
        }
        if width > MAX_WIDTH {
            return Err(format!("{width} texels wide: at most {MAX_WIDTH}"));
        }
        if texels.len() != (width * height) as usize {
            return Err(format!("{} texels for {width}×{height}", texels.len()));
        }
        if let Some(k) = texels
            .iter()
            .position(|t| !t.is_finite() || t.min_element() < 0.0)
        {
            return Err(format!(
                "texel ({}, {}) is {}: radiance must be finite and ≥ 0",
                k as u32 % width,
                k as u32 / width,
                texels[k]
            ));
        }
        let map = EnvMap {
            width,
            height,
            texels,
        };
        if map.luminance_integral() <= 0.0 {
            return Err("the map is black: it holds no light".into());
        }
        Ok(map)
    }

    /// Texel `(i, j)`'s centre direction and solid angle.
    fn texel_direction(&self, i: u32, j: u32) -> (Vec3, f64) {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let (t0, t1) = (PI * f64::from(j) / h, PI * f64::from(j + 1) / h);
        let theta = 0.5 * (t0 + t1);
        let phi = TAU * (f64::from(i) + 0.5) / w;
        let dir = DVec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
        (dir.as_vec3(), (TAU / w) * (t0.cos() - t1.cos()))
    }

    /// `∫ lum(m) dω` over the sphere.
    fn luminance_integral(&self) -> f64 {
        let mut total = 0.0;
        for j in 0..self.height {
            let (_, dw) = self.texel_direction(0, j);
            let row = &self.texels[(j * self.width) as usize..((j + 1) * self.width) as usize];
            total += row.iter().map(|t| f64::from(t.element_sum()) / 3.0).sum::<f64>() * dw;
        }
        total
    }

    /// `n` ≥ 2 lights (the sky's strata over the whole sphere) carrying the scene light's radiance `radiance` as
    /// the map distributes it.
    pub fn lights(&self, n: usize, radiance: Vec3) -> Vec<EnvLight> {
        let rows = row_counts(n.max(2));
        let scale = radiance.as_dvec3() / self.luminance_integral();
        let mut total = vec![DVec3::ZERO; rows.iter().sum()];
        let mut weighted = vec![DVec3::ZERO; total.len()];
        let mut centre = vec![DVec3::ZERO; total.len()];
        let firsts: Vec<usize> = rows
            .iter()
            .scan(0, |acc, &per| {
                let first = *acc;
                *acc += per;
                Some(first)
            })
            .collect();
        for j in 0..self.height {
            for i in 0..self.width {
                let (dir, dw) = self.texel_direction(i, j);
                let r = (((1.0 - dir.y) * 0.5 * rows.len() as f32) as usize).min(rows.len() - 1);
                let phi = f64::from(dir.z).atan2(f64::from(dir.x)).rem_euclid(TAU);
                let c = ((phi / TAU * rows[r] as f64) as usize).min(rows[r] - 1);
                let k = firsts[r] + c;
                let l = self.texels[(j * self.width + i) as usize].as_dvec3() * scale * dw;
                total[k] += l;
                weighted[k] += dir.as_dvec3() * l.element_sum();
                centre[k] += dir.as_dvec3();
            }
        }
        (0..total.len())
            .map(|k| EnvLight {
                to_light: weighted[k]
                    .try_normalize()
                    .or_else(|| centre[k].try_normalize())
                    .unwrap_or(DVec3::Y)
                    .as_vec3(),
                radiance: total[k].as_vec3(),
            })
            .collect()
    }
}

/// The sRGB transfer function's inverse.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `2h × h` map of grey `base` with one texel `(i, j)` of `spot`.
    fn spot_map(h: u32, base: f32, (i, j): (u32, u32), spot: f32) -> EnvMap {
        let w = 2 * h;
        let mut texels = vec![Vec3::splat(base); (w * h) as usize];
        texels[(j * w + i) as usize] = Vec3::splat(spot);
        EnvMap::from_texels(w, h, texels).unwrap()
    }

    /// A grey map's lights carry the scene light's radiance exactly (every texel counts once: within 1e-5
    /// relative, f32 sums), at every light count; where the strata are symmetric (2 lights: two hemispheres;
    /// 16: two rows of 8) a uniform map's lights balance (|Σ r_k ω_k| below 1e-3 of Σ r_k).
    #[test]
    fn a_grey_maps_lights_carry_the_scene_lights_radiance() {
        let map = spot_map(32, 0.5, (0, 0), 0.5);
        let e = Vec3::new(1.0, 0.9, 0.8);
        for n in [2, 3, 7, 16, 33, 64] {
            let lights = map.lights(n, e);
            assert_eq!(lights.len(), n);
            let sum: Vec3 = lights.iter().map(|l| l.radiance).sum();
            assert!(((sum - e) / e).abs().max_element() < 1e-5, "n {n}: {sum}");
            let pull: Vec3 = lights.iter().map(|l| l.to_light * l.radiance.x).sum();
            if n == 2 || n == 16 {
                assert!(pull.length() < 1e-3 * sum.x, "n {n}: {pull}");
            }
            for l in &lights {
                assert!((l.to_light.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    /// A bright texel pulls the light of its stratum to it: texel (8, 4) of a 32×16 map has its centre at
    /// θ = 4.5 π/16, φ = 8.5 · 2π/32 (by hand: (−0.0758, 0.6344, 0.7693)); with 1000× the background, the
    /// brightest of 16 lights points within 0.1 rad of it and carries over half the energy.
    #[test]
    fn a_bright_texel_pulls_its_light() {
        let map = spot_map(16, 0.01, (8, 4), 10.0);
        let lights = map.lights(16, Vec3::ONE);
        let brightest = lights
            .iter()
            .max_by(|a, b| a.radiance.x.total_cmp(&b.radiance.x))
            .unwrap();
        let (t, p) = (
            4.5 * std::f32::consts::PI / 16.0,
            8.5 * std::f32::consts::TAU / 32.0,
        );
        let spot = Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
        assert!(
            (spot - Vec3::new(-0.0758, 0.6344, 0.7693)).length() < 1e-3,
            "{spot}"
        );
        assert!(
            brightest.to_light.angle_between(spot) < 0.1,
            "{}",
            brightest.to_light
        );
        assert!(brightest.radiance.x > 0.5, "{}", brightest.radiance);
    }

    /// Bad maps are refused with what is wrong; `load` names the key and the file.
    #[test]
    fn bad_maps_are_refused() {
        let grey = |w: u32, h: u32| vec![Vec3::ONE; (w * h) as usize];
        assert!(
            EnvMap::from_texels(30, 16, grey(30, 16))
                .unwrap_err()
                .contains("twice as wide")
        );
        assert!(
            EnvMap::from_texels(8192, 4096, Vec::new())
                .unwrap_err()
                .contains("at most 4096")
        );
        assert!(
            EnvMap::from_texels(8, 4, vec![Vec3::ZERO; 32])
                .unwrap_err()
                .contains("black")
        );
        let mut nan = grey(8, 4);
        nan[9] = Vec3::new(f32::NAN, 0.0, 0.0);
        assert!(
            EnvMap::from_texels(8, 4, nan)
                .unwrap_err()
                .contains("texel (1, 1)")
        );
        let e = EnvMap::load(Path::new("/nonexistent/sky.hdr"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("fur.env_map = /nonexistent/sky.hdr: cannot read the image"),
            "{e}"
        );
    }

    /// A PNG is read as sRGB: 8-bit 188 is linear 0.5029 (by the sRGB formula), and the file round-trips into the
    /// same lights as the texels it holds.
    #[test]
    fn a_png_map_is_read_as_srgb() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sky.png");
        image::RgbImage::from_pixel(16, 8, image::Rgb([188, 188, 188]))
            .save(&path)
            .unwrap();
        let map = EnvMap::load(&path).unwrap();
        let expected =
            EnvMap::from_texels(16, 8, vec![Vec3::splat(srgb_to_linear(188.0 / 255.0)); 128]).unwrap();
        assert_eq!(map, expected);
        assert!((srgb_to_linear(188.0 / 255.0) - 0.5029).abs() < 1e-4);
    }
}
