//! Classic depth peeling (Everitt 2001; S&A 2009's ground truth and cost baseline): one geometry pass of shaded
//! hair per layer, each keeping the nearest fragment strictly behind the previous layer's depth in the
//! technique's own depth target, then a full-screen "under" blend of the layer, `C += T a c, T *= 1 − a`, into an
//! Rgba32Float accumulation; the resolve puts `(C, 1 − T)` over the opaque image.
//!
//! The depth test orders `frag_depth = depth / S`, S a power of two above the frame's far eye depth: the
//! division is exact, so the test orders exactly as the stored depth. The meshes' depth is a different quantity
//! (clip z), so the hair entry tests it by hand. The previous layer's depth is an R32Float second output,
//! ping-ponged between two targets.
//!
//! Layer count: a count pass first (one more geometry pass, the shared eye vertex stage, `atomicAdd` per pixel
//! and `atomicMax` over the frame) gives the deepest pixel's fragment count L, read back once per frame; the peel
//! then runs exactly L layers. Against an occlusion query or a written-pixel counter per layer this costs one
//! geometry pass and one readback instead of a readback (a stall) every layer or every few layers, and no layer
//! peels nothing. Exact-depth ties: a layer keeps the first rasterised fragment and the strict test drops the
//! others, so with ties the last layers are empty. More than `max_layers` layers is an error. Timed as one entry,
//! `depth peel (L layers)`; geometry passes L + 1. 4 (counts) + 4 (depth) + 16 (layer) + 2 × 4 (layer depths)
//! + 16 (accumulation) = 48 B per pixel.

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry,
    PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::complexity::DepthComplexity;
use crate::render::eye::passes::Resolve;
use crate::render::eye::pipelines::{self, replace};
use crate::render::eye::targets::Textures;
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role, value};
use crate::render::targets::EyeTargets;
use crate::transparency::classic_peel::ClassicPeelParams;
use crate::transparency::{Compositor, ModelContext};

pub const LAYER: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
pub const LAYER_DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The targets: the accumulation (read by the resolve), the layer (read by the under blend), the two layer
/// depths (written alternately, each read by the next layer) and the technique's own depth.
const TARGETS: [(&str, wgpu::TextureFormat); 5] = [
    ("accum", ACCUM),
    ("layer", LAYER),
    ("layer_depth0", LAYER_DEPTH),
    ("layer_depth1", LAYER_DEPTH),
    ("depth", EyeTargets::DEPTH),
];

const MAX_LAYERS: ParamSpec = ParamSpec {
    key: "max_layers",
    label: "max layers",
    help: "most layers a frame may peel (the deepest pixel's fragment count); beyond it the frame is an error",
    kind: ParamKind::Int { min: 1, max: 65536 },
    default: 4096.0,
};

static HAIR: HairEntry = HairEntry {
    entry: "fs_peel",
    targets: &[
        replace(LAYER, wgpu::ColorWrites::ALL),
        replace(LAYER_DEPTH, wgpu::ColorWrites::RED),
    ],
    depth: EntryDepth::Own,
    geometry: HairGeometry::Lines,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "depth-peel",
    label: "Depth peeling",
    paper: "Everitt 2001, Interactive Order-Independent Transparency (S&A 2009's ground truth)",
    role: Role::Approximation,
    hair_wgsl: "transparency/depth_peel.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &[
        "transparency/depth_peel_count.wgsl",
        "transparency/depth_peel_under.wgsl",
        "transparency/depth_peel_resolve.wgsl",
    ],
    params: &[MAX_LAYERS],
    color: [0, 114, 178],
    // f32 under blends front to back; measured 6.0e-8 on lavapipe (tests/it/transparency_gpu.rs, 160×120,
    // deepest 50).
    gpu_tolerance: 1e-5,
};

/// The "under" blend of a layer onto the accumulation `(C, T)`: `C += T (a c)`, `T *= 1 − a`.
const UNDER: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::DstAlpha,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The smallest power of two strictly above `far` (with a margin for rounding): `depth / S < 1` for every
/// fragment, and dividing by it is exact.
pub(super) fn depth_scale(far: f32) -> f32 {
    let far = if far.is_finite() { far.max(1e-6) } else { 1.0 };
    2f32.powi((far * 1.001).log2().floor() as i32 + 1)
}

pub struct DepthPeel;

impl EyeTransparency for DepthPeel {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        let device = &setup.gpu.device;
        let under_layout = bindings::layout(device, "hairlab.depth-peel.under_layout", &[Binding::Texture]);
        let under = crate::render::passes::shader_module(
            device,
            "hairlab.depth-peel.under.shader",
            INFO.pass_wgsl[1],
            None,
        );
        Ok(Box::new(DepthPeelGpu {
            complexity: DepthComplexity::new(setup, INFO.name, INFO.pass_wgsl[0])?,
            peel_layout: bindings::layout(
                device,
                "hairlab.depth-peel.peel_layout",
                &[Binding::MeshDepth, Binding::Texture, Binding::Uniform],
            ),
            under: pipelines::fullscreen(
                device,
                "hairlab.depth-peel.under.pipeline",
                &under,
                &[&under_layout],
                &[Some(wgpu::ColorTargetState {
                    blend: Some(UNDER),
                    ..replace(ACCUM, wgpu::ColorWrites::ALL)
                })],
            ),
            under_layout,
            resolve: Resolve::of_textures(device, INFO.name, INFO.pass_wgsl[2], 1, PREMULTIPLIED_OVER),
            scale: bindings::uniform(device, "hairlab.depth-peel.scale", 16),
            targets: Textures::new(device, INFO.name, &TARGETS, (setup.width, setup.height)),
            layers: 0,
            last: (0, 0),
        }))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(ClassicPeelParams)
    }
}

