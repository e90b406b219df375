//! Weighted blended order-independent transparency (McGuire & Bavoil 2013): one hair pass into two targets,
//! an accumulation of weighted premultiplied colour (Rgba16Float, One/One) and the revealage, the product of
//! `1 - alpha` (R16Float, Zero/OneMinusSrc), resolved as their weighted average colour over the opaque image with
//! coverage `1 - revealage`. Order-independent and one pass, at the price of an approximate colour where
//! fragments of different colours overlap (the depth weight favours the nearer ones). 10 B per pixel.

use super::{
    ADDITIVE, EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, TechniqueInfo,
    TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings;
use crate::render::method::{ParamValues, Role};
use crate::render::passes::composite::{CompositePass, texture_layout};
use crate::transparency::{Compositor, ModelContext};

pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

const REVEAL: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::Zero,
    dst_factor: wgpu::BlendFactor::OneMinusSrc,
    operation: wgpu::BlendOperation::Add,
};

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[
        wgpu::ColorTargetState {
            format: ACCUM,
            blend: Some(ADDITIVE),
            write_mask: wgpu::ColorWrites::ALL,
        },
        wgpu::ColorTargetState {
            format: REVEALAGE,
            blend: Some(wgpu::BlendState {
                color: REVEAL,
                alpha: REVEAL,
            }),
            write_mask: wgpu::ColorWrites::RED,
        },
    ],
    depth: EntryDepth::Meshes,
    geometry: super::HairGeometry::Lines,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "wboit",
    label: "Weighted blended OIT",
    paper: "McGuire & Bavoil 2013, Weighted Blended Order-Independent Transparency",
    role: Role::Approximation,
    hair_wgsl: "transparency/wboit.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &["transparency/wboit_resolve.wgsl"],
    params: &[],
    color: [230, 159, 0],
    // f16 targets rounded after every blend; the model rounds the same way in submission order. Measured 5.3e-4
    // on lavapipe (tests/it/transparency_gpu.rs).
    gpu_tolerance: 1e-3,
};

pub struct Wboit;

impl EyeTransparency for Wboit {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        let device = &setup.gpu.device;
        let layout = texture_layout(device, "hairlab.wboit.resolve_bind_group_layout", 2);
        let resolve = CompositePass::new(
            device,
            "hairlab.wboit.resolve",
            INFO.pass_wgsl[0],
            &layout,
            wgpu::BlendState::ALPHA_BLENDING,
        );
        let targets = WboitTargets::new(device, &layout, setup.width, setup.height);
        Ok(Box::new(WboitGpu {
            layout,
            resolve,
            targets,
        }))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::WboitParams::default())
    }
}

/// The two targets at one viewport size and the resolve's bind group reading them.
struct WboitTargets {
    accum: wgpu::TextureView,
    revealage: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    width: u32,
    height: u32,
}

impl WboitTargets {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, width: u32, height: u32) -> WboitTargets {
        let view = |label, format| bindings::texture(device, label, (width, height), format);
        let accum = view("hairlab.wboit.accum", ACCUM);
        let revealage = view("hairlab.wboit.revealage", REVEALAGE);
        let bind_group = crate::render::passes::composite::texture_bind_group(
            device,
            "hairlab.wboit.resolve_bind_group",
            layout,
            &[&accum, &revealage],
        );
        WboitTargets {
            accum,
            revealage,
            bind_group,
            width,
            height,
        }
    }
}

struct WboitGpu {
    layout: wgpu::BindGroupLayout,
    resolve: CompositePass,
    targets: WboitTargets,
}

impl TransparencyGpu for WboitGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (self.targets.width, self.targets.height) != (width, height) {
            self.targets = WboitTargets::new(&gpu.device, &self.layout, width, height);
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        // Nothing accumulated, everything revealed.
        let attachments = [
            cleared(&self.targets.accum, [0.0; 4]),
            cleared(&self.targets.revealage, [1.0, 0.0, 0.0, 0.0]),
        ];
        frame.draw_hair(
            HairDrawPass {
                entry: &HAIR,
                attachments: &attachments,
                depth: None,
                group: None,
                rows: None,
            },
            "eye: hair",
        );
        let timestamps = frame
            .timer
            .as_mut()
            .and_then(|t| t.pass(crate::gpu::timing::Phase::Resolve, "eye: resolve"));
        self.resolve.record(
            &mut frame.encoder,
            frame.output,
            &self.targets.bind_group,
            timestamps,
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let texel: u64 = HAIR
            .targets
            .iter()
            .filter_map(|t| t.format.block_copy_size(None))
            .map(u64::from)
            .sum();
        self.targets.width as u64 * self.targets.height as u64 * texel
    }

    fn geometry_passes(&self) -> u32 {
        1
    }
}
