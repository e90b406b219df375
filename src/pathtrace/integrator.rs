//! A CPU path tracer over the fibres (the reference the real-time methods are compared with): camera rays,
//! next-event estimation to the light (`light.rs`) through an any-hit shadow ray, BSDF sampling, Russian
//! roulette after depth 3 (pbrt's throughput-based survival), at most `max_depth` bounces, linear float RGB.
//! Each sample's random stream is `SplitMix64::stream(seed, pixel << 32 ^ sample)`, so an image depends only on
//! its seed, whatever the thread count; the samples are summed per pixel in `f64`, a NaN or infinite one left
//! out and counted (`accumulation.rs`).
//!
//! Each hit scatters by Chiang et al. 2016's fibre BSDF (`bsdf.rs`) in the frame x = tangent, y along the hit's
//! offset `h` (tangent × ray direction), z = x × y (towards where the ray came from). The fibre is a volume the
//! BSDF stands for: fibres cull back faces, so a direction into one passes out of it (Mitsuba 3's convention: the
//! walk inside enters and leaves at the hit). Mesh triangles are Lambertian with the mesh's colour as albedo,
//! from either side.

use glam::Vec3;

use super::accumulation::Sums;
use super::bsdf::{FibreBsdf, FibreParams};
use super::bvh::{Bvh, NO_PRIMITIVE};
use super::effects::{Effects, Events, FirstHit, map_point, transmittance};
use super::fibre::{Hit, Ray, Surface};
use super::light::{Light, Lighting};
use crate::rng::SplitMix64;
use crate::scene::Camera;

/// Bounces at most, a guard only: Russian roulette ends the paths. Light hair is mostly multiple scattering and
/// its chains are long: at 32 bounces `blond`'s truth lost 9.8 % of its light over the hair (14.6 % in red; 64
/// spp, two seeds 1 % apart), `default`'s 0.2 %, at the same render time.
pub const MAX_DEPTH: u32 = 1024;

/// What one path-traced image takes: its size, samples per pixel, seed, bounce limit, fibre and effects
/// (`crate::path_scene::PathScene` derives them from the preset's settings).
#[derive(Clone, Debug)]
pub struct TraceSettings {
    pub width: usize,
    pub height: usize,
    pub samples: u32,
    pub seed: u64,
    /// Bounces at most ([`MAX_DEPTH`] for the truth: hair's chains of scattering are long).
    pub max_depth: u32,
    /// The fibres' material.
    pub fibre: FibreParams,
    /// The effects the image carries ([`Effects::TRUTH`] for the truth).
    pub effects: Effects,
}

/// The BSDF at a hit and its local frame.
struct Shading {
    frame: [Vec3; 3],
    bsdf: FibreBsdf,
}

impl Shading {
    fn new(hit: &Hit, dir: Vec3, fibre: &FibreParams) -> Shading {
        let x = hit.tangent;
        let y = x
            .cross(dir)
            .try_normalize()
            .unwrap_or_else(|| x.any_orthonormal_vector());
        Shading {
            frame: [x, y, x.cross(y)],
            bsdf: FibreBsdf::new(fibre, hit.h),
        }
    }
    fn local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.frame[0]), w.dot(self.frame[1]), w.dot(self.frame[2]))
    }
    fn world(&self, l: Vec3) -> Vec3 {
        l.x * self.frame[0] + l.y * self.frame[1] + l.z * self.frame[2]
    }
}

/// Where a ray leaving `hit` along `w` starts: just off the surface on `w`'s side. Into a fibre is through it:
/// fibres cull back faces, as Mitsuba 3's curves do, and the BSDF stands for the walk inside.
fn leave(hit: &Hit, w: Vec3, eps: f32) -> Vec3 {
    hit.point + eps * hit.normal.dot(w).signum() * hit.normal
}

/// A unit vector in the hemisphere around `n`, cosine-distributed (Malley's method).
fn cosine_around(n: Vec3, u: [f32; 2]) -> Vec3 {
    let (r, phi) = (u[0].sqrt(), 2.0 * std::f32::consts::PI * u[1]);
    let (t, b) = n.any_orthonormal_pair();
    (r * phi.cos() * t + r * phi.sin() * b + (1.0 - u[0]).max(0.0).sqrt() * n).normalize()
}

