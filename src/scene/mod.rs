//! Scene model: strands, opaque meshes, one light and a camera — no more than a scene needs.
//!
//! Geometry lives in [`Scene`]; the light and camera are small parameter structs that presets and the GUI edit.
//! Loaders (`.hair`, glTF, TressFX `.tfx`, USC-HairSalon `.data`, USD) and the procedural generators all produce a [`Scene`].

pub mod fur_shapes;
pub mod generate;
pub mod gltf_check;
pub mod gltf_load;
pub mod hair;
pub mod light_frame;
pub mod load;
pub mod pick;
pub mod progress;
pub mod style;
pub mod tfx;
pub mod usc_data;
#[cfg(feature = "usd")]
pub mod usd;
pub mod usda_write;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grow(*p))
    }
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }
    /// Radius of the bounding sphere around [`Aabb::center`].
    pub fn radius(&self) -> f32 {
        self.extent().length() * 0.5
    }
    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }
}

/// Hair strands as polylines. `counts[i]` is the number of points of strand `i`; points are stored strand after
/// strand. Optional arrays are per point and, when present, have `points.len()` entries.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Strands {
    pub points: Vec<Vec3>,
    pub counts: Vec<u32>,
    pub thickness: Option<Vec<f32>>,
    /// Per-point opacity in [0,1] (the `.hair` format stores transparency = 1 - alpha).
    pub alpha: Option<Vec<f32>>,
    pub color: Option<Vec<Vec3>>,
}

impl Strands {
    pub fn strand_count(&self) -> usize {
        self.counts.len()
    }
    pub fn point_count(&self) -> usize {
        self.points.len()
    }
    /// Line segments: a strand of n points has n-1 segments.
    pub fn segment_count(&self) -> usize {
        self.counts.iter().map(|&c| c.saturating_sub(1) as usize).sum()
    }
    /// Iterates `(first_point, point_count)` per strand.
    pub fn ranges(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.counts.iter().scan(0usize, |start, &c| {
            let r = (*start, c as usize);
            *start += c as usize;
            Some(r)
        })
    }
    /// Appends the strands of `other`, materialising optional arrays with defaults where only one side has them.
    pub fn append(&mut self, other: &Strands) {
        fn merge<T: Clone>(a: &mut Option<Vec<T>>, b: &Option<Vec<T>>, na: usize, nb: usize, def: T) {
            match (a.as_mut(), b) {
                (None, None) => {}
                (Some(a), Some(b)) => a.extend_from_slice(b),
                (Some(a), None) => a.extend(std::iter::repeat_n(def, nb)),
                (None, Some(b)) => {
                    let mut v = vec![def; na];
                    v.extend_from_slice(b);
                    *a = Some(v);
                }
            }
        }
        let (na, nb) = (self.points.len(), other.points.len());
        merge(&mut self.thickness, &other.thickness, na, nb, 1.0);
        merge(&mut self.alpha, &other.alpha, na, nb, 1.0);
        merge(&mut self.color, &other.color, na, nb, Vec3::ONE);
        self.points.extend_from_slice(&other.points);
        self.counts.extend_from_slice(&other.counts);
    }
}

/// An opaque triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (same length as `positions`).
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
    pub color: Vec3,
}

impl Mesh {
    /// All `meshes` as one (indices re-based); the colour of the first.
    pub fn merged(meshes: &[Mesh]) -> Mesh {
        let mut out = Mesh {
            color: meshes.first().map_or(Vec3::ONE, |m| m.color),
            ..Mesh::default()
        };
        for m in meshes {
            let base = out.positions.len() as u32;
            out.positions.extend_from_slice(&m.positions);
            out.normals.extend_from_slice(&m.normals);
            out.indices.extend(m.indices.iter().map(|i| i + base));
        }
        out
    }

