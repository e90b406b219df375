//! Occupancy-ordered blending (Sintorn & Assarsson 2009 §3.4): the Occupancy Maps of the light-space method
//! built from the camera give each hair fragment an approximate number `o` of fragments in front of it, so
//! unsorted fragments can be blended additively with their back-to-front weights. The CPU model is
//! `transparency::occupancy_order`.
//!
//! Three geometry passes over the strands, all with the shared eye vertex stage and tested `Less` against the
//! meshes' depth without writing (the hair pass's depth state, so every pass sees the same fragments; the
//! occupancy pass tests by hand, `common/mesh_depth.wgsl`, before its atomics):
//! 1. `eye: depth range`: the pixel's nearest and furthest eye depth, two R32Float targets cleared to (big, 0)
//!    with Min / Max blending (spec A.3 #7: the paper's two depth-test passes in one);
//! 2. `eye: occupancy + slabs`: the 128-slice occupancy bitmap and the 4 slab counts of the pixel, `atomicOr` /
//!    `atomicAdd` into two storage buffers of four u32 per pixel, exactly the light-space pass on eye pixels
//!    (relative depth `(depth - near_p) / (far_p - near_p)` with the step convention of a zero range);
//! 3. `eye: hair`: each shaded fragment adds `(w c, w)`, `w = exp(-o b̄) ᾱ`, into an Rgba32Float (or, to show
//!    why the paper needs 32 bits, Rgba16Float) One/One target; `ᾱ` is the global hair alpha
//!    (`frame.hair_alpha`) and `b̄ = -ln(1 - min(ᾱ, 1 - 1e-6))`: each fragment's own alpha is not used (the paper
//!    assumes one alpha, spec A.3 #4).
//!    In `render.alpha = "coverage"` mode `ᾱ` is still `render.hair_alpha` (there the material opacity).
//!
//! The resolve (`eye: resolve`) sums the four slab counts to `n`, puts `T = exp(-n b̄)` on the background and
//! `Λ = 1 - T` of hair over it; with the correction on the colour is rescaled to `rgb · Λ / acc.a` (the reading
//! of A.3 #1 that makes the total weight Λ), output `(rgb, Λ)` with [`PREMULTIPLIED_OVER`]. Pixels without
//! fragments are left untouched.
//!
//! Passes 1 and 2 build the maps (`maps.rs`: their targets, buffers, pipelines and groups); the parameters and
//! the uniforms every pass reads are `params.rs`'s; this file is the technique and its passes in order.
//!
//! Memory: 4 + 4 (depth range) + 16 (bitmap) + 16 (slabs) + 16 (accumulation) = 56 bytes per pixel at f32, 48 at
//! f16. The buffers must fit the device's storage binding size (128 MiB on lavapipe: 8,388,608 pixels).

mod maps;
mod params;

pub use params::{OccupancyOrderUniforms, uniform_mirror};

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry,
    PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu,
};
use crate::gpu::readback::copy_out;
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::Resolve;
use crate::render::eye::pipelines::additive;
use crate::render::eye::targets::Textures;
use crate::render::method::{ParamValues, Role, UniformMirror};
use crate::transparency::{Compositor, ModelContext};
use maps::OccupancyMaps;
use params::{PARAMS, params};

/// Format of the two depth-range targets.
pub const RANGE: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Bytes per pixel of each of the two storage buffers (four u32).
pub const BUFFER_BYTES_PER_PIXEL: u64 = 16;
/// Largest per-channel |C_gpu - C_cpu| with `precision = f16`: the model rounds to f16 after every blend in
/// submission order, the GPU's blend order differs; measured 5.4e-4 on lavapipe (tests/it/transparency_occupancy.rs).
pub const F16_GPU_TOLERANCE: f32 = 1e-3;

static ACCUM_F32: [wgpu::ColorTargetState; 1] =
    [additive(wgpu::TextureFormat::Rgba32Float, wgpu::ColorWrites::ALL)];
static ACCUM_F16: [wgpu::ColorTargetState; 1] =
    [additive(wgpu::TextureFormat::Rgba16Float, wgpu::ColorWrites::ALL)];

static HAIR: [HairEntry; 2] = [
    HairEntry {
        entry: "fs_main",
        targets: &ACCUM_F32,
        depth: EntryDepth::Meshes,
        geometry: HairGeometry::Lines,
    },
    HairEntry {
        entry: "fs_half",
        targets: &ACCUM_F16,
        depth: EntryDepth::Meshes,
        geometry: HairGeometry::Lines,
    },
];

