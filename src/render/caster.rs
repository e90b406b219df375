//! Light casters: the geometry every light pass (the shared light-depth pass, the exact reference, each
//! method's own passes) draws from the light. A caster feeds the shared light vertex stage
//! (`shaders/common/light_vertex.wgsl`), whose light-fragment contract (normalised light depth, alpha, segment
//! id) is the interface between casters and methods, so a method never knows what it shadows. Today's caster is
//! the strands as line segments ([`crate::render::scene_gpu::SceneGpu`]); a caster of another primitive
//! (fur shells, ribbons) brings its own vertex stage honouring the same contract.

use std::ops::Range;

/// Geometry a light pass draws.
pub trait LightCaster: Sync {
    /// For labels and error messages.
    fn label(&self) -> &'static str;
    /// Whether there is anything to draw.
    fn is_empty(&self) -> bool;
    /// Binds the caster's vertex and index buffers and draws it (`instances`: what the pass's shader reads as
    /// its instance index, e.g. which slices an Opacity Shadow Maps pass writes).
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: Range<u32>);
}

/// Draws every caster with `pipeline`: group 0 the frame uniforms, group 1 the pass's own resources.
pub fn draw_casters(
    pass: &mut wgpu::RenderPass<'_>,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    resources: Option<&wgpu::BindGroup>,
    casters: &[&dyn LightCaster],
    instances: Range<u32>,
) {
    if casters.iter().all(|c| c.is_empty()) {
        return;
    }
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, frame, &[]);
    if let Some(r) = resources {
        pass.set_bind_group(1, r, &[]);
    }
    for c in casters.iter().filter(|c| !c.is_empty()) {
        c.draw(pass, instances.clone());
    }
}
