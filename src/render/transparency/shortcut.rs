//! TressFX ShortCut-style blending (AMD TressFX; spec A.12): the K nearest fragments of each pixel blended
//! exactly, the rest as one weighted layer behind them. Pass 1 (`eye: k nearest`) keeps the K smallest depth keys
//! per pixel with an `atomicMin` insertion chain in a storage buffer (K words per pixel); pass 2, the shaded hair
//! entry, stores a fragment whose key is one of them in that key's slot and adds every other fragment to the
//! tail (additive `(a c, a)` RGBA32F and a revealage product R32F); the resolve blends the slots front to back,
//! then the tail, and resets the words and slots for the next frame. Both passes write storage, so they have no
//! depth attachment and test the meshes by hand. Two geometry passes, `20 K + 20` B per pixel.
//!
//! Equal keys: the depth pass gives each its own word; in pass 2 each fragment with that key takes the first
//! free one (`atomicExchange`), so equal-depth fragments in the K nearest are blended in the order they arrive,
//! not by segment as the model orders them, and where more share the K-th depth than words are left, which of
//! them stay in front is the arrival order too. CPU model: [`crate::transparency::ShortcutParams`].

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry,
    PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::{self, Resolve};
use crate::render::eye::pipelines::{self, additive, revealage};
use crate::render::eye::targets::{self, Textures};
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role, value};
use crate::transparency::shortcut::K_RANGE;
use crate::transparency::{Compositor, ModelContext, ShortcutParams};
use bytemuck::{Pod, Zeroable};

pub const TAIL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
pub const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Bytes per pixel and kept fragment: a key word and an RGBA32F slot.
const SLOT_BYTES: u64 = 4 + 16;

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[additive(TAIL, wgpu::ColorWrites::ALL), revealage(REVEALAGE)],
    depth: EntryDepth::Manual,
    geometry: HairGeometry::Lines,
};

const K: ParamSpec = ParamSpec {
    key: "k",
    label: "K nearest",
    help: "fragments per pixel blended exactly, nearest first (TressFX: 3); the rest form one averaged layer",
    kind: ParamKind::Int {
        min: K_RANGE[0] as i32,
        max: K_RANGE[1] as i32,
    },
    default: 3.0,
};
const FRONT: ParamSpec = ParamSpec {
    key: "front",
    label: "front blending",
    help: "ordered: the K nearest blended front to back; averaged: their weighted average, TressFX 4.x as shipped",
    kind: ParamKind::Choice {
        options: &["ordered", "averaged"],
    },
    default: 0.0,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "shortcut",
    label: "ShortCut (K nearest)",
    paper: "AMD TressFX 4, ShortCut; k-buffer front with an order-independent tail (Maule et al. 2013)",
    role: Role::Approximation,
    hair_wgsl: "transparency/shortcut.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &[
        "transparency/shortcut_depths.wgsl",
        "transparency/shortcut_resolve.wgsl",
    ],
    params: &[K, FRONT],
    color: [68, 170, 153],
    // f32 sums and products in another order only. Measured on lavapipe, 160x120 head (tests/it/transparency_gpu.rs):
    // 6.0e-8 at K = 1, 3 and 8, ordered and averaged (one pixel of 3489 has an exact depth tie among its 5
    // nearest; no pixel differed by more).
    gpu_tolerance: 1e-5,
};

/// The model's parameters from `values`.
fn params(values: &ParamValues) -> ShortcutParams {
    ShortcutParams {
        k: value(values, &K) as u32,
        average_front: value(values, &FRONT) >= 1.0,
    }
}

pub struct Shortcut;

impl EyeTransparency for Shortcut {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(ShortcutGpu::new(setup)?))
    }

    fn model(&self, values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(params(values))
    }

    fn uniform_mirror(&self) -> Option<crate::render::method::UniformMirror> {
        Some(crate::uniform_mirror!(
            "ShortcutUniforms",
            ShortcutUniforms {
                k,
                width,
                average_front,
                pad0
            }
        ))
    }
}

/// Mirrors `ShortcutUniforms` in `shaders/common/shortcut.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ShortcutUniforms {
    pub k: u32,
    pub width: u32,
    pub average_front: u32,
    pub pad0: u32,
}

/// The key words and slots of one viewport size and K.
struct Slots {
    keys: wgpu::Buffer,
    slots: wgpu::Buffer,
    size: (u32, u32),
    k: u32,
}

impl Slots {
    fn new(gpu: &Gpu, (width, height): (u32, u32), k: u32) -> Result<Slots, GpuError> {
        let words = width as u64 * height as u64 * k as u64;
        let buffer = |name, what, bytes| {
            let what = format!("ShortCut's {what} (K = {k}) at {width}x{height}");
            targets::storage(gpu, INFO.name, name, &what, bytes)
        };
        let keys = buffer("keys", "key words", words * 4)?;
        let slots = buffer("slots", "slots", words * 16)?;
        // Key words start empty (all ones) and slots at zero; each resolve resets them for the next frame.
        gpu.queue
            .write_buffer(&keys, 0, &vec![0xff; keys.size() as usize]);
        Ok(Slots {
            keys,
            slots,
            size: (width, height),
            k,
        })
    }
}