struct DepthPeelGpu {
    /// The count pass: the deepest pixel's fragment count is the frame's layer count.
    complexity: DepthComplexity,
    peel_layout: wgpu::BindGroupLayout,
    under_layout: wgpu::BindGroupLayout,
    under: wgpu::RenderPipeline,
    resolve: Resolve,
    scale: wgpu::Buffer,
    targets: Textures,
    /// Layers peeled in the last frame.
    layers: u32,
    /// The last frame's deepest pixel and total fragment count.
    last: (u32, u64),
}

impl TransparencyGpu for DepthPeelGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.complexity.resize(gpu, (width, height))?;
        self.targets.resize(&gpu.device, (width, height));
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        self.layers = 0;
        let (layers, total) = self.complexity.count(frame)?;
        self.last = (layers, u64::from(total));
        let max_layers = value(frame.values, &MAX_LAYERS) as u32;
        if layers > max_layers {
            return Err(GpuError::Setting(format!(
                "transparency.max_layers: depth peel did not finish within {max_layers} layers (the deepest pixel \
                 has {layers} fragments)"
            )));
        }
        if layers == 0 {
            return Ok(());
        }
        let scale = [1.0 / depth_scale(frame.model.depth_range[1]), 0.0, 0.0, 0.0];
        frame
            .gpu
            .queue
            .write_buffer(&self.scale, 0, bytemuck::cast_slice(&scale));
        let [accum, layer, depth0, depth1, depth] = [0, 1, 2, 3, 4].map(|i| self.targets.view(i));
        let layer_depths = [depth0, depth1];
        // Group 2 of a layer: the meshes' depth, the previous layer's depth, `1 / S`.
        let groups = [depth1, depth0].map(|previous| {
            bindings::group(
                &frame.gpu.device,
                "hairlab.depth-peel.peel_bind_group",
                &self.peel_layout,
                &[
                    wgpu::BindingResource::TextureView(&frame.targets.depth_view),
                    wgpu::BindingResource::TextureView(previous),
                    self.scale.as_entire_binding(),
                ],
            )
        });
        let layer_group = bindings::group(
            &frame.gpu.device,
            "hairlab.depth-peel.layer_bind_group",
            &self.under_layout,
            &[wgpu::BindingResource::TextureView(layer)],
        );
        let span = frame.timer.as_mut().and_then(|timer| {
            timer.span(
                crate::gpu::timing::Phase::EyeHair,
                format!("depth peel ({layers} layers)"),
            )
        });
        // Nothing accumulated, everything transmitted; no layer before the first.
        frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hairlab.depth-peel.clear.pass"),
            color_attachments: &[cleared(accum, [0.0, 0.0, 0.0, 1.0]), cleared(depth1, [0.0; 4])],
            depth_stencil_attachment: None,
            timestamp_writes: span.as_ref().map(|s| s.first()),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for k in 0..layers as usize {
            let attachments = [
                cleared(layer, [0.0; 4]),
                cleared(layer_depths[k % 2], [f32::MAX as f64, 0.0, 0.0, 0.0]),
            ];
            frame.draw_hair_untimed(HairDrawPass {
                entry: &HAIR,
                attachments: &attachments,
                depth: Some((depth, Some(1.0))),
                group: Some((&self.peel_layout, &groups[k % 2])),
                rows: None,
            });
            let last = k + 1 == layers as usize;
            pipelines::record_fullscreen(
                &mut frame.encoder,
                "hairlab.depth-peel.under.pass",
                accum,
                span.as_ref().filter(|_| last).map(|s| s.last()),
                None,
                &self.under,
                &[&layer_group],
            );
        }
        self.resolve.record_textures(frame, &[accum]);
        self.layers = layers;
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let (width, height) = self.targets.size();
        self.targets.bytes() + width as u64 * height as u64 * DepthComplexity::BYTES_PER_PIXEL
    }

    fn geometry_passes(&self) -> u32 {
        self.layers + 1
    }

    fn depth_complexity(&self) -> Option<(u32, u64)> {
        Some(self.last)
    }
}

#[cfg(test)]
mod tests {
    use super::depth_scale;

    #[test]
    fn the_depth_scale_is_the_power_of_two_above_the_far_depth() {
        assert_eq!(depth_scale(1.3), 2.0);
        assert_eq!(depth_scale(2.0), 4.0);
        assert_eq!(depth_scale(0.3), 0.5);
        assert_eq!(depth_scale(3.99), 4.0);
        assert_eq!(depth_scale(3.999), 8.0);
        assert_eq!(depth_scale(f32::NAN), 2.0);
    }
}
