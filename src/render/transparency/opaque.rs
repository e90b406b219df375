//! No transparency (S&A 2009 Fig. 2's "no transparency", their fastest): one hair pass with depth writes into
//! the technique's own Depth32Float target, cleared each frame, keeping the nearest fragment's colour `(c, 1)` in
//! an Rgba32Float target, which the resolve copies onto the image where a fragment was written. The hair entry
//! writes `frag_depth = depth / S` (S a power of two above the frame's far eye depth, as depth peeling does) and
//! tests the meshes by hand: a copy of the meshes' depth would order the hair by clip z, which differs from the
//! stored eye depth the model orders by (measured: 9e-2 off the model on the GPU = CPU test). Exact-depth ties
//! keep the first rasterised fragment (the lowest segment), as the model does. 20 B per pixel.

use super::depth_peel::depth_scale;
use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, PREMULTIPLIED_OVER,
    TechniqueInfo, TransparencyGpu,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::Resolve;
use crate::render::eye::pipelines::replace;
use crate::render::eye::targets::Textures;
use crate::render::method::{ParamValues, Role};
use crate::render::targets::EyeTargets;
use crate::transparency::opaque::OpaqueParams;
use crate::transparency::{Compositor, ModelContext};

pub const NEAREST: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[replace(NEAREST, wgpu::ColorWrites::ALL)],
    depth: EntryDepth::Own,
    geometry: super::HairGeometry::Lines,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "opaque",
    label: "No transparency",
    paper: "Sintorn & Assarsson 2009, Hair Self Shadowing and Transparency Depth Ordering Using Occupancy Maps \
            (Fig. 2, no transparency)",
    role: Role::Baseline,
    hair_wgsl: "transparency/opaque.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &["transparency/opaque_resolve.wgsl"],
    params: &[],
    color: [120, 120, 120],
    // The nearest fragment's colour copied; measured 0 on lavapipe (tests/it/transparency_gpu.rs, 160×120).
    gpu_tolerance: 1e-6,
};

pub struct Opaque;

impl EyeTransparency for Opaque {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        let device = &setup.gpu.device;
        Ok(Box::new(OpaqueGpu {
            // The technique's own depth (the nearest hair), read where the meshes' depth would be.
            hair_layout: bindings::layout(
                device,
                "hairlab.opaque.hair_layout",
                &[Binding::MeshDepth, Binding::Uniform],
            ),
            scale: bindings::uniform(device, "hairlab.opaque.scale", 16),
            resolve: Resolve::of_textures(device, INFO.name, INFO.pass_wgsl[0], 1, PREMULTIPLIED_OVER),
            targets: Textures::new(
                device,
                INFO.name,
                &[("nearest", NEAREST), ("depth", EyeTargets::DEPTH)],
                (setup.width, setup.height),
            ),
        }))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(OpaqueParams)
    }
}

struct OpaqueGpu {
    /// Group 2 of the hair entry: the meshes' depth and `1 / S`.
    hair_layout: wgpu::BindGroupLayout,
    scale: wgpu::Buffer,
    resolve: Resolve,
    /// The nearest colour and the technique's depth.
    targets: Textures,
}

impl TransparencyGpu for OpaqueGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.targets.resize(&gpu.device, (width, height));
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let scale = [1.0 / depth_scale(frame.model.depth_range[1]), 0.0, 0.0, 0.0];
        frame
            .gpu
            .queue
            .write_buffer(&self.scale, 0, bytemuck::cast_slice(&scale));
        let group = bindings::group(
            &frame.gpu.device,
            "hairlab.opaque.hair_bind_group",
            &self.hair_layout,
            &[
                wgpu::BindingResource::TextureView(&frame.targets.depth_view),
                self.scale.as_entire_binding(),
            ],
        );
        let t = &self.targets;
        frame.draw_hair(
            HairDrawPass {
                entry: &HAIR,
                attachments: &t.cleared(&[[0.0; 4]]),
                depth: Some((t.view(1), Some(1.0))),
                group: Some((&self.hair_layout, &group)),
                rows: None,
            },
            "eye: hair",
        );
        self.resolve.record_textures(frame, &[t.view(0)]);
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.targets.bytes()
    }

    fn geometry_passes(&self) -> u32 {
        1
    }
}
