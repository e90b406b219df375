//! The contract between casters and light passes: a caster's vertex stage ([`CasterStage`], what a light
//! pipeline is specialised by), the geometry a pass draws ([`LightCaster`]), and the light pipelines built for a
//! frame's stage ([`LightStage`]). The casters and the passes both use it; which caster draws a setting is the
//! caster module's.

use crate::render::geometry::RIBBON_GROUP;
use std::ops::Range;

/// How a caster's vertices are made: what a light pipeline is specialised by.
#[derive(Debug)]
pub struct CasterStage {
    /// The caster's vertex stage (`casters/<name>.wgsl`), defining `LightVertexIn` and `light_vertex`.
    pub wgsl: &'static str,
    pub topology: wgpu::PrimitiveTopology,
    /// The vertex buffer it reads at slot 0, if any.
    pub vertex_buffer: Option<fn() -> wgpu::VertexBufferLayout<'static>>,
    /// Whether it pulls the strand points from [`RIBBON_GROUP`].
    pub binds_points: bool,
}

/// Geometry a light pass draws.
pub trait LightCaster: Sync {
    /// The vertex stage its pipelines are built for.
    fn stage(&self) -> &'static CasterStage;
    /// Whether there is anything to draw.
    fn is_empty(&self) -> bool;
    /// Binds the caster's own buffers and bind groups and draws it (`instances`: what the pass's shader reads
    /// as its instance index, e.g. which slices an Opacity Shadow Maps pass writes).
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, instances: Range<u32>);
}

/// The vertex stage the light pipelines of a frame are built for, and the layout its points are bound with.
#[derive(Clone, Debug)]
pub struct LightStage {
    pub caster: &'static CasterStage,
    /// The renderer's [`crate::render::geometry::ribbon_layout`].
    pub ribbon_layout: wgpu::BindGroupLayout,
}

impl LightStage {
    /// The light pass `path` composed with the caster's vertex stage.
    pub fn module(&self, device: &wgpu::Device, label: &str, path: &str) -> wgpu::ShaderModule {
        // Every light pass composes with every caster (the `every_light_pass_validates_with_every_caster` test).
        let src = crate::shaders::compose_light(path, self.caster.wgsl).unwrap_or_else(|e| panic!("{e}"));
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        })
    }

    /// A light pipeline over bind groups `groups` (group 0 the frame uniforms; the caster's own group is added
    /// at [`RIBBON_GROUP`]): `module`'s `vs_main`, no depth test, fragment entry `fragment_entry` writing
    /// `targets`.
    pub fn pipeline(
        &self,
        device: &wgpu::Device,
        label: &str,
        groups: &[&wgpu::BindGroupLayout],
        module: &wgpu::ShaderModule,
        fragment_entry: &str,
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> wgpu::RenderPipeline {
        self.pipeline_with_constants(device, label, groups, module, (fragment_entry, &[]), targets)
    }

    /// [`LightStage::pipeline`] with the fragment stage's pipeline-overridable constants set: `fragment` is the
    /// entry and its `(name, value)` constants.
    pub fn pipeline_with_constants(
        &self,
        device: &wgpu::Device,
        label: &str,
        groups: &[&wgpu::BindGroupLayout],
        module: &wgpu::ShaderModule,
        (fragment_entry, constants): (&str, &[(&str, f64)]),
        targets: &[Option<wgpu::ColorTargetState>],
    ) -> wgpu::RenderPipeline {
        let mut layouts: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
        if self.caster.binds_points {
            layouts.resize(RIBBON_GROUP as usize, None);
            layouts.push(Some(&self.ribbon_layout));
        }
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&format!("{label}.layout")),
            bind_group_layouts: &layouts,
            immediate_size: 0,
        });
        let buffers: Vec<Option<wgpu::VertexBufferLayout>> =
            self.caster.vertex_buffer.iter().map(|b| Some(b())).collect();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: self.caster.topology,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fragment_entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
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
