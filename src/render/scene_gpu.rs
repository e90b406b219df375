//! The scene on the GPU, the one home of everything the renderer knows about the geometry: the strand and mesh
//! buffers (sized from the scene, checked against the device's limits, with copy rights so they can be
//! rewritten), the bounds, and a generation that changes whenever the geometry does. Moving hair has one write
//! path, [`SceneGpu::update_points`]: new positions with their tangents (derived from them on the CPU by
//! [`write_tangents`], as at upload) written into the existing buffers, the bounds refitted, a new generation.
//! Meshes that ride on a moving root frame (a turning head) have theirs, [`SceneGpu::pose_meshes`]: their rest
//! vertices transformed on the CPU and written into the existing mesh buffer, which every pass that draws
//! meshes (the eye, the light passes, the opaque shadow map) reads.
//! Whatever depends on the geometry (the light frame, the inspector's lists, the bench's reference) keys on
//! [`SceneGpu::generation`], never on settings.

use std::sync::atomic::{AtomicU64, Ordering};

use super::caster::lines::StrandLines;
use super::caster::ribbons::StrandRibbons;
use super::caster::{LightCaster, LightStrands};
use super::geometry::{
    HairVertex, MeshVertex, RIBBON_VERTICES_PER_SEGMENT, hair_indices, hair_vertices, write_tangents,
};
use super::probe_cache::{self, Bake, ProbeCache, ProbeKey};
use crate::gpu::{Gpu, GpuError};
use crate::pathtrace::triangle::Triangle;
use crate::scene::{Aabb, LightFit, PointCountMismatch, Scene};
use crate::shading::mesh_bounce;
use crate::shading::probe_light::ProbeLight;
use glam::{Affine3A, Vec3};
use wgpu::util::DeviceExt;

/// Generations are unique across every scene of the process, so a cache keyed on one never confuses two scenes.
static NEXT_GENERATION: AtomicU64 = AtomicU64::new(1);

fn next_generation() -> u64 {
    NEXT_GENERATION.fetch_add(1, Ordering::Relaxed)
}

/// The bounds the renderer fits frusta and ranges to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneBounds {
    /// The hair alone (the hair maps' light frame, the eye depth range).
    pub strands: Aabb,
    /// Hair and meshes (the camera's range, the meshes' shadow map, where a spot light stands).
    pub all: Aabb,
}