    /// Computes area-weighted smooth normals from the triangles.
    pub fn compute_normals(&mut self) {
        let mut n = vec![Vec3::ZERO; self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
            let f = (self.positions[b] - self.positions[a]).cross(self.positions[c] - self.positions[a]);
            n[a] += f;
            n[b] += f;
            n[c] += f;
        }
        self.normals = n
            .into_iter()
            .map(|v| v.try_normalize().unwrap_or(Vec3::Y))
            .collect();
    }
}

/// Geometry of one scene; bounds are computed once at construction.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub strands: Strands,
    pub meshes: Vec<Mesh>,
    /// What reading the file said without failing, one line each: a USD layer missing or unreadable, an arc
    /// dropped (see [`load::load_scene_with`]). Empty for a generated scene.
    pub warnings: Vec<String>,
    strand_bounds: Aabb,
    bounds: Aabb,
}

impl Scene {
    pub fn new(strands: Strands, meshes: Vec<Mesh>) -> Scene {
        let strand_bounds = Aabb::from_points(&strands.points);
        let bounds = meshes
            .iter()
            .fold(strand_bounds, |b, m| b.union(Aabb::from_points(&m.positions)));
        Scene {
            strands,
            meshes,
            warnings: Vec::new(),
            strand_bounds,
            bounds,
        }
    }
    /// Bounds of the hair alone: the light frustum and map ranges are fitted to these.
    pub fn strand_bounds(&self) -> Aabb {
        self.strand_bounds
    }
    /// Bounds of everything (hair and meshes).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
    /// What the camera frames: the hair when there is any (a floor should not push it into the distance), else
    /// everything.
    pub fn framing_bounds(&self) -> Aabb {
        if self.strand_bounds.is_empty() {
            self.bounds
        } else {
            self.strand_bounds
        }
    }
    /// This scene with the meshes `moving` mapped by `transform` (normals by its linear part), what the renderer
    /// draws after `SceneGpu::pose_meshes` with the same arguments; a mesh the scene lacks is an error.
    pub fn posed(&self, moving: &[usize], transform: glam::Affine3A) -> Result<Scene, String> {
        check_moving(moving, self.meshes.len())?;
        let mut scene = self.clone();
        for &m in moving {
            let mesh = &mut scene.meshes[m];
            mesh.positions
                .iter_mut()
                .for_each(|p| *p = transform.transform_point3(*p));
            mesh.normals
                .iter_mut()
                .for_each(|n| *n = transform.transform_vector3(*n).normalize_or_zero());
        }
        scene.bounds = scene.meshes.iter().fold(scene.strand_bounds, |b, m| {
            b.union(Aabb::from_points(&m.positions))
        });
        Ok(scene)
    }
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len() / 3).sum()
    }
    /// Moves the strands' points to `points` (one per point, same order; strands, thickness, alpha and colour
    /// kept) and updates the bounds: the CPU side of the renderer's one write path for moving hair
    /// (`Renderer::update_points`).
    pub fn set_strand_points(&mut self, points: &[Vec3]) -> Result<(), PointCountMismatch> {
        if points.len() != self.strands.points.len() {
            return Err(PointCountMismatch {
                expected: self.strands.points.len(),
                got: points.len(),
            });
        }
        self.strands.points.copy_from_slice(points);
        *self = Scene::new(
            std::mem::take(&mut self.strands),
            std::mem::take(&mut self.meshes),
        );
        Ok(())
    }
}

/// Checks that every mesh of `moving` is one of the scene's `count` meshes: the one check of both posers (the
/// renderer's `SceneGpu::pose_meshes` and [`Scene::posed`]).
pub fn check_moving(moving: &[usize], count: usize) -> Result<(), String> {
    match moving.iter().find(|&&m| m >= count) {
        Some(m) => Err(format!(
            "mesh {m} cannot move with the root frame: the scene has {count} meshes"
        )),
        None => Ok(()),
    }
}

/// New strand points whose count is not the scene's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{got} new strand points for a scene of {expected} points (the topology of moving hair is fixed)")]
pub struct PointCountMismatch {
    pub expected: usize,
    pub got: usize,
}