/// A unit vector uniform over the sphere.
fn uniform_sphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// What a hit does with light: the BSDF times the cosine towards the light, and a sampled continuation (its
/// world direction and `f·|cos|/pdf`).
fn scatter(
    hit: &Hit,
    dir: Vec3,
    s: &TraceSettings,
    to_light: Vec3,
    u: [f32; 4],
) -> (Vec3, Option<(Vec3, Vec3)>) {
    match hit.surface {
        Surface::Fibre => {
            let shading = Shading::new(hit, dir, &s.fibre);
            let wo = shading.local(-dir);
            let l = shading.local(to_light);
            let out = shading.bsdf.outgoing(wo);
            let direct = shading.bsdf.eval_at(&out, l) * l.z.abs();
            let next = shading
                .bsdf
                .sample_at(&out, u)
                .map(|x| (shading.world(x.wi).normalize(), x.f * x.wi.z.abs() / x.pdf));
            (direct, next)
        }
        Surface::Mesh { albedo } => {
            let cos = hit.normal.dot(to_light).max(0.0);
            let next = cosine_around(hit.normal, [u[0], u[1]]);
            (albedo * std::f32::consts::FRAC_1_PI * cos, Some((next, albedo)))
        }
    }
}

/// The camera ray through image point `(x, y)` in pixels (top left origin).
pub fn camera_ray(camera: &Camera, width: usize, height: usize, x: f32, y: f32) -> Ray {
    Rays::new(camera, width, height).at(x, y)
}

/// [`camera_ray`]'s per-image part, worked out once.
struct Rays {
    eye: Vec3,
    to_world: glam::Mat4,
    tan: f32,
    aspect: f32,
    size: (f32, f32),
}

impl Rays {
    fn new(camera: &Camera, width: usize, height: usize) -> Rays {
        Rays {
            eye: camera.eye(),
            to_world: camera.world_to_view().inverse(),
            tan: (camera.fov_y_deg.to_radians() * 0.5).tan(),
            aspect: width as f32 / height as f32,
            size: (width as f32, height as f32),
        }
    }

    fn at(&self, x: f32, y: f32) -> Ray {
        let d = Vec3::new(
            (2.0 * x / self.size.0 - 1.0) * self.tan * self.aspect,
            (1.0 - 2.0 * y / self.size.1) * self.tan,
            -1.0,
        );
        Ray::new(self.eye, self.to_world.transform_vector3(d))
    }
}

/// The radiance arriving at `ray`'s origin from along `ray.dir`: every effect of `s` (the light itself, a delta,
/// is not met).
fn radiance(bvh: &Bvh, light: &impl Lighting, s: &TraceSettings, mut ray: Ray, rng: &mut SplitMix64) -> Vec3 {
    let (mut sum, mut beta) = (Vec3::ZERO, Vec3::ONE);
    // The primitive the ray leaves, which it cannot meet again.
    let mut from = NO_PRIMITIVE;
    for depth in 0..s.max_depth {
        let Some(hit) = bvh.closest_hit_from(&ray, f32::INFINITY, from) else {
            break;
        };
        from = hit.primitive;
        let eps = hit.offset();
        let u = [rng.unit(), rng.unit(), rng.unit(), rng.unit()];
        // The shadow ray's share of the light under the image's hair shadows.
        let visible = |to_light: Vec3, distance: f32| {
            let shadow = Ray::new(leave(&hit, to_light, eps), to_light);
            let reach = distance * (1.0 - 1e-4);
            transmittance(
                &s.effects.hair_shadows,
                map_point(
                    &hit,
                    bvh.segments().get(hit.primitive as usize).map(|g| (g.a, g.b)),
                ),
                matches!(hit.surface, Surface::Fibre).then_some(hit.tangent),
                || bvh.any_hit_from(&shadow, reach, hit.primitive),
                || bvh.any_mesh_hit_from(&shadow, reach, hit.primitive),
            )
        };
        if depth > 0 && s.effects.events == Events::Fibres && matches!(hit.surface, Surface::Mesh { .. }) {
            break;
        }
        if let (0, FirstHit::Raster(raster)) = (depth, &s.effects.first_hit) {
            let (to_light, distance) = raster.light.toward(hit.point);
            return raster.radiance(&hit, -ray.dir, to_light, visible(to_light, distance));
        }
        let arrival = light.arrival(hit.point);
        let to_light = arrival.map_or(Vec3::Z, |a| a.to_light);
        let (direct, mut next) = scatter(&hit, ray.dir, s, to_light, u);
        if let (0, Surface::Fibre, FirstHit::Isotropic(albedo)) = (depth, hit.surface, &s.effects.first_hit) {
            next = Some((uniform_sphere([u[2], u[3]]), *albedo));
        }
        if let Some(a) = arrival.filter(|_| direct.max_element() > 0.0) {
            sum += beta * direct * a.irradiance * visible(a.to_light, a.distance);
        }
        if s.effects.events == Events::One {
            break;
        }
        let Some((wi, weight)) = next else {
            break;
        };
        beta *= weight;
        if depth >= 3 {
            let survive = beta.max_element().min(0.95);
            if rng.unit() >= survive {
                break;
            }
            beta /= survive;
        }
        ray = Ray::new(leave(&hit, wi, eps), wi);
    }
    sum
}