struct ShortcutGpu {
    uniforms: wgpu::Buffer,
    depths_layout: wgpu::BindGroupLayout,
    hair_layout: wgpu::BindGroupLayout,
    depths_pipeline: wgpu::RenderPipeline,
    resolve: Resolve,
    slots: Slots,
    /// The tail and its revealage.
    targets: Textures,
}

impl ShortcutGpu {
    fn new(setup: &EyeSetup) -> Result<ShortcutGpu, GpuError> {
        let device = &setup.gpu.device;
        use Binding::{MeshDepth, StorageRw, Texture, Uniform};
        let depths_layout = bindings::layout(
            device,
            "hairlab.shortcut.depths_layout",
            &[Uniform, StorageRw, MeshDepth],
        );
        let depths_pipeline = pipelines::storage_pass(
            device,
            "hairlab.shortcut.depths",
            INFO.pass_wgsl[0],
            [setup.frame_layout, &depths_layout],
            HairGeometry::Lines,
        );
        let size = (setup.width, setup.height);
        Ok(ShortcutGpu {
            uniforms: bindings::uniform(
                device,
                "hairlab.shortcut.uniforms",
                std::mem::size_of::<ShortcutUniforms>() as u64,
            ),
            depths_layout,
            hair_layout: bindings::layout(
                device,
                "hairlab.shortcut.hair_layout",
                &[Uniform, StorageRw, StorageRw, MeshDepth],
            ),
            depths_pipeline,
            resolve: Resolve::new(
                device,
                INFO.name,
                INFO.pass_wgsl[1],
                &[Uniform, StorageRw, StorageRw, Texture, Texture],
                PREMULTIPLIED_OVER,
            ),
            slots: Slots::new(setup.gpu, size, ShortcutParams::default().k)?,
            targets: Textures::new(
                device,
                INFO.name,
                &[("tail", TAIL), ("revealage", REVEALAGE)],
                size,
            ),
        })
    }

    /// Re-creates the key words and slots for `size` and `k` when either changed, and the targets for `size`.
    fn ensure(&mut self, gpu: &Gpu, size: (u32, u32), k: u32) -> Result<(), GpuError> {
        if (self.slots.size, self.slots.k) != (size, k) {
            self.slots = Slots::new(gpu, size, k)?;
        }
        self.targets.resize(&gpu.device, size);
        Ok(())
    }
}

impl TransparencyGpu for ShortcutGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.ensure(gpu, (width, height), self.slots.k)
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let p = params(frame.values);
        let k = p.k() as u32;
        self.ensure(frame.gpu, self.slots.size, k)?;
        let u = ShortcutUniforms {
            k,
            width: self.slots.size.0,
            average_front: u32::from(p.average_front),
            pad0: 0,
        };
        frame
            .gpu
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let device = &frame.gpu.device;
        let (uniforms, keys, slots) = (
            self.uniforms.as_entire_binding(),
            self.slots.keys.as_entire_binding(),
            self.slots.slots.as_entire_binding(),
        );
        let mesh_depth = wgpu::BindingResource::TextureView(&frame.targets.depth_view);
        let depths_group = bindings::group(
            device,
            "hairlab.shortcut.depths_group",
            &self.depths_layout,
            &[uniforms.clone(), keys.clone(), mesh_depth.clone()],
        );
        let hair_group = bindings::group(
            device,
            "hairlab.shortcut.hair_group",
            &self.hair_layout,
            &[uniforms.clone(), keys.clone(), slots.clone(), mesh_depth],
        );
        passes::record_line_count(
            frame,
            "hairlab.shortcut.depths_pass",
            "eye: k nearest",
            &self.depths_pipeline,
            &depths_group,
        );
        let [tail, revealage] = [0, 1].map(|i| self.targets.view(i));
        frame.draw_hair(
            HairDrawPass {
                entry: &HAIR,
                // Nothing in the tail, everything revealed.
                attachments: &self.targets.cleared(&[[0.0; 4], [1.0, 0.0, 0.0, 0.0]]),
                depth: None,
                group: Some((&self.hair_layout, &hair_group)),
                rows: None,
            },
            "eye: hair",
        );
        self.resolve.record(
            frame,
            &[
                uniforms,
                keys,
                slots,
                wgpu::BindingResource::TextureView(tail),
                wgpu::BindingResource::TextureView(revealage),
            ],
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let (width, height) = self.slots.size;
        let pixels = width as u64 * height as u64;
        pixels * self.slots.k as u64 * SLOT_BYTES + self.targets.bytes() + self.uniforms.size()
    }

    fn geometry_passes(&self) -> u32 {
        2
    }
}
