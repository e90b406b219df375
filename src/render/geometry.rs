//! The vertex formats of the scene's GPU buffers ([`crate::render::scene_gpu::SceneGpu`] holds them): strand
//! points and mesh vertices, the LineList indices (one index pair per segment), and the layout of
//! [`RIBBON_GROUP`], where the strand buffers are bound as storage for the camera-facing ribbons (spec B.6) that
//! pull a segment's points from them (`eye_ribbon_point` in `shaders/common/eye_vertex.wgsl`).

use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

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
    /// Height above the strand's root along its first segment ([`crate::fur::darkening::base_heights`]), the
    /// guard hairs' base darkening's input; the scene's as loaded (moving hair keeps its rest heights).
    pub base_height: f32,
    pub pad: [f32; 3],
}

impl HairVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32, 4 => Float32x4, 5 => Float32
    ];
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
        ("base_height", offset_of!(HairVertex, base_height)),
        ("pad", offset_of!(HairVertex, pad)),
    ]
};

/// The bind group index of the ribbon storage buffers in every ribbon pipeline (groups 0–2 are the scene, the
/// shadow method and the technique's own in the hair pass).
pub const RIBBON_GROUP: u32 = 3;

/// Vertices a ribbon draw takes per strand segment: two triangles.
pub const RIBBON_VERTICES_PER_SEGMENT: u32 = 6;

/// The layout of [`RIBBON_GROUP`]: the strand points (binding 0, `array<HairPoint>`) and the segment index
/// pairs (binding 1, `array<u32>`), read-only in the vertex stage. The renderer creates it once; every
/// [`crate::render::scene_gpu::SceneGpu`] binds its buffers with it.
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

/// Builds the per-point vertices of every strand: tangents by central differences along each strand
/// ([`write_tangents`]).
pub fn hair_vertices(scene: &Scene) -> Vec<HairVertex> {
    let s = &scene.strands;
    let mut out: Vec<HairVertex> = (0..s.points.len())
        .map(|k| {
            let (color, has_color) = match &s.color {
                Some(c) => (c[k], 1.0),
                None => (Vec3::ONE, 0.0),
            };
            HairVertex {
                position: s.points[k].into(),
                alpha: s.alpha.as_ref().map_or(1.0, |a| a[k]),
                tangent: [0.0; 3],
                thickness: s.thickness.as_ref().map_or(1.0, |t| t[k]),
                color: [color.x, color.y, color.z, has_color],
                base_height: 0.0,
                pad: [0.0; 3],
            }
        })
        .collect();
    for (start, n) in s.ranges() {
        let heights = crate::fur::darkening::base_heights(&s.points[start..start + n]);
        for (v, h) in out[start..start + n].iter_mut().zip(heights) {
            v.base_height = h;
        }
    }
    write_tangents(&mut out, s.ranges());
    out
}

/// Sets every vertex's tangent from the positions: the unit central difference along its strand (one-sided at
/// the ends, +Y where the points coincide). `ranges` are the strands' `(first point, point count)`.
pub fn write_tangents(vertices: &mut [HairVertex], ranges: impl IntoIterator<Item = (usize, usize)>) {
    for (start, n) in ranges {
        for i in 0..n {
            let a = Vec3::from(vertices[start + i.saturating_sub(1)].position);
            let b = Vec3::from(vertices[start + (i + 1).min(n - 1)].position);
            vertices[start + i].tangent = (b - a).try_normalize().unwrap_or(Vec3::Y).into();
        }
    }
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