/// The radiance arriving at `p` from `directions` directions uniform over the sphere (every effect of `s` along
/// each; the light itself, a delta, is not among them), each with its direction: what the fibres model's probe
/// (`shading::mesh_bounce`, `pathtrace::probe`) estimates at its points. A point inside a fibre sees out of it
/// (back faces culled). `stream` picks the directions and their paths.
pub fn arriving<'a>(
    bvh: &'a Bvh,
    light: &'a impl Lighting,
    s: &'a TraceSettings,
    p: Vec3,
    directions: u32,
    stream: u64,
) -> impl Iterator<Item = (Vec3, Vec3)> + 'a {
    (0..directions).map(move |k| {
        let mut rng = SplitMix64::stream(s.seed, stream << 32 ^ k as u64);
        let dir = uniform_sphere([rng.unit(), rng.unit()]);
        (dir, radiance(bvh, light, s, Ray::new(p, dir), &mut rng))
    })
}

/// The mean of [`arriving`]'s radiances.
pub fn arriving_mean(directions: impl Iterator<Item = (Vec3, Vec3)>) -> Vec3 {
    let (sum, n) = directions.fold((Vec3::ZERO, 0u32), |(sum, n), (_, l)| (sum + l, n + 1));
    sum / n.max(1) as f32
}

/// The image, row after row, `width × height` linear RGB.
pub fn render(bvh: &Bvh, camera: &Camera, light: &Light, s: &TraceSettings) -> Vec<Vec3> {
    render_in_passes(bvh, camera, light, s, s.samples, &mut crate::progress::Quiet).mean()
}

/// [`render`] in passes of `pass` samples per pixel, `progress` told the samples so far after each; it stops early
/// when that answers `false`. Returns the samples taken: their mean, their count per pixel and those dropped.
/// Sample `k` of a pixel has its own stream and the sums run in sample order, so the image is [`render`]'s
/// whatever `pass`.
pub fn render_in_passes(
    bvh: &Bvh,
    camera: &Camera,
    light: &Light,
    s: &TraceSettings,
    pass: u32,
    progress: &mut dyn crate::progress::Progress,
) -> Accumulation {
    let mut acc = Accumulation::new(s);
    while acc.samples() < s.samples {
        let n = pass.max(1).min(s.samples - acc.samples());
        acc.add(bvh, camera, light, s, n);
        let done = acc.samples();
        let label = format!("path tracing: {done}/{} spp", s.samples);
        if !progress.step(&label, crate::progress::share(done as usize, s.samples as usize)) {
            break;
        }
    }
    acc
}

