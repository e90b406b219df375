//! Light casters: the geometry every light pass (the shared light-depth pass, the exact reference, each
//! method's own passes) draws from the light. A caster feeds the shared light vertex stage
//! (`shaders/common/light_vertex.wgsl`) through its own vertex stage (`shaders/casters/<name>.wgsl`, pasted at
//! `#include_caster`), whose light-fragment contract (normalised light depth, alpha, segment id) is the
//! interface between casters and methods, so a method never knows what it shadows. Light pipelines are built
//! for a caster's [`CasterStage`] (the stage is the key, as in a specialised pipeline: the base descriptor of
//! [`LightStage::pipeline`] adjusted by the stage's topology, vertex buffers and bind groups).
//!
//! The strands are drawn from the light by one of [`LightStrands`]: as lines ([`lines`]) or as light-facing
//! ribbons with a minimum width of one texel and a coverage alpha ([`ribbons`], the anti-aliasing engines apply
//! in the shadow view). Every light pass and the reference draw the same casters, so the reference stays exact
//! for what the methods see.
//!
//! How the strand lines become light texels is [`Raster`]: the GPU's line rasteriser, or the compute rasteriser
//! ([`compute`]) whose fragment stream (under the written coverage rule of [`raster_model`]) is drawn as points.

pub mod compute;
pub mod lines;
pub mod raster_model;
pub mod ribbons;

use crate::render::geometry::RIBBON_GROUP;
use serde::{Deserialize, Serialize};
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

/// How the strands are drawn from the light (`render.light_strands`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LightStrands {
    /// One line per segment ([`lines::LINES`]): a strand thinner than a texel covers a texel or not as the
    /// rasteriser's line rule decides.
    #[default]
    Lines,
    /// Light-facing ribbons at least one texel wide, alpha scaled by the covered fraction ([`ribbons::RIBBONS`]).
    Ribbons,
}

impl LightStrands {
    pub const ALL: [LightStrands; 2] = [LightStrands::Lines, LightStrands::Ribbons];

    pub fn stage(self) -> &'static CasterStage {
        match self {
            LightStrands::Lines => &lines::LINES,
            LightStrands::Ribbons => &ribbons::RIBBONS,
        }
    }

    /// The setting's word.
    pub fn word(self) -> &'static str {
        match self {
            LightStrands::Lines => "lines",
            LightStrands::Ribbons => "ribbons",
        }
    }
}

/// How the strand lines become light texels (`render.raster`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Raster {
    /// The GPU's line rasteriser ([`lines::LINES`], or the ribbons' triangles).
    #[default]
    Hardware,
    /// The compute rasteriser ([`compute::COMPUTE`]): lines only, under the coverage rule of [`raster_model`].
    Compute,
}

impl Raster {
    pub const ALL: [Raster; 2] = [Raster::Hardware, Raster::Compute];

    /// The setting's word.
    pub fn word(self) -> &'static str {
        match self {
            Raster::Hardware => "hardware",
            Raster::Compute => "compute",
        }
    }

    /// The vertex stage of the strands drawn as `strands` by this rasteriser, or the error naming the keys when
    /// the combination is not drawn (the compute rasteriser lines strands only).
    pub fn stage(self, strands: LightStrands) -> Result<&'static CasterStage, String> {
        match (self, strands) {
            (Raster::Hardware, s) => Ok(s.stage()),
            (Raster::Compute, LightStrands::Lines) => Ok(&compute::COMPUTE),
            (Raster::Compute, s) => Err(format!(
                "render.raster = compute rasterises the strands as lines; render.light_strands = {} needs \
                 render.raster = hardware",
                s.word()
            )),
        }
    }
}

/// Every caster's vertex stage (what the shader tests compose every light pass with).
pub const ALL_STAGES: [&CasterStage; 3] = [&lines::LINES, &ribbons::RIBBONS, &compute::COMPUTE];

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
