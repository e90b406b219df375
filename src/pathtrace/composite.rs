//! The path-traced image as the window shows it: the fibres' and meshes' radiance over the raster's background
//! colour, weighted by how much of each pixel the scene covers. The path tracer returns black where a camera ray
//! meets nothing; the raster clears to `render.background`. [`coverage`] estimates each pixel's covered share
//! with `N × N` stratified camera rays (any hit, no shading) and [`over_background`] adds
//! `(1 − coverage) × background` before the sRGB encoding, so the window's path-traced view and the compare
//! view's path-traced slot sit on the same background as the raster images beside them.

use glam::Vec3;
use rayon::prelude::*;

use super::bvh::Bvh;
use super::integrator::camera_ray;
use crate::scene::Camera;

/// The share of each pixel of a `width × height` image that the scene covers, from `n × n` stratified camera rays
/// through the pixel, row after row, the rows on rayon's pool.
pub fn coverage(bvh: &Bvh, camera: &Camera, width: usize, height: usize, n: usize) -> Vec<f32> {
    let n = n.max(1);
    let mut out = vec![0.0f32; width * height];
    out.par_chunks_mut(width.max(1)).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let mut hits = 0usize;
            for j in 0..n {
                for i in 0..n {
                    let (sx, sy) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let ray = camera_ray(camera, width, height, x as f32 + sx, y as f32 + sy);
                    hits += usize::from(bvh.any_hit(&ray, f32::INFINITY));
                }
            }
            *px = hits as f32 / (n * n) as f32;
        }
    });
    out
}

/// `radiance + (1 − coverage) × background` per pixel (linear RGB), encoded as opaque sRGB.
pub fn over_background(
    radiance: &[Vec3],
    coverage: &[f32],
    background: [f32; 3],
    width: u32,
    height: u32,
) -> image::RgbaImage {
    let bg = Vec3::from(background);
    image::RgbaImage::from_fn(width, height, |x, y| {
        let i = (y * width + x) as usize;
        let c = radiance.get(i).copied().unwrap_or(Vec3::ZERO)
            + (1.0 - coverage.get(i).copied().unwrap_or(0.0)) * bg;
        let [r, g, b] = c.to_array().map(crate::io::srgb8);
        image::Rgba([r, g, b, 255])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::triangle::Triangle;

    #[test]
    fn coverage_is_the_covered_share_of_each_pixel() {
        // A camera at z = 1 looking down −z with a 90° vertical field: a 4 × 2 image spans x ∈ [−2, 2],
        // y ∈ [−1, 1] at z = 0, one unit a pixel. A quad over x ∈ [1, 2] covers pixel column 3 wholly; one over
        // x ∈ [0.5, 2] also covers the right half of column 2 (2 of the 4 stratified columns of rays).
        let camera = Camera {
            target: [0.0, 0.0, 0.0],
            distance: 1.0,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            fov_y_deg: 90.0,
        };
        let quad = |x0: f32, x1: f32| {
            let (a, b, c, d) = (
                Vec3::new(x0, -1.0, 0.0),
                Vec3::new(x1, -1.0, 0.0),
                Vec3::new(x1, 1.0, 0.0),
                Vec3::new(x0, 1.0, 0.0),
            );
            let tri = |p0: Vec3, p1: Vec3, p2: Vec3| Triangle {
                p0,
                e1: p1 - p0,
                e2: p2 - p0,
                albedo: Vec3::ONE,
            };
            [tri(a, b, c), tri(a, c, d)]
        };
        let bvh = Bvh::with_triangles(Vec::new(), quad(1.0, 2.0).to_vec());
        let cov = coverage(&bvh, &camera, 4, 2, 4);
        assert_eq!(cov, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], "{cov:?}");
        let bvh = Bvh::with_triangles(Vec::new(), quad(0.5, 2.0).to_vec());
        let cov = coverage(&bvh, &camera, 4, 2, 4);
        assert_eq!(cov, vec![0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.5, 1.0], "{cov:?}");
    }

    #[test]
    fn uncovered_pixels_show_the_background_and_covered_ones_their_radiance() {
        // Linear 0.5 encodes to sRGB 188 (1.055 · 0.5^(1/2.4) − 0.055 = 0.7354 → 187.5) and 0.6 to 203
        // (0.7977 → 203.4); 0.2 + (1 − 0.5) · 0.6 = 0.5.
        let radiance = [Vec3::ZERO, Vec3::splat(0.5), Vec3::splat(0.2)];
        let img = over_background(&radiance, &[0.0, 1.0, 0.5], [0.6; 3], 3, 1);
        assert_eq!(img.get_pixel(0, 0).0, [203, 203, 203, 255]);
        assert_eq!(img.get_pixel(1, 0).0, [188, 188, 188, 255]);
        assert_eq!(img.get_pixel(2, 0).0, [188, 188, 188, 255]);
    }
}
