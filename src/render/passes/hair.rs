//! Eye pass for hair: strands as lines (LineList) through the shared eye vertex stage, or as camera-facing
//! ribbons (TriangleList, `vs_ribbon` pulling each segment's points from the storage buffers of
//! [`RIBBON_GROUP`], spec B.6) for an entry that asks for them, shaded with the shadow method's visibility,
//! into what the eye transparency technique's entry point writes (its colour targets, its storage).
//! Depth-tested against the meshes without writing, or against a technique's own depth target. One pipeline
//! per method, technique and entry point.

use crate::render::geometry::{HairVertex, RIBBON_GROUP};
use crate::render::method::{LightMethod, MethodGpu};
use crate::render::pipelines::{Pass, PipelineCache, PipelineKey};
use crate::render::scene_gpu::SceneGpu;
use crate::render::targets::EyeTargets;

pub struct HairPass {
    scene_layout: wgpu::BindGroupLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
}

/// What one hair draw reads besides the technique's [`HairDrawPass`].
pub struct HairScene<'a> {
    pub device: &'a wgpu::Device,
    pub method: &'a dyn LightMethod,
    pub method_gpu: &'a dyn MethodGpu,
    pub technique: HairTechnique,
    pub scene: &'a wgpu::BindGroup,
    pub geometry: &'a SceneGpu,
    pub targets: &'a EyeTargets,
}

/// The eye transparency technique whose entries a hair draw uses: its name (the pipelines' key) and its hair
/// file (pasted at `#include_technique`).
#[derive(Clone, Copy, Debug)]
pub struct HairTechnique {
    pub name: &'static str,
    pub hair_wgsl: &'static str,
}

/// One fragment entry point of the hair pass and what it writes.
#[derive(Debug)]
pub struct HairEntry {
    pub entry: &'static str,
    pub targets: &'static [wgpu::ColorTargetState],
    pub depth: EntryDepth,
    /// What the entry's pipeline draws the strands as.
    pub geometry: HairGeometry,
}

/// The primitives of a hair entry's pipeline. Either way the fragment entry receives the same `VertexOut`
/// (`shaders/hair.wgsl`) with the same segment ids, so `shade_hair` and every entry work unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HairGeometry {
    /// Strands as lines (LineList, `vs_main`, one index pair per segment): what the hair methods compare.
    Lines,
    /// Camera-facing ribbons (spec B.6, `vs_ribbon`): two triangles per segment pulled from the storage
    /// buffers of [`RIBBON_GROUP`], widened to one pixel with alpha scaled by the
    /// covered fraction when thinner (`eye_ribbon_point` in `common/eye_vertex.wgsl`).
    Ribbons,
}

/// How a hair entry is depth-tested.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryDepth {
    /// `Less` against the meshes' depth, not written (the shared hair state).
    Meshes,
    /// `Less` against the technique's own depth target, written.
    Own,
    /// No depth attachment: the entry tests the meshes' depth by hand (`common/mesh_depth.wgsl`) before its
    /// storage writes, which a fixed-function test after the shader would not undo.
    Manual,
}

/// A shaded hair pass as a technique asks for it.
pub struct HairDrawPass<'a> {
    pub entry: &'static HairEntry,
    pub attachments: &'a [Option<wgpu::RenderPassColorAttachment<'a>>],
    /// The technique's own depth target (entries with [`EntryDepth::Own`]), cleared to `clear` or loaded.
    pub depth: Option<(&'a wgpu::TextureView, Option<f32>)>,
    /// Group 2 of the hair pass: the technique's own resources.
    pub group: Option<(&'a wgpu::BindGroupLayout, &'a wgpu::BindGroup)>,
    /// Rows `[y0, y1)` only (a scissor rect), for techniques that render in bands.
    pub rows: Option<(u32, u32)>,
}

impl HairPass {
    /// Pipelines this pass has built ([`PipelineCache::built`]).
    pub fn pipelines_built(&self) -> u64 {
        self.pipelines.built()
    }

    pub fn new(scene_layout: &wgpu::BindGroupLayout) -> Self {
        Self {
            scene_layout: scene_layout.clone(),
            pipelines: PipelineCache::default(),
        }
    }

