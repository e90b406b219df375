//! Weighted average blending (Bavoil & Myers 2008 as published; S&A 2009's "dull" comparison): one hair pass
//! sums `(a c, a)` into an Rgba32Float target and counts the fragments in an R32Float target (both One/One); the
//! resolve takes the alpha-weighted mean colour `C_avg = Σ a c / Σ a` and the mean alpha `α_avg = Σ a / n` and
//! covers the opaque image with `n` layers of it: `T = (1 − α_avg)^n`, `C = C_avg (1 − T) + T B`.
//! Order-independent and one geometry pass; the colour is an average, so depth order and contrast are lost.
//! 20 B per pixel.

use super::{
    ADDITIVE, EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, PREMULTIPLIED_OVER,
    TechniqueInfo, TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings;
use crate::render::method::{ParamValues, Role};
use crate::render::passes::composite::{CompositePass, texture_bind_group, texture_layout};
use crate::transparency::weighted_average::WeightedAverageParams;
use crate::transparency::{Compositor, ModelContext};

pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
pub const COUNT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[
        wgpu::ColorTargetState {
            format: ACCUM,
            blend: Some(ADDITIVE),
            write_mask: wgpu::ColorWrites::ALL,
        },
        wgpu::ColorTargetState {
            format: COUNT,
            blend: Some(ADDITIVE),
            write_mask: wgpu::ColorWrites::RED,
        },
    ],
    depth: EntryDepth::Meshes,
    geometry: super::HairGeometry::Lines,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "weighted-average",
    label: "Weighted average",
    paper: "Bavoil & Myers 2008, Order Independent Transparency with Dual Depth Peeling (weighted average)",
    role: Role::Approximation,
    hair_wgsl: "transparency/weighted_average.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &["transparency/weighted_average_resolve.wgsl"],
    params: &[],
    color: [0, 158, 115],
    // f32 sums in blend order; measured 1.8e-7 on lavapipe (tests/it/transparency_gpu.rs, 160×120, deepest 50).
    gpu_tolerance: 1e-5,
};

pub struct WeightedAverage;

impl EyeTransparency for WeightedAverage {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        let device = &setup.gpu.device;
        let layout = texture_layout(device, "hairlab.weighted-average.resolve_bind_group_layout", 2);
        let resolve = CompositePass::new(
            device,
            "hairlab.weighted-average.resolve",
            INFO.pass_wgsl[0],
            &layout,
            PREMULTIPLIED_OVER,
        );
        let targets = Targets::new(device, &layout, setup.width, setup.height);
        Ok(Box::new(WeightedAverageGpu {
            layout,
            resolve,
            targets,
        }))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(WeightedAverageParams)
    }
}

/// The accumulation and count targets at one viewport size and the resolve's bind group reading them.
struct Targets {
    accum: wgpu::TextureView,
    count: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    width: u32,
    height: u32,
}

impl Targets {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, width: u32, height: u32) -> Targets {
        let view = |label, format| bindings::texture(device, label, (width, height), format);
        let accum = view("hairlab.weighted-average.accum", ACCUM);
        let count = view("hairlab.weighted-average.count", COUNT);
        let bind_group = texture_bind_group(
            device,
            "hairlab.weighted-average.resolve_bind_group",
            layout,
            &[&accum, &count],
        );
        Targets {
            accum,
            count,
            bind_group,
            width,
            height,
        }
    }
}

struct WeightedAverageGpu {
    layout: wgpu::BindGroupLayout,
    resolve: CompositePass,
    targets: Targets,
}

impl TransparencyGpu for WeightedAverageGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (self.targets.width, self.targets.height) != (width, height) {
            self.targets = Targets::new(&gpu.device, &self.layout, width, height);
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let attachments = [
            cleared(&self.targets.accum, [0.0; 4]),
            cleared(&self.targets.count, [0.0; 4]),
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