/// The light's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum LightKind {
    #[default]
    Directional,
    Spot,
}

/// One light, placed by azimuth/elevation around the scene centre so it can be dragged and typed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Light {
    pub kind: LightKind,
    /// Degrees around +Y, 0 = light placed on +Z.
    pub azimuth_deg: f32,
    /// Degrees above the horizontal plane.
    pub elevation_deg: f32,
    /// Spot only: distance from the scene centre in scene radii.
    pub distance: f32,
    /// Spot only: full cone angle in degrees.
    pub cone_deg: f32,
    pub intensity: f32,
    pub color: [f32; 3],
    /// What the hair maps' light frame is fitted to ([`LightFit`]).
    pub fit: LightFit,
}

/// What the light frame of the hair maps is fitted to, the one policy every light-space pass follows
/// (`Renderer::hair_light_frame`). For a still scene `per-frame` and `bound` give the same frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum LightFit {
    /// The strands of the frame being drawn: the tightest frame, so every texel and depth bit covers hair, but
    /// under motion the frustum and the normalised light depth follow the hair and can swim.
    PerFrame,
    /// A conservative bound fitted once: the bound the scene's motion declares (`Renderer::set_fit_bound`), else
    /// the strands as they were uploaded, grown by the current strands where they leave it, so a moving groom
    /// keeps one frustum and one depth normalisation.
    Bound,
    /// Stabilised (Valient 2008, "Stable rendering of cascaded shadow maps"): fitted once to the bounding sphere
    /// of the bound `Bound` uses (the motion's, else the strands as uploaded), so the extent and the depth range
    /// change with neither the pose nor the light direction, with the light-space origin snapped to whole
    /// texels, so a strand that moves changes only the texels it crosses. The default.
    #[default]
    Stable,
}

impl Default for Light {
    fn default() -> Self {
        Light {
            kind: LightKind::Directional,
            azimuth_deg: 35.0,
            elevation_deg: 50.0,
            distance: 3.0,
            cone_deg: 40.0,
            intensity: 1.0,
            color: [1.0, 1.0, 1.0],
            fit: LightFit::Stable,
        }
    }
}

impl Light {
    /// Unit vector from the scene centre towards the light.
    pub fn to_light(&self) -> Vec3 {
        let (az, el) = (self.azimuth_deg.to_radians(), self.elevation_deg.to_radians());
        Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos())
    }

    /// Where a spot light stands: `distance` radii of `around` (at least 1.01) from its centre towards the
    /// light. The one placement: the renderer's light frames and the path tracer's light read it, with the box
    /// the light fit places the light around (`SceneGpu::light_fit`; a still scene's whole bounds).
    pub fn spot_position(&self, around: &Aabb) -> Vec3 {
        let (centre, radius) = if around.is_empty() {
            (Vec3::ZERO, 1e-3)
        } else {
            (around.center(), around.radius().max(1e-3))
        };
        centre + self.to_light() * radius * self.distance.max(1.01)
    }
}

/// An orbit camera around a target point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Camera {
    pub target: [f32; 3],
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    /// Distance from the target in world units; 0 means "frame the scene" on load.
    pub distance: f32,
    pub fov_y_deg: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            target: [0.0; 3],
            yaw_deg: 20.0,
            pitch_deg: 10.0,
            distance: 0.0,
            fov_y_deg: 40.0,
        }
    }
}

impl Camera {
    pub fn eye(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::from(self.target) + self.distance * Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos())
    }
    /// Places the camera so the whole of `bounds` is in view.
    pub fn frame(&mut self, bounds: &Aabb) {
        if bounds.is_empty() {
            return;
        }
        self.target = bounds.center().into();
        let r = bounds.radius().max(1e-3);
        self.distance = r / (self.fov_y_deg.to_radians() * 0.5).sin() * 1.05;
    }
    pub fn world_to_view(&self) -> glam::Mat4 {
        glam::Mat4::look_at_rh(self.eye(), Vec3::from(self.target), Vec3::Y)
    }
}
