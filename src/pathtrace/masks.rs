//! What the camera sees first through each pixel: the share of a pixel's footprint where the first hit is a
//! fibre, and where it is a mesh. The error decomposition (`measure::truth`) judges images over the hair (pixels
//! mostly covered by fibres) and over the shadow receivers (pixels mostly covered by meshes) separately, so that
//! neither the background nor the other region dilutes a figure.

use rayon::prelude::*;

use super::bvh::Bvh;
use super::fibre::Surface;
use super::integrator::camera_ray;
use crate::scene::Camera;

/// A pixel's first-hit shares, each in [0, 1] (the rest is background).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstHits {
    pub fibre: f32,
    pub mesh: f32,
}

/// The first-hit shares of every pixel of a `width × height` image (row after row), from `n × n` rays through
/// each pixel, one at the centre of each stratum.
pub fn first_hits(bvh: &Bvh, camera: &Camera, width: usize, height: usize, n: usize) -> Vec<FirstHits> {
    let n = n.max(1);
    let share = 1.0 / (n * n) as f32;
    (0..width * height)
        .into_par_iter()
        .map(|pixel| {
            let (x, y) = ((pixel % width) as f32, (pixel / width) as f32);
            let mut out = FirstHits::default();
            for k in 0..n * n {
                let dx = ((k % n) as f32 + 0.5) / n as f32;
                let dy = ((k / n) as f32 + 0.5) / n as f32;
                match bvh
                    .closest_hit(&camera_ray(camera, width, height, x + dx, y + dy), f32::INFINITY)
                    .map(|h| h.surface)
                {
                    Some(Surface::Fibre) => out.fibre += share,
                    Some(Surface::Mesh { .. }) => out.mesh += share,
                    None => {}
                }
            }
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::fibre::Segment;
    use crate::pathtrace::triangle::Triangle;
    use glam::Vec3;

    /// A fibre across the middle of the view in front of a square: the fibre's rows are fibre, the square's
    /// pixels beside it mesh, the corners background; a pixel the fibre's edge crosses has both shares.
    #[test]
    fn a_fibre_before_a_square_splits_the_pixels() {
        let r = 0.2;
        let square = |z: f32| {
            let c = |x: f32, y: f32| Vec3::new(x, y, z);
            let tri = |p0: Vec3, p1: Vec3, p2: Vec3| Triangle {
                p0,
                e1: p1 - p0,
                e2: p2 - p0,
                albedo: Vec3::ONE,
            };
            vec![
                tri(c(-0.5, -0.5), c(0.5, -0.5), c(0.5, 0.5)),
                tri(c(-0.5, -0.5), c(0.5, 0.5), c(-0.5, 0.5)),
            ]
        };
        let bvh = Bvh::with_triangles(
            vec![Segment::new(
                Vec3::new(-5.0, 0.0, 0.0),
                Vec3::new(5.0, 0.0, 0.0),
                r,
                r,
            )],
            square(-1.0),
        );
        let camera = Camera {
            target: [0.0; 3],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            distance: 4.0,
            fov_y_deg: 30.0,
        };
        let (w, h) = (32, 24);
        let hits = first_hits(&bvh, &camera, w, h, 4);
        let at = |x: usize, y: usize| hits[y * w + x];
        // Pixels per world unit at distance d: 12 / (d · tan 15°). The fibre (d = 4) spans rows 12 ± 2.24, so
        // rows 10..=13 are fibre across the whole width; the square (d = 5) spans 16 ± 4.48 columns and 12 ± 4.48
        // rows, so row 8 of column 16 is mesh, row 9 is split by the fibre's edge, and the corner is background.
        for y in 10..=13 {
            assert_eq!(
                at(1, y),
                FirstHits {
                    fibre: 1.0,
                    mesh: 0.0
                },
                "row {y}"
            );
            assert_eq!(
                at(16, y),
                FirstHits {
                    fibre: 1.0,
                    mesh: 0.0
                },
                "row {y}"
            );
        }
        assert_eq!(
            at(16, 8),
            FirstHits {
                fibre: 0.0,
                mesh: 1.0
            }
        );
        let edge = at(16, 9);
        assert!(edge.fibre > 0.0 && edge.mesh > 0.0, "{edge:?}");
        assert_eq!(at(0, 0), FirstHits::default());
        assert!(hits.iter().all(|p| p.fibre + p.mesh <= 1.0 + 1e-6));
        assert!(
            hits.iter().any(|p| p.fibre > 0.0 && p.fibre < 1.0),
            "no pixel on the fibre's edge"
        );
    }
}
