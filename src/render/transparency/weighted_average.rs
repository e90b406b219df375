//! Weighted average blending (Bavoil & Myers 2008 as published; S&A 2009's "dull" comparison): one hair pass
//! sums `(a c, a)` into an Rgba32Float target and counts the fragments in an R32Float target (both One/One); the
//! resolve takes the alpha-weighted mean colour `C_avg = Σ a c / Σ a` and the mean alpha `α_avg = Σ a / n` and
//! covers the opaque image with `n` layers of it: `T = (1 − α_avg)^n`, `C = C_avg (1 − T) + T B`.
//! Order-independent and one geometry pass; the colour is an average, so depth order and contrast are lost.
//! 20 B per pixel.

use super::{
    EntryDepth, EyeSetup, EyeTransparency, HairEntry, PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu,
};
use crate::gpu::GpuError;
use crate::render::eye::one_pass::{OnePass, OnePassSpec};
use crate::render::eye::pipelines::additive;
use crate::render::method::{ParamValues, Role};
use crate::transparency::weighted_average::WeightedAverageParams;
use crate::transparency::{Compositor, ModelContext};

pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
pub const COUNT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[
        additive(ACCUM, wgpu::ColorWrites::ALL),
        additive(COUNT, wgpu::ColorWrites::RED),
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
        Ok(Box::new(OnePass::new(setup, &PASSES)))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(WeightedAverageParams)
    }
}

/// Nothing summed, nothing counted; resolved as `(C_avg (1 − T), 1 − T)`, premultiplied over.
static PASSES: OnePassSpec = OnePassSpec {
    info: &INFO,
    entry: &HAIR,
    targets: &[("accum", [0.0; 4]), ("count", [0.0; 4])],
    blend: PREMULTIPLIED_OVER,
};
