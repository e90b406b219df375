//! The strands as light-facing ribbons: two triangles per segment pulled from the strand buffers bound at
//! [`RIBBON_GROUP`], at least one light texel wide, alpha scaled by the covered fraction
//! (`shaders/casters/ribbons.wgsl`). The light-space twin of the eye's camera-facing ribbons (Andersen et al.
//! 2016) and the strand anti-aliasing of Unreal's groom renderer in its shadow views (a minimum strand width
//! that grows with distance, opacity times coverage): a strand no longer covers a texel or misses it as it
//! moves by a fraction of a texel, which is what flickers under motion.

use super::stage::{CasterStage, LightCaster};
use crate::render::geometry::{RIBBON_GROUP, RIBBON_VERTICES_PER_SEGMENT};

pub const RIBBONS: CasterStage = CasterStage {
    wgsl: "casters/ribbons.wgsl",
    topology: wgpu::PrimitiveTopology::TriangleList,
    vertex_buffer: None,
    binds_points: true,
};

/// The scene's strand buffers drawn as ribbons.
pub struct StrandRibbons {
    /// The strand points and segments bound with the renderer's ribbon layout.
    pub points: wgpu::BindGroup,
    pub segment_count: u32,
}

impl LightCaster for StrandRibbons {
    fn stage(&self) -> &'static CasterStage {
        &RIBBONS
    }

    fn is_empty(&self) -> bool {
        self.segment_count == 0
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>) {
        pass.set_bind_group(RIBBON_GROUP, &self.points, &[]);
        pass.draw(0..self.segment_count * RIBBON_VERTICES_PER_SEGMENT, instances);
    }
}
