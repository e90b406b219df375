//! Eye pass for hair: strands as lines (LineList), depth-tested against the meshes without writing depth, into
//! the weighted-blended OIT targets (accumulation: One/One; revealage: Zero/OneMinusSrc). One pipeline per method.

use crate::render::geometry::{GeometryBuffers, HairVertex};
use crate::render::method::{LightMethod, MethodGpu};
use crate::render::targets::EyeTargets;
use std::collections::HashMap;

pub struct HairPass {
    scene_layout: wgpu::BindGroupLayout,
    pipelines: HashMap<&'static str, wgpu::RenderPipeline>,
}

impl HairPass {
    pub fn new(scene_layout: &wgpu::BindGroupLayout) -> Self {
        Self {
            scene_layout: scene_layout.clone(),
            pipelines: HashMap::new(),
        }
    }

    fn pipeline(
        &mut self,
        device: &wgpu::Device,
        method: &dyn LightMethod,
        method_gpu: &dyn MethodGpu,
    ) -> &wgpu::RenderPipeline {
        let scene_layout = &self.scene_layout;
        self.pipelines.entry(method.name()).or_insert_with(|| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("hairlab.hair.layout"),
                bind_group_layouts: &[Some(scene_layout), Some(method_gpu.bind_group_layout())],
                immediate_size: 0,
            });
            let module = super::shader_module(
                device,
                "hairlab.hair.shader",
                "hair.wgsl",
                Some(method.lookup_wgsl()),
            );
            let additive = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            };
            let reveal = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::OneMinusSrc,
                operation: wgpu::BlendOperation::Add,
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("hairlab.hair.pipeline"),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(HairVertex::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineList,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: EyeTargets::DEPTH,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[
                        Some(wgpu::ColorTargetState {
                            format: EyeTargets::ACCUM,
                            blend: Some(wgpu::BlendState {
                                color: additive,
                                alpha: additive,
                            }),
                            write_mask: wgpu::ColorWrites::ALL,
                        }),
                        Some(wgpu::ColorTargetState {
                            format: EyeTargets::REVEALAGE,
                            blend: Some(wgpu::BlendState {
                                color: reveal,
                                alpha: reveal,
                            }),
                            write_mask: wgpu::ColorWrites::RED,
                        }),
                    ],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    pub fn record(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        method: &dyn LightMethod,
        method_gpu: &dyn MethodGpu,
        targets: &EyeTargets,
        scene: &wgpu::BindGroup,
        geometry: &GeometryBuffers,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let pipeline = self.pipeline(device, method, method_gpu);
        let clear = |view, v: f64| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: v,
                        g: 0.0,
                        b: 0.0,
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.hair.pass"),
            color_attachments: &[
                clear(&targets.accum_view, 0.0),
                clear(&targets.revealage_view, 1.0),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_view,
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
        if geometry.hair_index_count == 0 {
            return;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, method_gpu.bind_group(), &[]);
        pass.set_vertex_buffer(0, geometry.hair_vertices.slice(..));
        pass.set_index_buffer(geometry.hair_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..geometry.hair_index_count, 0, 0..1);
    }
}
