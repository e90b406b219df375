//! Scene geometry on the GPU: strands as a LineList (one index pair per segment) and opaque meshes, with buffers
//! sized from the scene and checked against the device's limits. The strand vertex and index buffers are also
//! storage buffers, bound at [`RIBBON_GROUP`] for the camera-facing ribbons (spec B.6) that pull a segment's
//! points from them (`eye_ribbon_point` in `shaders/common/eye_vertex.wgsl`).

use crate::gpu::{Gpu, GpuError};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// One strand point as the hair passes read it (`VertexIn` in `shaders/hair.wgsl`, and `HairPoint` in
/// `shaders/common/eye_vertex.wgsl` as the ribbons pull it from storage; a test checks both layouts).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct HairVertex {
    pub position: [f32; 3],
    pub alpha: f32,
    pub tangent: [f32; 3],
    pub thickness: f32,
    /// rgb, a = 1 when the strand has its own colour.
    pub color: [f32; 4],
}

impl HairVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 5] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32, 4 => Float32x4];
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<HairVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// [`HairVertex`]'s field names and byte offsets, in declaration order, for the layout test against
/// `HairPoint` in `shaders/common/eye_vertex.wgsl`.
pub const HAIR_VERTEX_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("position", offset_of!(HairVertex, position)),
        ("alpha", offset_of!(HairVertex, alpha)),
        ("tangent", offset_of!(HairVertex, tangent)),
        ("thickness", offset_of!(HairVertex, thickness)),
        ("color", offset_of!(HairVertex, color)),
    ]
};

/// The bind group index of the ribbon storage buffers in every ribbon pipeline (groups 0–2 are the scene, the
/// shadow method and the technique's own in the hair pass).
pub const RIBBON_GROUP: u32 = 3;

/// Vertices a ribbon draw takes per strand segment: two triangles.
pub const RIBBON_VERTICES_PER_SEGMENT: u32 = 6;

/// The layout of [`RIBBON_GROUP`]: the strand points (binding 0, `array<HairPoint>`) and the segment index
/// pairs (binding 1, `array<u32>`), read-only in the vertex stage. The renderer creates it once; every
/// [`GeometryBuffers`] binds its buffers with it.
pub fn ribbon_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hairlab.geometry.ribbon_layout"),
        entries: &[entry(0), entry(1)],
    })
}

/// One mesh vertex (`VertexIn` in `shaders/mesh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct MeshVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub color: [f32; 3],
}

impl MeshVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3];
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// Builds the per-point vertices of every strand: tangents by central differences along each strand.
pub fn hair_vertices(scene: &Scene) -> Vec<HairVertex> {
    let s = &scene.strands;
    let mut out = Vec::with_capacity(s.points.len());
    for (start, n) in s.ranges() {
        let pts = &s.points[start..start + n];
        for i in 0..n {
            let a = pts[i.saturating_sub(1)];
            let b = pts[(i + 1).min(n - 1)];
            let tangent = (b - a).try_normalize().unwrap_or(Vec3::Y);
            let k = start + i;
            let (color, has_color) = match &s.color {
                Some(c) => (c[k], 1.0),
                None => (Vec3::ONE, 0.0),
            };
            out.push(HairVertex {
                position: pts[i].into(),
                alpha: s.alpha.as_ref().map_or(1.0, |a| a[k]),
                tangent: tangent.into(),
                thickness: s.thickness.as_ref().map_or(1.0, |t| t[k]),
                color: [color.x, color.y, color.z, has_color],
            });
        }
    }
    out
}

/// LineList indices: one pair per segment.
pub fn hair_indices(scene: &Scene) -> Vec<u32> {
    let mut out = Vec::with_capacity(scene.strands.segment_count() * 2);
    for (start, n) in scene.strands.ranges() {
        for i in 1..n {
            out.push((start + i - 1) as u32);
            out.push((start + i) as u32);
        }
    }
    out
}

