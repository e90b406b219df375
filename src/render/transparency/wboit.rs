//! Weighted blended order-independent transparency (McGuire & Bavoil 2013): one hair pass into two targets,
//! an accumulation of weighted premultiplied colour (Rgba16Float, One/One) and the revealage, the product of
//! `1 - alpha` (R16Float, Zero/OneMinusSrc), resolved as their weighted average colour over the opaque image with
//! coverage `1 - revealage`. Order-independent and one pass, at the price of an approximate colour where
//! fragments of different colours overlap (the depth weight favours the nearer ones). 10 B per pixel.

use super::{EntryDepth, EyeSetup, EyeTransparency, HairEntry, TechniqueInfo, TransparencyGpu};
use crate::gpu::GpuError;
use crate::render::eye::one_pass::{OnePass, OnePassSpec};
use crate::render::eye::pipelines::{additive, revealage};
use crate::render::method::{ParamValues, Role};
use crate::transparency::{Compositor, ModelContext};

pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[additive(ACCUM, wgpu::ColorWrites::ALL), revealage(REVEALAGE)],
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
        Ok(Box::new(OnePass::new(setup, &PASSES)))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::WboitParams::default())
    }
}

/// Nothing accumulated, everything revealed; resolved as their weighted average, alpha-blended over.
static PASSES: OnePassSpec = OnePassSpec {
    info: &INFO,
    entry: &HAIR,
    targets: &[("accum", [0.0; 4]), ("revealage", [1.0, 0.0, 0.0, 0.0])],
    blend: wgpu::BlendState::ALPHA_BLENDING,
};