/// A progressive image: the radiance of samples `0..samples()` of every pixel summed ([`Sums`]: in `f64`, a NaN
/// or infinite sample left out and counted). Adding `n` more samples takes samples `samples()..samples() + n` of
/// each pixel's streams, so the mean after any sequence of additions is [`render`]'s at that sample count.
#[derive(Clone, Debug)]
pub struct Accumulation {
    sums: Sums,
    done: u32,
}

impl Accumulation {
    /// No samples yet, sized for `s`' image.
    pub fn new(s: &TraceSettings) -> Accumulation {
        Accumulation {
            sums: Sums::new(s.width, s.height),
            done: 0,
        }
    }

    /// Samples per pixel so far.
    pub fn samples(&self) -> u32 {
        self.done
    }

    /// Samples left out so far for a NaN or infinite radiance, over the whole image.
    pub fn dropped(&self) -> u64 {
        self.sums.dropped()
    }

    /// Adds the next `n` samples of every pixel.
    pub fn add(&mut self, bvh: &Bvh, camera: &Camera, light: &Light, s: &TraceSettings, n: u32) {
        let rays = Rays::new(camera, s.width, s.height);
        self.sums.add(self.done..self.done + n, |pixel, sample| {
            let (x, y) = (pixel % s.width, pixel / s.width);
            let mut rng = SplitMix64::stream(s.seed, ((pixel as u64) << 32) ^ sample as u64);
            let (jx, jy) = (rng.unit(), rng.unit());
            radiance(bvh, light, s, rays.at(x as f32 + jx, y as f32 + jy), &mut rng)
        });
        self.done += n;
    }

