//! Recording the eye passes a technique writes in one shape: a geometry pass over the strands as lines
//! ([`record_lines`], and its storage-only form [`record_line_count`]) and the resolve onto the frame's output
//! ([`Resolve`]: the group-0 declaration, the full-screen pass per output format, timed as `eye: resolve`).

use super::bindings::{self, Binding};
use crate::gpu::timing::Phase;
use crate::render::passes::composite::CompositePass;
use crate::render::transparency::EyeFrame;

/// A geometry pass over the strands as lines, as a technique records it: group 0 the frame's, group 1 `group`.
pub struct LinePass<'a> {
    pub label: &'a str,
    /// The timer entry (phase eye hair).
    pub timer: &'a str,
    pub pipeline: &'a wgpu::RenderPipeline,
    pub group: Option<&'a wgpu::BindGroup>,
    /// The colour attachments (cleared or loaded as each says).
    pub attachments: &'a [Option<wgpu::RenderPassColorAttachment<'a>>],
    /// Whether the meshes' depth is attached, for a pipeline of [`super::pipelines::DepthTest::Meshes`];
    /// otherwise the entry tests it by hand.
    pub mesh_depth: bool,
}

/// Records `pass` over every strand segment; the pass is begun (its clears done) even without strands.
pub fn record_lines(frame: &mut EyeFrame<'_>, pass: LinePass<'_>) {
    let timestamps = frame
        .timer
        .as_mut()
        .and_then(|t| t.pass(Phase::EyeHair, pass.timer));
    let depth_view = &frame.targets.depth_view;
    let mut render = frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(pass.label),
        color_attachments: pass.attachments,
        depth_stencil_attachment: pass.mesh_depth.then_some(wgpu::RenderPassDepthStencilAttachment {
            view: depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    let geometry = frame.geometry;
    if geometry.hair_index_count == 0 {
        return;
    }
    render.set_pipeline(pass.pipeline);
    render.set_bind_group(0, frame.frame_bind_group, &[]);
    if let Some(group) = pass.group {
        render.set_bind_group(1, group, &[]);
    }
    render.set_vertex_buffer(0, geometry.hair_vertices.slice(..));
    render.set_index_buffer(geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
    render.draw_indexed(0..geometry.hair_index_count, 0, 0..1);
}

/// Records a storage-only pass over the strands as lines (the count passes' shape): into the never-written null
/// target, the meshes tested by hand, group 1 `group`.
pub fn record_line_count(
    frame: &mut EyeFrame<'_>,
    label: &str,
    timer: &str,
    pipeline: &wgpu::RenderPipeline,
    group: &wgpu::BindGroup,
) {
    let null = [frame.targets.null_attachment()];
    record_lines(
        frame,
        LinePass {
            label,
            timer,
            pipeline,
            group: Some(group),
            attachments: &null,
            mesh_depth: false,
        },
    );
}

/// A technique's resolve: the layout of its group 0 declared as a list of [`Binding`]s, and the full-screen pass
/// of its WGSL over it ([`CompositePass`]: one pipeline per output format), blended onto the frame's output.
pub struct Resolve {
    group_label: String,
    layout: wgpu::BindGroupLayout,
    pass: CompositePass,
}

impl Resolve {
    /// The resolve `hairlab.<technique>.resolve` running `wgsl` over group 0 declared as `group`, blended with
    /// `blend`.
    pub fn new(
        device: &wgpu::Device,
        technique: &str,
        wgsl: &str,
        group: &[Binding],
        blend: wgpu::BlendState,
    ) -> Resolve {
        let label = format!("hairlab.{technique}.resolve");
        let layout = bindings::layout(device, &format!("{label}_layout"), group);
        Resolve {
            pass: CompositePass::new(device, &label, wgsl, &layout, blend),
            group_label: format!("{label}_group"),
            layout,
        }
    }

    /// A resolve reading `count` textures (group 0 of `count` [`Binding::Texture`]s).
    pub fn of_textures(
        device: &wgpu::Device,
        technique: &str,
        wgsl: &str,
        count: usize,
        blend: wgpu::BlendState,
    ) -> Resolve {
        Resolve::new(device, technique, wgsl, &vec![Binding::Texture; count], blend)
    }

    /// Records the resolve over `resources` (group 0, in declared order) onto the frame's output, timed as
    /// `eye: resolve`.
    pub fn record(&self, frame: &mut EyeFrame<'_>, resources: &[wgpu::BindingResource<'_>]) {
        let group = bindings::group(&frame.gpu.device, &self.group_label, &self.layout, resources);
        let timestamps = frame
            .timer
            .as_mut()
            .and_then(|t| t.pass(Phase::Resolve, "eye: resolve"));
        self.pass
            .record(&mut frame.encoder, frame.output, &group, timestamps);
    }

    /// [`Resolve::record`] over `views`, for a resolve [`of_textures`](Resolve::of_textures).
    pub fn record_textures(&self, frame: &mut EyeFrame<'_>, views: &[&wgpu::TextureView]) {
        let resources: Vec<_> = views
            .iter()
            .map(|v| wgpu::BindingResource::TextureView(v))
            .collect();
        self.record(frame, &resources);
    }
}