static INFO: TechniqueInfo = TechniqueInfo {
    name: "occupancy-order",
    label: "Occupancy-ordered blending",
    paper: "Sintorn & Assarsson 2009, Hair Self Shadowing and Transparency Depth Ordering Using Occupancy Maps, §3.4",
    role: Role::Approximation,
    hair_wgsl: "transparency/occupancy_order.wgsl",
    hair_entries: &HAIR,
    pass_wgsl: &[
        "transparency/occupancy_order_maps.wgsl",
        "transparency/occupancy_order_resolve.wgsl",
    ],
    params: PARAMS,
    color: [86, 180, 233],
    // f32 sums of the same f32 weights in another order: measured 8.9e-8 on lavapipe (tests/it/transparency_gpu.rs,
    // 160×120, deepest pixel 50). The f16 accumulation has its own bound, F16_GPU_TOLERANCE.
    gpu_tolerance: 1e-6,
};

pub struct OccupancyOrder;

impl EyeTransparency for OccupancyOrder {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(OccupancyOrderGpu::new(setup)?))
    }

    fn model(&self, values: &ParamValues, ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(params(values).model(ctx))
    }

    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(uniform_mirror())
    }

    /// The paper's method and each option on its own: occupancy only, no Λ correction, the −½ bias, f16.
    fn sweep(&self) -> Vec<ParamValues> {
        let one = |key: &str| ParamValues::from([(key.to_string(), 1.0)]);
        vec![
            ParamValues::new(),
            one("variant"),
            one("correction"),
            one("order_bias"),
            one("precision"),
        ]
    }
}

/// Occupancy-ordered blending's GPU state, created with its maps (so they always exist).
pub struct OccupancyOrderGpu {
    maps: OccupancyMaps,
    uniforms: wgpu::Buffer,
    accum: Textures,
    resolve: Resolve,
}

impl OccupancyOrderGpu {
    fn new(setup: &EyeSetup) -> Result<OccupancyOrderGpu, GpuError> {
        let device = &setup.gpu.device;
        Ok(OccupancyOrderGpu {
            maps: OccupancyMaps::new(setup)?,
            uniforms: bindings::uniform(
                device,
                "hairlab.occupancy-order.uniforms",
                std::mem::size_of::<OccupancyOrderUniforms>() as u64,
            ),
            accum: Textures::new(
                device,
                INFO.name,
                &[("accum", HAIR[0].targets[0].format)],
                (setup.width, setup.height),
            ),
            resolve: Resolve::new(
                device,
                INFO.name,
                INFO.pass_wgsl[1],
                &[Binding::Texture, Binding::StorageRo, Binding::Uniform],
                PREMULTIPLIED_OVER,
            ),
        })
    }

    /// The slab counts of the last frame, four u32 per pixel, row-major (occupancy-only: the total in the first):
    /// `n` of a pixel is their sum.
    pub fn read_slabs(&self, gpu: &Gpu) -> Result<Vec<[u32; 4]>, GpuError> {
        Ok(bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.maps.slabs)?))
    }
}

impl TransparencyGpu for OccupancyOrderGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.maps.resize(gpu, (width, height))?;
        self.accum.resize(&gpu.device, (width, height));
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let p = params(frame.values);
        let hair = &HAIR[usize::from(p.half_precision)];
        self.accum
            .set_format(&frame.gpu.device, 0, hair.targets[0].format);
        frame.gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&OccupancyOrderUniforms::new(&p, frame.model.hair_alpha)),
        );
        self.maps.record(frame, &self.uniforms);
        let maps_group = self.maps.group(&frame.gpu.device, &self.uniforms, None);
        frame.draw_hair(
            HairDrawPass {
                entry: hair,
                attachments: &self.accum.cleared(&[[0.0; 4]]),
                depth: None,
                group: Some((&self.maps.hair_layout, &maps_group)),
                rows: None,
            },
            "eye: hair",
        );
        self.resolve.record(
            frame,
            &[
                wgpu::BindingResource::TextureView(self.accum.view(0)),
                self.maps.slabs.as_entire_binding(),
                self.uniforms.as_entire_binding(),
            ],
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.maps.bytes() + self.accum.bytes()
    }

    fn geometry_passes(&self) -> u32 {
        3
    }
}

/// The slab counts of the last frame `renderer` drew with occupancy-order (see [`OccupancyOrderGpu::read_slabs`]).
pub fn read_slabs(renderer: &crate::render::Renderer) -> Result<Vec<[u32; 4]>, GpuError> {
    let state = renderer.transparency_gpu().map(|t| t as &dyn std::any::Any);
    state
        .and_then(|t| t.downcast_ref::<OccupancyOrderGpu>())
        .ok_or_else(|| {
            GpuError::Setting("transparency.name: the last frame was not drawn with occupancy-order".into())
        })?
        .read_slabs(renderer.gpu())
}
