//! The scene's meshes for the path tracer: triangles with the mesh's colour as a Lambertian albedo, hit from
//! either side (Möller & Trumbore 1997), flat-shaded by their geometric normal (as Mitsuba 3 renders a mesh
//! with `face_normals`, what `export --format mitsuba` writes).

use glam::Vec3;

use super::fibre::{Hit, Ray, Surface};
use crate::scene::{Aabb, Mesh};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub p0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    pub albedo: Vec3,
}

/// Every non-degenerate triangle of `meshes`.
pub fn triangles(meshes: &[Mesh]) -> Vec<Triangle> {
    let mut out = Vec::new();
    for m in meshes {
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            let tri = Triangle {
                p0: a,
                e1: b - a,
                e2: c - a,
                albedo: m.color,
            };
            if tri.e1.cross(tri.e2).length_squared() > 0.0 {
                out.push(tri);
            }
        }
    }
    out
}

/// The two triangles of a square of half-size `half` around `centre`, spanned by the unit axes `u` and `v`, of
/// albedo `albedo` (the tests' lit floors and walls).
#[cfg(test)]
pub fn square(centre: Vec3, u: Vec3, v: Vec3, half: f32, albedo: Vec3) -> Vec<Triangle> {
    let corner = |a: f32, b: f32| centre + half * (a * u + b * v);
    let tri = |p0: Vec3, p1: Vec3, p2: Vec3| Triangle {
        p0,
        e1: p1 - p0,
        e2: p2 - p0,
        albedo,
    };
    vec![
        tri(corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0)),
        tri(corner(-1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)),
    ]
}

impl Triangle {
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&[self.p0, self.p0 + self.e1, self.p0 + self.e2])
    }

    /// The crossing with `t` in `(t_min, t_max)`, the normal facing where the ray came from.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let p = ray.dir.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let s = ray.origin - self.p0;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = ray.dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let n = self.e1.cross(self.e2).normalize();
        let normal = if n.dot(ray.dir) > 0.0 { -n } else { n };
        Some(Hit {
            t,
            point: ray.at(t),
            tangent: self.e1.normalize(),
            normal,
            h: 0.0,
            primitive: 0,
            radius: 0.0,
            surface: Surface::Mesh { albedo: self.albedo },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_meets_a_triangle_from_either_side_inside_its_edges_only() {
        let tri = Triangle {
            p0: Vec3::ZERO,
            e1: Vec3::X,
            e2: Vec3::Y,
            albedo: Vec3::ONE,
        };
        for (origin, dir, t) in [
            (Vec3::new(0.25, 0.25, 2.0), -Vec3::Z, Some(2.0)),
            (Vec3::new(0.25, 0.25, -3.0), Vec3::Z, Some(3.0)),
            (Vec3::new(0.75, 0.75, 2.0), -Vec3::Z, None),
            (Vec3::new(-0.01, 0.5, 2.0), -Vec3::Z, None),
            (Vec3::new(0.25, 0.25, 2.0), Vec3::Z, None),
        ] {
            let hit = tri.intersect(&Ray::new(origin, dir), 0.0, 10.0);
            assert_eq!(hit.map(|h| h.t), t, "{origin} {dir}");
            if let Some(h) = hit {
                assert_eq!(h.normal, -dir, "the normal faces the ray");
            }
        }
    }
}