    /// The mean radiance per pixel of the samples kept (black before the first sample).
    pub fn mean(&self) -> Vec<Vec3> {
        self.sums.mean()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pathtrace::fibre::Segment;
    use crate::pathtrace::light::DirectionalLight;
    use crate::pathtrace::triangle::square;

    fn settings(seed: u64) -> TraceSettings {
        TraceSettings {
            width: 32,
            height: 24,
            samples: 4,
            seed,
            max_depth: 32,
            effects: Effects::TRUTH,
            fibre: crate::pathtrace::bsdf::fibre_params([0.8; 3]),
        }
    }

    fn camera() -> Camera {
        Camera {
            target: [0.0; 3],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            distance: 4.0,
            fov_y_deg: 30.0,
        }
    }

    const LIGHT: Light = Light::Directional(DirectionalLight {
        to_light: Vec3::Z,
        irradiance: Vec3::ONE,
    });

    #[test]
    fn the_same_seed_gives_the_same_image() {
        let mut rng = SplitMix64::new(4);
        let segments = (0..200)
            .map(|_| {
                let a = Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 0.4;
                Segment::new(
                    a,
                    a + Vec3::new(rng.normal(), rng.normal(), rng.normal()) * 0.3,
                    0.03,
                    0.02,
                )
            })
            .collect();
        let bvh = Bvh::new(segments);
        let light = Light::Directional(DirectionalLight {
            to_light: Vec3::new(0.3, 0.8, 0.5).normalize(),
            irradiance: Vec3::ONE,
        });
        let a = render(&bvh, &camera(), &light, &settings(1));
        assert_eq!(a, render(&bvh, &camera(), &light, &settings(1)));
        assert_ne!(a, render(&bvh, &camera(), &light, &settings(2)));
        assert!(a.iter().any(|p| p.max_element() > 0.0));
        let mut quiet = crate::progress::Quiet;
        let passes = render_in_passes(&bvh, &camera(), &light, &settings(1), 3, &mut quiet);
        assert_eq!((passes.mean(), passes.samples(), passes.dropped()), (a, 4, 0));
        // Stops once told half the samples are in (2 of 4).
        let mut half = |_: &str, f: f32| f < 0.5;
        let stopped = render_in_passes(&bvh, &camera(), &light, &settings(1), 1, &mut half);
        assert_eq!(stopped.samples(), 2);
    }

    /// A Lambertian square facing the camera, lit at 60° from its normal by irradiance π: every pixel on it shows
    /// albedo × cos 60° exactly (the light's one bounce; what leaves the square escapes), from either side.
    #[test]
    fn a_lambertian_square_shows_albedo_times_cosine() {
        let albedo = Vec3::new(0.8, 0.5, 0.25);
        for facing in [1.0f32, -1.0] {
            let bvh = Bvh::with_triangles(Vec::new(), square(Vec3::ZERO, Vec3::X, Vec3::Y, 5.0, albedo));
            let light = Light::Directional(DirectionalLight {
                to_light: Vec3::new(0.0, 60f32.to_radians().sin(), facing * 0.5),
                irradiance: Vec3::splat(std::f32::consts::PI),
            });
            let mut cam = camera();
            cam.yaw_deg = if facing > 0.0 { 0.0 } else { 180.0 };
            let image = render(&bvh, &cam, &light, &settings(5));
            for p in &image {
                assert!(
                    (*p - albedo * 0.5).abs().max_element() < 1e-5,
                    "{p} for {}",
                    albedo * 0.5
                );
            }
        }
    }

    /// The mean radiance arriving at a point a unit above the centre of a lit Lambertian square of half-size 1
    /// (albedo ρ, lit along its normal by irradiance π: radiance ρ) is ρ times the square's share of the sphere,
    /// `4 asin(a² / (a² + d²)) / 4π` = 1/6 at a = d = 1; what leaves the square escapes. 80 000 directions: the
    /// share's relative standard error is 0.8 %, measured 0.984, the tolerance 4 %. Below the square (its unlit
    /// side) nothing arrives.
    #[test]
    fn the_light_arriving_over_a_lit_square_is_its_solid_angle() {
        let albedo = Vec3::new(0.8, 0.5, 0.25);
        let bvh = Bvh::with_triangles(Vec::new(), square(Vec3::ZERO, Vec3::X, Vec3::Y, 1.0, albedo));
        let light = Light::Directional(DirectionalLight {
            to_light: Vec3::Z,
            irradiance: Vec3::splat(std::f32::consts::PI),
        });
        let s = settings(11);
        let above = arriving_mean(arriving(&bvh, &light, &s, Vec3::Z, 80_000, 3));
        let expected = albedo / 6.0;
        assert!(
            ((above - expected) / expected).abs().max_element() < 0.04,
            "{above} vs {expected}"
        );
        assert_eq!(
            arriving_mean(arriving(&bvh, &light, &s, -Vec3::Z, 2_000, 3)),
            Vec3::ZERO
        );
    }

    /// A lone fibre along x through the view's centre, lit from the camera: pixels whose four corner rays all
    /// pass inside the fibre's band are lit, pixels whose corners all pass on one side of it are black.
    #[test]
    fn a_lone_fibre_lights_exactly_where_it_projects() {
        let r = 0.2;
        let bvh = Bvh::new(vec![Segment::new(
            Vec3::new(-5.0, 0.0, 0.0),
            Vec3::new(5.0, 0.0, 0.0),
            r,
            r,
        )]);
        let s = settings(3);
        let cam = camera();
        let image = render(&bvh, &cam, &LIGHT, &s);
        // Height at which the ray through an image point crosses the plane z = 0.
        let y_at = |x: usize, y: usize| {
            let ray = camera_ray(&cam, s.width, s.height, x as f32, y as f32);
            ray.at(-ray.origin.z / ray.dir.z).y
        };
        let (mut lit, mut dark) = (0, 0);
        for y in 0..s.height {
            for x in 0..s.width {
                let ys = [y_at(x, y), y_at(x + 1, y), y_at(x, y + 1), y_at(x + 1, y + 1)];
                let v = image[y * s.width + x].max_element();
                if ys.iter().all(|c| c.abs() < 0.99 * r) {
                    assert!(v > 0.0, "({x}, {y}) inside the fibre is black");
                    lit += 1;
                } else if ys.iter().all(|&c| c > 1.01 * r) || ys.iter().all(|&c| c < -1.01 * r) {
                    assert_eq!(v, 0.0, "({x}, {y}) off the fibre is lit");
                    dark += 1;
                }
            }
        }
        assert!(
            lit >= s.width && dark >= s.width * (s.height - 8),
            "{lit} lit, {dark} dark"
        );
    }
}