    /// Drops `technique`'s pipelines: its GPU state (and group-2 layout) was re-created.
    pub fn forget_technique(&mut self, technique: &str) {
        self.pipelines.forget_technique(technique);
    }

    fn pipeline(&mut self, s: &HairScene, draw: &HairDrawPass) -> &wgpu::RenderPipeline {
        let scene_layout = &self.scene_layout;
        let ribbons = draw.entry.geometry == HairGeometry::Ribbons;
        let key = PipelineKey {
            pass: if ribbons { Pass::HairRibbons } else { Pass::Hair },
            method: s.method.name(),
            technique: Some((s.technique.name, draw.entry.entry)),
        };
        self.pipelines.get_or_build(key, |key| {
            let mut layouts = vec![Some(scene_layout), Some(s.method_gpu.bind_group_layout())];
            if let Some((layout, _)) = draw.group {
                layouts.push(Some(layout));
            }
            if ribbons {
                layouts.resize(RIBBON_GROUP as usize, None);
                layouts.push(Some(&s.geometry.ribbon_layout));
            }
            let layout = s.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&key.label("layout")),
                bind_group_layouts: &layouts,
                immediate_size: 0,
            });
            let src = crate::shaders::compose_with(
                "hair.wgsl",
                Some(s.method.lookup_wgsl()),
                Some(s.technique.hair_wgsl),
            )
            // As `passes::shader_module`: only a shader failing naga validation panics, which
            // `tests/shaders.rs` rules out for every method × technique.
            .unwrap_or_else(|e| panic!("{e}"));
            let module = s.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&key.label("shader")),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            let targets: Vec<_> = draw.entry.targets.iter().cloned().map(Some).collect();
            let lines = [Some(HairVertex::layout())];
            let (entry_point, buffers, topology) = if ribbons {
                ("vs_ribbon", &[][..], wgpu::PrimitiveTopology::TriangleList)
            } else {
                ("vs_main", &lines[..], wgpu::PrimitiveTopology::LineList)
            };
            s.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&key.label("pipeline")),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(entry_point),
                    compilation_options: Default::default(),
                    buffers,
                },
                // Ribbons face the camera but their winding follows the strand: no culling.
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: (draw.entry.depth != EntryDepth::Manual).then(|| wgpu::DepthStencilState {
                    format: EyeTargets::DEPTH,
                    depth_write_enabled: Some(draw.entry.depth == EntryDepth::Own),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(draw.entry.entry),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    pub fn record(
        &mut self,
        s: &HairScene,
        encoder: &mut wgpu::CommandEncoder,
        draw: HairDrawPass,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let pipeline = self.pipeline(s, &draw);
        let depth_view = draw.depth.map_or(&s.targets.depth_view, |(v, _)| v);
        let load = match draw.depth {
            Some((_, Some(clear))) => wgpu::LoadOp::Clear(clear),
            _ => wgpu::LoadOp::Load,
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.hair.pass"),
            color_attachments: draw.attachments,
            depth_stencil_attachment: (draw.entry.depth != EntryDepth::Manual).then_some(
                wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                },
            ),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if s.geometry.hair_index_count == 0 {
            return;
        }
        if let Some((y0, y1)) = draw.rows {
            if y1 <= y0 {
                return;
            }
            pass.set_scissor_rect(0, y0, s.targets.width, y1 - y0);
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, s.scene, &[]);
        pass.set_bind_group(1, s.method_gpu.bind_group(), &[]);
        if let Some((_, group)) = draw.group {
            pass.set_bind_group(2, group, &[]);
        }
        match draw.entry.geometry {
            HairGeometry::Lines => {
                pass.set_vertex_buffer(0, s.geometry.hair_vertices.slice(..));
                pass.set_index_buffer(s.geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..s.geometry.hair_index_count, 0, 0..1);
            }
            HairGeometry::Ribbons => match s.geometry.ribbons() {
                Ok(group) => {
                    pass.set_bind_group(RIBBON_GROUP, group, &[]);
                    pass.draw(0..s.geometry.ribbon_vertex_count(), 0..1);
                }
                // A technique drawing ribbons reports this from `SceneGpu::ribbons` before recording.
                Err(e) => log::error!("hair ribbons not drawn: {e}"),
            },
        }
    }
}