/// The scene's vertex and index buffers.
pub struct GeometryBuffers {
    /// Per strand point; vertex and storage usage.
    pub hair_vertices: wgpu::Buffer,
    /// One index pair per segment; index and storage usage.
    pub hair_indices: wgpu::Buffer,
    pub hair_index_count: u32,
    /// The layout of [`RIBBON_GROUP`] ([`ribbon_layout`], the renderer's).
    pub ribbon_layout: wgpu::BindGroupLayout,
    /// The two strand buffers bound with `ribbon_layout`, or the buffer that exceeds the storage binding limit
    /// (name, bytes, limit).
    ribbon_group: Result<wgpu::BindGroup, (&'static str, u64, u64)>,
    pub mesh_vertices: wgpu::Buffer,
    pub mesh_indices: wgpu::Buffer,
    pub mesh_index_count: u32,
    /// Bytes of GPU memory these buffers hold.
    pub bytes: u64,
}

impl GeometryBuffers {
    /// Uploads `scene`'s strands and meshes; `ribbon_layout` is the renderer's [`ribbon_layout`].
    pub fn upload(
        gpu: &Gpu,
        scene: &Scene,
        ribbon_layout: &wgpu::BindGroupLayout,
    ) -> Result<GeometryBuffers, GpuError> {
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
        for m in &scene.meshes {
            let base = mv.len() as u32;
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
        let v = wgpu::BufferUsages::VERTEX;
        let i = wgpu::BufferUsages::INDEX;
        let s = wgpu::BufferUsages::STORAGE;
        let hair_vertices = buf("hairlab.geometry.hair_vertices", bytemuck::cast_slice(&hv), v | s);
        let hair_indices = buf("hairlab.geometry.hair_indices", bytemuck::cast_slice(&hi), i | s);
        let binding_limit = gpu.device.limits().max_storage_buffer_binding_size;
        let ribbon_group = match sizes[..2].iter().find(|(_, b)| *b as u64 > binding_limit) {
            Some(&(what, bytes)) => Err((what, bytes as u64, binding_limit)),
            None => Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hairlab.geometry.ribbon_group"),
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
        Ok(GeometryBuffers {
            hair_vertices,
            hair_indices,
            hair_index_count: hi.len() as u32,
            ribbon_layout: ribbon_layout.clone(),
            ribbon_group,
            mesh_vertices: buf("hairlab.geometry.mesh_vertices", bytemuck::cast_slice(&mv), v),
            mesh_indices: buf("hairlab.geometry.mesh_indices", bytemuck::cast_slice(&mi), i),
            mesh_index_count: mi.len() as u32,
            bytes: sizes.iter().map(|(_, b)| *b as u64).sum(),
        })
    }
}

impl GeometryBuffers {
    /// The bind group of [`RIBBON_GROUP`] over the strand buffers, or the error saying which buffer exceeds the
    /// storage binding limit. A technique that draws ribbons checks it before recording.
    pub fn ribbons(&self) -> Result<&wgpu::BindGroup, GpuError> {
        self.ribbon_group
            .as_ref()
            .map_err(|&(what, bytes, limit)| GpuError::TooLarge {
                what: format!("the {what} bound as storage for ribbons"),
                bytes,
                limit,
            })
    }

    /// Vertices of a ribbon draw of every segment: [`RIBBON_VERTICES_PER_SEGMENT`] per segment.
    pub fn ribbon_vertex_count(&self) -> u32 {
        self.hair_index_count / 2 * RIBBON_VERTICES_PER_SEGMENT
    }
}

impl crate::render::caster::LightCaster for GeometryBuffers {
    fn label(&self) -> &'static str {
        "strands"
    }

    fn is_empty(&self) -> bool {
        self.hair_index_count == 0
    }

    /// Every strand segment as a line (LineList, one index pair per segment).
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>) {
        pass.set_vertex_buffer(0, self.hair_vertices.slice(..));
        pass.set_index_buffer(self.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.hair_index_count, 0, instances);
    }
}