/// The scene's buffers, bounds and generation.
pub struct SceneGpu {
    /// Per strand point; vertex, storage and copy-destination usage.
    pub hair_vertices: wgpu::Buffer,
    /// One index pair per segment; index and storage usage.
    pub hair_indices: wgpu::Buffer,
    pub hair_index_count: u32,
    /// The layout of [`crate::render::geometry::RIBBON_GROUP`] (the renderer's).
    pub ribbon_layout: wgpu::BindGroupLayout,
    /// The strand buffers bound with `ribbon_layout` (drawn as light-facing ribbons), or the buffer that exceeds
    /// the storage
    /// binding limit (name, bytes, limit).
    ribbons: Result<StrandRibbons, (&'static str, u64, u64)>,
    /// The strands drawn as lines.
    lines: StrandLines,
    pub mesh_vertices: wgpu::Buffer,
    pub mesh_indices: wgpu::Buffer,
    pub mesh_index_count: u32,
    /// Bytes of GPU memory these buffers hold.
    pub bytes: u64,
    /// The strand vertices as uploaded last, which [`SceneGpu::update_points`] rewrites (positions, tangents).
    vertices: Vec<HairVertex>,
    /// Each strand's `(first point, point count)`.
    ranges: Vec<(usize, usize)>,
    /// The mesh vertices as uploaded (rest pose), which [`SceneGpu::pose_meshes`] transforms.
    mesh_rest: Vec<MeshVertex>,
    /// Each mesh's `(first vertex, vertex count)`.
    mesh_ranges: Vec<(usize, usize)>,
    mesh_bounds: Aabb,
    /// The meshes' bounds at rest, which [`LightFit::Stable`] places a spot light around (posing moves none).
    mesh_rest_bounds: Aabb,
    bounds: SceneBounds,
    /// The strands as uploaded, or the bound given by [`SceneGpu::set_fit_bound`]: what [`LightFit::Bound`]
    /// fits to and [`LightFit::Stable`] takes the bounding sphere of.
    fit_bound: Aabb,
    generation: u64,
    /// The meshes as the probe of `shading::mesh_bounce` sees them (posed as drawn), and its answers kept.
    bounce_triangles: Vec<BounceTriangle>,
    probes: ProbeCache,
}

/// A digest of the strand points' positions and thicknesses and the posed triangles: equal poses give equal
/// digests, and two poses whose digests are equal are taken for one (a 64-bit hash).
fn pose_digest(vertices: &[HairVertex], triangles: &[BounceTriangle]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for v in vertices {
        (v.position.map(f32::to_bits), v.thickness.to_bits()).hash(&mut h);
    }
    for t in triangles {
        let t = &t.triangle;
        [t.p0, t.e1, t.e2, t.albedo]
            .map(|v| v.to_array().map(f32::to_bits))
            .hash(&mut h);
    }
    h.finish()
}

impl SceneGpu {
    /// Uploads `scene`'s strands and meshes; `ribbon_layout` is the renderer's
    /// [`crate::render::geometry::ribbon_layout`].
    pub fn upload(
        gpu: &Gpu,
        scene: &Scene,
        ribbon_layout: &wgpu::BindGroupLayout,
    ) -> Result<SceneGpu, GpuError> {
        let points = scene.strands.point_count() as u64;
        if points > u32::MAX as u64 {
            return Err(GpuError::TooLarge {
                what: "strand points".into(),
                bytes: points,
                limit: u32::MAX as u64,
            });
        }
        let hv = hair_vertices(scene);
        let hi = hair_indices(scene);
        let mut mv = Vec::new();
        let mut mi = Vec::new();
        let mut mesh_ranges = Vec::with_capacity(scene.meshes.len());
        for m in &scene.meshes {
            let base = mv.len() as u32;
            mesh_ranges.push((mv.len(), m.positions.len()));
            for (p, n) in m.positions.iter().zip(&m.normals) {
                mv.push(MeshVertex {
                    position: (*p).into(),
                    normal: (*n).into(),
                    color: m.color.into(),
                });
            }
            mi.extend(m.indices.iter().map(|i| i + base));
        }
        let sizes = [
            ("strand vertex buffer", std::mem::size_of_val(hv.as_slice())),
            ("strand index buffer", std::mem::size_of_val(hi.as_slice())),
            ("mesh vertex buffer", std::mem::size_of_val(mv.as_slice())),
            ("mesh index buffer", std::mem::size_of_val(mi.as_slice())),
        ];
        for (what, bytes) in sizes {
            gpu.check_buffer_size(what, bytes as u64)?;
        }
        let buf = |label: &str, contents: &[u8], usage| {
            // Empty buffers are legal but a zero-sized binding is not: keep at least one HairVertex.
            let padded;
            let contents = if contents.is_empty() {
                padded = [0u8; std::mem::size_of::<HairVertex>()];
                &padded[..]
            } else {
                contents
            };
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let v = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST;
        let i = wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST;
        let s = wgpu::BufferUsages::STORAGE;
        let hair_vertices = buf("hairlab.scene.hair_vertices", bytemuck::cast_slice(&hv), v | s);
        let hair_indices = buf("hairlab.scene.hair_indices", bytemuck::cast_slice(&hi), i | s);
        let binding_limit = gpu.device.limits().max_storage_buffer_binding_size;
        let ribbon_group = match sizes[..2].iter().find(|(_, b)| *b as u64 > binding_limit) {
            Some(&(what, bytes)) => Err((what, bytes as u64, binding_limit)),
            None => Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hairlab.scene.ribbon_group"),
                layout: ribbon_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: hair_vertices.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: hair_indices.as_entire_binding(),
                    },
                ],
            })),
        };
        let bounce = bounce_triangles(&mv, &mi);
        let mesh_bounds = scene
            .meshes
            .iter()
            .fold(Aabb::EMPTY, |b, m| b.union(Aabb::from_points(&m.positions)));
        let strands = scene.strand_bounds();
        let lines = StrandLines {
            vertices: hair_vertices.clone(),
            indices: hair_indices.clone(),
            index_count: hi.len() as u32,
        };
        let ribbons = ribbon_group.map(|points| StrandRibbons {
            points,
            segment_count: hi.len() as u32 / 2,
        });
        Ok(SceneGpu {
            lines,
            ribbons,
            hair_vertices,
            hair_indices,
            hair_index_count: hi.len() as u32,
            ribbon_layout: ribbon_layout.clone(),
            mesh_vertices: buf(
                "hairlab.scene.mesh_vertices",
                bytemuck::cast_slice(&mv),
                v | wgpu::BufferUsages::COPY_SRC,
            ),
            mesh_indices: buf("hairlab.scene.mesh_indices", bytemuck::cast_slice(&mi), i),
            mesh_index_count: mi.len() as u32,
            bytes: sizes.iter().map(|(_, b)| *b as u64).sum(),
            vertices: hv,
            ranges: scene.strands.ranges().collect(),
            mesh_rest: mv,
            mesh_ranges,
            mesh_bounds,
            mesh_rest_bounds: mesh_bounds,
            bounds: SceneBounds {
                strands,
                all: scene.bounds(),
            },
            fit_bound: strands,
            generation: next_generation(),
            bounce_triangles: bounce,
            probes: ProbeCache::default(),
        })
    }

    /// The one write path for moving hair: `points` (one per strand point, in the scene's order) replace the
    /// positions, tangents are derived from them as at upload, both are written into the existing vertex
    /// buffer, the bounds follow, and the generation changes. Nothing is re-created.
    pub fn update_points(&mut self, gpu: &Gpu, points: &[Vec3]) -> Result<(), PointCountMismatch> {
        if points.len() != self.vertices.len() {
            return Err(PointCountMismatch {
                expected: self.vertices.len(),
                got: points.len(),
            });
        }
        for (v, p) in self.vertices.iter_mut().zip(points) {
            v.position = (*p).into();
        }
        write_tangents(&mut self.vertices, self.ranges.iter().copied());
        if !self.vertices.is_empty() {
            gpu.queue
                .write_buffer(&self.hair_vertices, 0, bytemuck::cast_slice(&self.vertices));
        }
        let strands = Aabb::from_points(points);
        self.bounds = SceneBounds {
            strands,
            all: strands.union(self.mesh_bounds),
        };
        self.generation = next_generation();
        Ok(())
    }

    /// The write path for meshes that move rigidly (the head on a turning root frame): the meshes `moving`
    /// (indices into the scene's meshes) are drawn at their rest vertices mapped by `transform` (normals by its
    /// linear part, a rotation), every other mesh at rest. Always computed from the rest vertices, so a pose
    /// gives the same bits whatever was drawn before; the bounds follow and the generation changes.
    pub fn pose_meshes(&mut self, gpu: &Gpu, moving: &[usize], transform: Affine3A) -> Result<(), GpuError> {
        crate::scene::check_moving(moving, self.mesh_ranges.len()).map_err(GpuError::Setting)?;
        let mut mv = self.mesh_rest.clone();
        for &m in moving {
            let (first, n) = self.mesh_ranges[m];
            for v in &mut mv[first..first + n] {
                v.position = transform.transform_point3(Vec3::from(v.position)).into();
                v.normal = transform.transform_vector3(Vec3::from(v.normal)).into();
            }
        }
        if !mv.is_empty() {
            gpu.queue
                .write_buffer(&self.mesh_vertices, 0, bytemuck::cast_slice(&mv));
        }
        self.mesh_bounds = mv.iter().fold(Aabb::EMPTY, |b, v| b.grow(Vec3::from(v.position)));
        for t in &mut self.bounce_triangles {
            t.pose(&mv);
        }
        self.bounds.all = self.bounds.strands.union(self.mesh_bounds);
        self.generation = next_generation();
        Ok(())
    }

    /// Reads the mesh vertex positions back from the GPU (tests: the posed meshes a frame draws).
    pub fn read_mesh_positions(&self, gpu: &Gpu) -> Result<Vec<Vec3>, GpuError> {
        let bytes = std::mem::size_of_val(self.mesh_rest.as_slice()) as u64;
        if bytes == 0 {
            return Ok(Vec::new());
        }
        let raw = crate::gpu::readback::copy_out(gpu, &self.mesh_vertices)?;
        let vertices: Vec<MeshVertex> = bytemuck::pod_collect_to_vec(&raw[..bytes as usize]);
        Ok(vertices.iter().map(|v| Vec3::from(v.position)).collect())
    }

    /// Makes `bound` (e.g. the bound of a whole motion) what [`LightFit::Bound`] fits the hair maps to; `None`
    /// goes back to the strands' current bounds. The light frame changes, so the generation does.
    pub fn set_fit_bound(&mut self, bound: Option<Aabb>) {
        self.fit_bound = bound.unwrap_or(self.bounds.strands);
        self.generation = next_generation();
    }

    /// Changes whenever the geometry (or the bound the light frame fits) changes; unique across scenes.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// How many probes [`SceneGpu::mesh_bounce`] and [`SceneGpu::mesh_bounce_or_bake`] have baked (the answers
    /// they did not find kept).
    pub fn probe_bakes(&self) -> usize {
        self.probes.bakes()
    }

    /// Whether a probe asked for by [`SceneGpu::mesh_bounce_or_bake`] is being baked.
    pub fn probe_pending(&self) -> bool {
        self.probes.pending()
    }

    pub fn bounds(&self) -> &SceneBounds {
        &self.bounds
    }

    /// Under `fit`, the box the hair maps' light frame is fitted to and the box the light is placed around
    /// (the one place the policy is applied; [`crate::render::Renderer::hair_light_frame`] reads it). Under
    /// [`LightFit::Stable`] the frame is fitted to the first box's bounding sphere
    /// ([`crate::scene::light_frame::LightFrame::stable`]) and a spot light is placed around the second, which
    /// holds the meshes at rest, so that no pose moves it.
    pub fn light_fit(&self, fit: LightFit) -> (Aabb, Aabb) {
        match fit {
            LightFit::PerFrame => (self.bounds.strands, self.bounds.all),
            LightFit::Bound => {
                let hair = self.fit_bound.union(self.bounds.strands);
                (hair, hair.union(self.mesh_bounds))
            }
            LightFit::Stable => {
                let hair = self.fit_bound.union(self.bounds.strands);
                (hair, hair.union(self.mesh_rest_bounds))
            }
        }
    }

    /// What every light pass draws from the light (the light-depth pass, the exact reference, each method's
    /// passes), the strands drawn as `strands` says (`Auto` resolved before, as lines if not): the one list, so
    /// a new caster is added here once. The casters of a frame share one vertex stage (the light pipelines are
    /// built for it).
    pub fn casters(&self, strands: LightStrands) -> Result<[&dyn LightCaster; 1], GpuError> {
        Ok(match strands {
            LightStrands::Auto | LightStrands::Lines => [&self.lines],
            LightStrands::Ribbons => [self.ribbons.as_ref().map_err(too_large)?],
        })
    }

    /// Segments of the strands.
    pub fn segment_count(&self) -> usize {
        self.hair_index_count as usize / 2
    }

    /// The bind group of [`crate::render::geometry::RIBBON_GROUP`] over the strand buffers, or the error
    /// saying which buffer exceeds the storage binding limit. A technique that draws ribbons checks it before
    /// recording.
    pub fn ribbons(&self) -> Result<&wgpu::BindGroup, GpuError> {
        self.ribbons.as_ref().map(|r| &r.points).map_err(too_large)
    }

    /// Vertices of a ribbon draw of every segment: [`RIBBON_VERTICES_PER_SEGMENT`] per segment.
    pub fn ribbon_vertex_count(&self) -> u32 {
        self.hair_index_count / 2 * RIBBON_VERTICES_PER_SEGMENT
    }
}

