//! No transparency (S&A 2009 Fig. 2's "no transparency", their fastest): one hair pass with depth writes. The
//! technique's own Depth32Float target starts each frame as a copy of the meshes' depth; the hair entry tests it
//! `Less` and writes it, so the nearest fragment's colour `(c, 1)` stays in an Rgba32Float target, which the
//! resolve copies onto the image where a fragment was written. Exact-depth ties keep the first rasterised
//! fragment (the lowest segment), as the model does. 20 B per pixel.

use super::{
    EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, PREMULTIPLIED_OVER, TechniqueInfo,
    TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::method::{ParamValues, Role};
use crate::render::passes::composite::{CompositePass, texture_bind_group, texture_layout};
use crate::render::targets::{EyeTargets, eye_texture};
use crate::transparency::opaque::OpaqueParams;
use crate::transparency::{Compositor, ModelContext};

pub const NEAREST: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[wgpu::ColorTargetState {
        format: NEAREST,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    }],
    depth_write: true,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "opaque",
    label: "No transparency",
    paper: "Sintorn & Assarsson 2009, Hair Self Shadowing and Transparency Depth Ordering Using Occupancy Maps \
            (Fig. 2, no transparency)",
    role: Role::Approximation,
    hair_wgsl: "transparency/opaque.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &["transparency/opaque_resolve.wgsl"],
    params: &[],
    color: [120, 120, 120],
    gpu_tolerance: 1e-5,
};

pub struct Opaque;

impl EyeTransparency for Opaque {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        let device = &setup.gpu.device;
        let layout = texture_layout(device, "hairlab.opaque.resolve_bind_group_layout", 1);
        let resolve = CompositePass::new(
            device,
            "hairlab.opaque.resolve",
            INFO.pass_wgsl[0],
            &layout,
            PREMULTIPLIED_OVER,
        );
        let targets = Targets::new(device, &layout, setup.width, setup.height);
        Ok(Box::new(OpaqueGpu {
            layout,
            resolve,
            targets,
        }))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(OpaqueParams)
    }
}

/// The nearest colour and the depth target at one viewport size, and the resolve's bind group.
struct Targets {
    nearest: wgpu::TextureView,
    depth: wgpu::Texture,
    depth_view: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    width: u32,
    height: u32,
}

impl Targets {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, width: u32, height: u32) -> Targets {
        let nearest = eye_texture(
            device,
            "hairlab.opaque.nearest",
            (width, height),
            NEAREST,
            wgpu::TextureUsages::TEXTURE_BINDING,
            &[],
        )
        .create_view(&Default::default());
        let depth = eye_texture(
            device,
            "hairlab.opaque.depth",
            (width, height),
            EyeTargets::DEPTH,
            wgpu::TextureUsages::COPY_DST,
            &[],
        );
        let bind_group = texture_bind_group(device, "hairlab.opaque.resolve_bind_group", layout, &[&nearest]);
        Targets {
            nearest,
            depth_view: depth.create_view(&Default::default()),
            depth,
            bind_group,
            width,
            height,
        }
    }
}

struct OpaqueGpu {
    layout: wgpu::BindGroupLayout,
    resolve: CompositePass,
    targets: Targets,
}

impl TransparencyGpu for OpaqueGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (self.targets.width, self.targets.height) != (width, height) {
            self.targets = Targets::new(&gpu.device, &self.layout, width, height);
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let t = &self.targets;
        frame.encoder.copy_texture_to_texture(
            frame.targets.depth.as_image_copy(),
            t.depth.as_image_copy(),
            t.depth.size(),
        );
        let attachments = [cleared(&t.nearest, [0.0; 4])];
        frame.draw_hair(
            HairDrawPass {
                entry: &HAIR,
                attachments: &attachments,
                depth: Some((&t.depth_view, None)),
                group: None,
                rows: None,
            },
            "eye: hair",
        );
        let timestamps = frame.timer.as_mut().and_then(|t| t.pass("eye: resolve"));
        self.resolve.record(
            &mut frame.encoder,
            &frame.targets.color_view,
            &t.bind_group,
            timestamps,
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let texel = NEAREST.block_copy_size(None).unwrap_or(0) + 4;
        self.targets.width as u64 * self.targets.height as u64 * u64::from(texel)
    }

    fn geometry_passes(&self) -> u32 {
        1
    }
}
