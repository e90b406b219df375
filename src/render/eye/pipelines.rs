//! Base pipeline descriptors of the eye passes (bevy's specialised pipelines: one base, adjusted by what a pass
//! declares): [`geometry`], a pass over the strands from the eye through the shared eye vertex stage
//! (`common/eye_vertex.wgsl`), as lines or camera-facing ribbons, into the technique's targets with or without the
//! meshes' depth test; [`fullscreen`], a resolve's full-screen triangle (`common/fullscreen.wgsl`).

use crate::render::geometry::{HairVertex, RIBBON_GROUP};
use crate::render::passes::hair::HairGeometry;
use crate::render::targets::EyeTargets;

/// An eye geometry pass as a technique declares it.
pub struct GeometryPass<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    /// Groups 0.. (the frame's first); a ribbon pass gets the strands' group at [`RIBBON_GROUP`] added.
    pub layouts: &'a [&'a wgpu::BindGroupLayout],
    /// Lines (`vs_main` taking [`HairVertex`]) or ribbons (`vs_main` pulling the strands' storage buffers).
    pub geometry: HairGeometry,
    /// The fragment entry and what it writes.
    pub fragment: &'a str,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    /// The depth test: none (the entry tests the meshes' depth by hand, `common/mesh_depth.wgsl`), or `Less`
    /// against a `EyeTargets::DEPTH` image, written or not.
    pub depth: Option<DepthTest>,
}

/// How a geometry pass tests depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthTest {
    /// `Less` against the meshes' depth, not written.
    Meshes,
    /// `Less` against a technique's own depth image, written.
    Own,
}

/// The pipeline of `pass`.
pub fn geometry(device: &wgpu::Device, pass: &GeometryPass) -> wgpu::RenderPipeline {
    let ribbons = pass.geometry == HairGeometry::Ribbons;
    let ribbon_layout = ribbons.then(|| crate::render::geometry::ribbon_layout(device));
    let mut layouts: Vec<Option<&wgpu::BindGroupLayout>> = pass.layouts.iter().copied().map(Some).collect();
    if let Some(l) = &ribbon_layout {
        layouts.resize(RIBBON_GROUP as usize, None);
        layouts.push(Some(l));
    }
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(pass.label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    let lines = [Some(HairVertex::layout())];
    let (buffers, topology) = if ribbons {
        // Ribbons face the camera but their winding follows the strand: no culling.
        (&[][..], wgpu::PrimitiveTopology::TriangleList)
    } else {
        (&lines[..], wgpu::PrimitiveTopology::LineList)
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(pass.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: pass.module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            ..Default::default()
        },
        depth_stencil: pass.depth.map(|d| wgpu::DepthStencilState {
            format: EyeTargets::DEPTH,
            depth_write_enabled: Some(d == DepthTest::Own),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: pass.module,
            entry_point: Some(pass.fragment),
            compilation_options: Default::default(),
            targets: pass.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A storage-only pass over the strands (the count passes' shape): `wgsl`'s `vs_main` and `fs_main`, group 0 the
/// frame's and group 1 `group`, into the never-written null target; the entry tests the meshes' depth by hand
/// (`common/mesh_depth.wgsl`), before its atomics, which a fixed-function test after the shader would not undo.
pub fn storage_pass(
    device: &wgpu::Device,
    label: &str,
    wgsl: &str,
    layouts: [&wgpu::BindGroupLayout; 2],
    geometry: HairGeometry,
) -> wgpu::RenderPipeline {
    let module = crate::render::passes::shader_module(device, &format!("{label}.shader"), wgsl, None);
    self::geometry(
        device,
        &GeometryPass {
            label: &format!("{label}.pipeline"),
            module: &module,
            layouts: &layouts,
            geometry,
            fragment: "fs_main",
            targets: &[Some(EyeTargets::NULL)],
            depth: None,
        },
    )
}

/// A full-screen pass of `module` (`vs_main` the full-screen triangle, `fs_main`) over groups `layouts`,
/// writing `targets`.
pub fn fullscreen(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let layouts: Vec<_> = layouts.iter().copied().map(Some).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The target of a resolve that outputs `(H, 1 - T)` blended premultiplied over `format`'s image: colour only
/// onto the colour image (its alpha stays the meshes'), everything onto a capture target.
pub fn over_target(format: wgpu::TextureFormat) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
        write_mask: if format == EyeTargets::COLOR {
            wgpu::ColorWrites::COLOR
        } else {
            wgpu::ColorWrites::ALL
        },
    }
}

/// A colour target of `format` written unblended, `write_mask` channels.
pub const fn replace(format: wgpu::TextureFormat, write_mask: wgpu::ColorWrites) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: None,
        write_mask,
    }
}

/// A colour target summed One/One (colour and alpha) into `format`, `write_mask` channels written: the
/// accumulations of the order-independent techniques.
pub const fn additive(format: wgpu::TextureFormat, write_mask: wgpu::ColorWrites) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: Some(crate::render::transparency::ADDITIVE),
        write_mask,
    }
}

/// A revealage target of `format`: its red channel multiplied by `1 - src` (Zero/OneMinusSrc), so that cleared to
/// 1 it ends as the product of every fragment's `1 - alpha`.
pub const fn revealage(format: wgpu::TextureFormat) -> wgpu::ColorTargetState {
    const PRODUCT: wgpu::BlendComponent = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrc,
        operation: wgpu::BlendOperation::Add,
    };
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState {
            color: PRODUCT,
            alpha: PRODUCT,
        }),
        write_mask: wgpu::ColorWrites::RED,
    }
}

/// A shader module of the composed `src` (a composer error is a bug the shader tests rule out: it panics).
pub fn module(
    device: &wgpu::Device,
    label: &str,
    src: Result<String, crate::shaders::ShaderError>,
) -> wgpu::ShaderModule {
    let src = src.unwrap_or_else(|e| panic!("{e}"));
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    })
}

/// Records a full-screen pass of `pipeline` loaded and blended onto `output` (rows `[y0, y1)` only when given;
/// nothing drawn for an empty band), groups 0.. from `groups`.
pub fn record_fullscreen(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    output: &wgpu::TextureView,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    rows: Option<(u32, u32, u32)>,
    pipeline: &wgpu::RenderPipeline,
    groups: &[&wgpu::BindGroup],
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: output,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if let Some((width, y0, y1)) = rows {
        if y1 <= y0 {
            return;
        }
        pass.set_scissor_rect(0, y0, width, y1 - y0);
    }
    pass.set_pipeline(pipeline);
    for (i, g) in groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *g, &[]);
    }
    pass.draw(0..3, 0..1);
}
