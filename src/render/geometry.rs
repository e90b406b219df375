//! Scene geometry on the GPU: strands as a LineList (one index pair per segment) and opaque meshes, with buffers
//! sized from the scene and checked against the device's limits.

use crate::gpu::{Gpu, GpuError};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// One strand point as the hair passes read it (`VertexIn` in `shaders/hair.wgsl`).
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
    pub hair_vertices: wgpu::Buffer,
    pub hair_indices: wgpu::Buffer,
    pub hair_index_count: u32,
    pub mesh_vertices: wgpu::Buffer,
    pub mesh_indices: wgpu::Buffer,
    pub mesh_index_count: u32,
    /// Bytes of GPU memory these buffers hold.
    pub bytes: u64,
}

impl GeometryBuffers {
    pub fn upload(gpu: &Gpu, scene: &Scene) -> Result<GeometryBuffers, GpuError> {
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
            // Empty buffers are legal but a zero-sized binding is not: keep at least 16 bytes.
            let padded;
            let contents = if contents.is_empty() {
                padded = [0u8; 16];
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
        Ok(GeometryBuffers {
            hair_vertices: buf("hairlab.geometry.hair_vertices", bytemuck::cast_slice(&hv), v),
            hair_indices: buf("hairlab.geometry.hair_indices", bytemuck::cast_slice(&hi), i),
            hair_index_count: hi.len() as u32,
            mesh_vertices: buf("hairlab.geometry.mesh_vertices", bytemuck::cast_slice(&mv), v),
            mesh_indices: buf("hairlab.geometry.mesh_indices", bytemuck::cast_slice(&mi), i),
            mesh_index_count: mi.len() as u32,
            bytes: sizes.iter().map(|(_, b)| *b as u64).sum(),
        })
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