/// The error of a strand buffer too large to bind as storage for ribbons.
fn too_large(&(what, bytes, limit): &(&'static str, u64, u64)) -> GpuError {
    GpuError::TooLarge {
        what: format!("the {what} bound as storage for ribbons"),
        bytes,
        limit,
    }
}

/// A mesh triangle for the bounce probe, with the vertices it was built from (so posing can move it).
#[derive(Clone, Copy, Debug)]
struct BounceTriangle {
    corners: [u32; 3],
    triangle: Triangle,
}

impl BounceTriangle {
    fn pose(&mut self, vertices: &[MeshVertex]) {
        let p = |k: usize| Vec3::from(vertices[self.corners[k] as usize].position);
        let a = p(0);
        (self.triangle.p0, self.triangle.e1, self.triangle.e2) = (a, p(1) - a, p(2) - a);
    }
}

/// The triangles of the meshes `vertices`/`indices` (one index triple a triangle) for the bounce probe.
fn bounce_triangles(vertices: &[MeshVertex], indices: &[u32]) -> Vec<BounceTriangle> {
    indices
        .chunks_exact(3)
        .filter(|c| c.iter().all(|&i| (i as usize) < vertices.len()))
        .map(|c| {
            let mut t = BounceTriangle {
                corners: [c[0], c[1], c[2]],
                triangle: Triangle {
                    p0: Vec3::ZERO,
                    e1: Vec3::ZERO,
                    e2: Vec3::ZERO,
                    albedo: Vec3::from(vertices[c[0] as usize].color),
                },
            };
            t.pose(vertices);
            t
        })
        .collect()
}

impl SceneGpu {
    /// The probe of the light the lit meshes send to the hair (`shading::mesh_bounce`) under the light of `u`, as the eye
    /// passes light a point (`light_dir`, `light_radiance` of `shaders/common/frame.wgsl`), through the hair of
    /// `u.hair_color` with the strands' widths (`HairDensity`), or under [`mesh_bounce::Probe::Traced`] the path
    /// tracer's gather at the same points (`pathtrace::probe`, through the fibres of those widths and the
    /// meshes); kept per pose ([`probe_cache::PROBE_CACHE`] of them), so a motion bakes each frame once. Baked here when not
    /// kept.
    pub fn mesh_bounce(
        &self,
        u: &crate::render::uniforms::FrameUniforms,
        probe: mesh_bounce::Probe,
    ) -> mesh_bounce::Grid<ProbeLight> {
        let key = self.probe_key(u, probe);
        self.probes
            .get(&key)
            .unwrap_or_else(|| self.probes.bake_now(self.probe_bake(key, u)))
    }

    /// [`SceneGpu::mesh_bounce`] if kept; else the probe bakes on another thread ([`SceneGpu::probe_pending`]
    /// until it is kept) and the answer holds the probe of that kind used last, to draw with meanwhile.
    pub fn mesh_bounce_or_bake(
        &self,
        u: &crate::render::uniforms::FrameUniforms,
        probe: mesh_bounce::Probe,
    ) -> probe_cache::Answer {
        let key = self.probe_key(u, probe);
        self.probes.get_or_bake_later(&key, || self.probe_bake(key, u))
    }

    fn probe_key(&self, u: &crate::render::uniforms::FrameUniforms, probe: mesh_bounce::Probe) -> ProbeKey {
        let pose = self.probes.pose(self.generation, || {
            pose_digest(&self.vertices, &self.bounce_triangles)
        });
        probe_cache::key(pose, u, probe)
    }

    fn probe_bake(&self, key: ProbeKey, u: &crate::render::uniforms::FrameUniforms) -> Bake {
        Bake {
            key,
            uniforms: *u,
            points: self.vertices.iter().map(|v| Vec3::from(v.position)).collect(),
            thickness: self.vertices.iter().map(|v| v.thickness).collect(),
            ranges: self.ranges.clone(),
            triangles: self.bounce_triangles.iter().map(|t| t.triangle).collect(),
        }
    }
}
