//! The strands as lines from the light: one LineList index pair per segment, the points read from the strand
//! vertex buffer (`shaders/casters/lines.wgsl`). What the seed papers draw.

use super::stage::{CasterStage, LightCaster};
use crate::render::geometry::HairVertex;

pub const LINES: CasterStage = CasterStage {
    wgsl: "casters/lines.wgsl",
    topology: wgpu::PrimitiveTopology::LineList,
    vertex_buffer: Some(HairVertex::layout),
    binds_points: false,
};

/// The scene's strand buffers drawn as lines.
pub struct StrandLines {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

impl LightCaster for StrandLines {
    fn stage(&self) -> &'static CasterStage {
        &LINES
    }

    fn is_empty(&self) -> bool {
        self.index_count == 0
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, instances);
    }
}
