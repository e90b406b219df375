//! The eye transparency contract: how a technique turns the shaded hair fragments of the eye view into the final
//! image over the opaque meshes. A technique is a constant description ([`TechniqueInfo`]), a CPU model (its
//! [`Compositor`], the specification in `crate::transparency`) and a GPU state ([`TransparencyGpu`]) that records
//! the technique's passes into an [`EyeFrame`]: its own geometry passes over the strands (depth ranges, counts,
//! occupancy), shaded hair passes drawn through [`HairDraw`] and its resolve onto the colour image. The renderer
//! defines the contract and holds one technique's state at a time; `registry.rs` is the one list of techniques.
//! Techniques build their passes from the eye toolkit ([`crate::render::eye`]: declared bindings, base pipeline
//! descriptors, per-pixel lists). A scene's fur is content of the scene that only a technique which
//! [`EyeTransparency::shows_fur`] draws (the fur's typed lists, `crate::render::fur::typed`); the renderer refuses
//! a scene with fur to any other, naming the one that shows it.
//!
//! A technique's hair file (`TechniqueInfo::hair_wgsl`) is pasted into `hair.wgsl` at `#include_technique` and
//! defines the hair pass's fragment entry points. Each calls `shade_hair(in)` (hair.wgsl) for the shaded
//! fragment:
//!
//! ```wgsl
//! struct ShadedHair {
//!     color: vec3<f32>,   // shaded linear radiance (not premultiplied)
//!     alpha: f32,         // coverage in [0, 1]
//!     depth: f32,         // distance from the eye in units of the camera-to-target distance
//!     segment: u32,       // the segment id (index of its first point)
//!     pixel: vec2<u32>,
//! }
//! ```
//!
//! The technique's own geometry passes use `common/eye_vertex.wgsl`, the vertex stage the hair pass shares, so
//! every eye pass sees bitwise the same fragments (positions, depths, segment ids): `eye_vertex` for an entry
//! drawn as [`HairGeometry::Lines`], `eye_ribbon_point` for one drawn as [`HairGeometry::Ribbons`].

pub mod depth_peel;
pub mod mboit;
pub mod occupancy_order;
pub mod opaque;
pub mod registry;
pub mod shortcut;
pub mod sorted;
pub mod wboit;
pub mod weighted_average;

use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError};
use crate::render::fur::state::{FurState, SceneFur};
use crate::render::method::{ParamSpec, ParamValues, Role, UniformMirror};
pub use crate::render::passes::hair::{EntryDepth, HairDrawPass, HairEntry, HairGeometry};
use crate::render::passes::hair::{HairPass, HairScene};
use crate::render::scene_gpu::SceneGpu;
use crate::render::targets::EyeTargets;
use crate::scene::Light;
use crate::transparency::{Compositor, EyeFragment, ModelContext};

/// A technique's constants: the registry, the panel, the pipelines and the tests read them.
#[derive(Debug)]
pub struct TechniqueInfo {
    /// Stable identifier used in `transparency.name` (kebab-case).
    pub name: &'static str,
    /// Human-readable name for the UI.
    pub label: &'static str,
    /// The paper the technique follows.
    pub paper: &'static str,
    pub role: Role,
    /// The WGSL file under `shaders/` pasted into `hair.wgsl` at `#include_technique`: its hair fragment entries.
    pub hair_wgsl: &'static str,
    /// The technique's hair fragment entry points and the colour targets of each (in location order).
    pub hair_entries: &'static [HairEntry],
    /// The WGSL passes under `shaders/` of its own passes (geometry passes over the strands, the resolve).
    pub pass_wgsl: &'static [&'static str],
    pub params: &'static [ParamSpec],
    /// Colour in the charts (sRGB).
    pub color: [u8; 3],
    /// Largest per-channel |C_gpu - C_cpu| (linear) the GPU = CPU test allows, stated per technique.
    pub gpu_tolerance: f32,
}

/// What the renderer asks of an eye transparency technique.
pub trait EyeTransparency: Sync {
    fn info(&self) -> &'static TechniqueInfo;
    fn name(&self) -> &'static str {
        self.info().name
    }
    /// Creates the technique's GPU state for a `width`×`height` viewport.
    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError>;
    /// The CPU model with `values` (missing keys take their defaults).
    fn model(&self, values: &ParamValues, ctx: &ModelContext) -> Box<dyn Compositor>;
    /// The configurations `bench transparency` measures (the defaults unless a technique has more to show).
    fn sweep(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
    /// The technique's own uniform struct and its WGSL twin in its passes (`None` when it has none).
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        None
    }
    /// Whether the technique shows a scene's fur ([`EyeSetup::scene_fur`]); the renderer refuses a scene with fur
    /// to a technique that does not, naming one that does.
    fn shows_fur(&self) -> bool {
        false
    }
}

/// What a technique's GPU state is created from.
pub struct EyeSetup<'a> {
    pub gpu: &'a Gpu,
    /// Group 0 of the technique's own geometry passes (the frame uniforms).
    pub frame_layout: &'a wgpu::BindGroupLayout,
    pub width: u32,
    pub height: u32,
    /// The scene's fur, when it has one: content of the scene, shown by a technique that [`shows_fur`]
    /// (`EyeTransparency::shows_fur`), which builds what it needs from it.
    ///
    /// [`shows_fur`]: EyeTransparency::shows_fur
    pub scene_fur: Option<&'a SceneFur>,
}

/// A technique's GPU side.
pub trait TransparencyGpu: Send + std::any::Any {
    /// Re-creates the viewport-sized resources for `width`×`height` (nothing when the size is unchanged).
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError>;
    /// Brings the state up to `setup` before a frame: its size, and for a technique that shows fur the scene's
    /// fur (nothing re-created that did not change).
    fn update(&mut self, setup: &EyeSetup) -> Result<(), GpuError> {
        self.resize(setup.gpu, setup.width, setup.height)
    }
    /// Records the technique's passes of one frame: after the meshes, before the frame is submitted.
    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError>;
    /// GPU memory held, in bytes (viewport-sized targets and per-fragment buffers).
    fn memory_bytes(&self) -> u64;
    /// Geometry passes over the strands in the last frame recorded.
    fn geometry_passes(&self) -> u32;
    /// The last frame's per-pixel fragment lists (row-major, each front to back on (depth, segment)), for a
    /// technique that keeps them (the exact reference); an error when they cannot be read whole.
    fn read_lists(&self, _gpu: &Gpu) -> Option<Result<Vec<Vec<EyeFragment>>, GpuError>> {
        None
    }
    /// The last frame's eye depth complexity (deepest pixel, total fragments), for a technique that counts it.
    fn depth_complexity(&self) -> Option<(u32, u64)> {
        None
    }
    /// The fur the state shows (its shell, its last frame's typed lists), for a technique that shows fur.
    fn fur(&self) -> Option<FurState<'_>> {
        None
    }
}

/// One frame of the eye view as a technique records it.
pub struct EyeFrame<'a> {
    pub gpu: &'a Gpu,
    /// The frame's encoder (light passes and meshes already recorded); [`EyeFrame::flush`] submits it.
    pub encoder: wgpu::CommandEncoder,
    pub timer: &'a mut Option<GpuTimer>,
    /// Group 0 of the technique's geometry passes.
    pub frame_bind_group: &'a wgpu::BindGroup,
    pub geometry: &'a SceneGpu,
    /// The colour image (the opaque meshes) and the meshes' depth.
    pub targets: &'a EyeTargets,
    /// Where the resolve draws, and its format: the colour image, or the capture target
    /// ([`crate::render::targets::CAPTURE_FORMAT`], cleared to zero) when the frame is captured.
    pub output: (&'a wgpu::TextureView, wgpu::TextureFormat),
    pub values: &'a ParamValues,
    pub model: ModelContext,
    /// The frame's light (a technique that marches a volume lights it).
    pub light: &'a Light,
    pub hair: HairDraw<'a>,
}

impl EyeFrame<'_> {
    /// Timestamp writes for the next render pass, of `phase`, named `name`.
    pub fn timestamps(&mut self, phase: Phase, name: &str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.timer.as_mut().and_then(|t| t.pass(phase, name))
    }

    /// Submits what is recorded so far and starts a new encoder: for a technique that reads back a count
    /// before sizing its buffers. The frame's timestamps are resolved with the last encoder.
    pub fn flush(&mut self) {
        let next = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.frame.encoder"),
            });
        let done = std::mem::replace(&mut self.encoder, next);
        self.gpu.queue.submit([done.finish()]);
    }

    /// Records a shaded hair draw without a timer entry of its own (a technique timing many passes as one
    /// `GpuTimer::span`).
    pub fn draw_hair_untimed(&mut self, draw: HairDrawPass<'_>) {
        self.hair.record(&mut self.encoder, draw, None);
    }

    /// Records a shaded hair draw of entry `entry` (one of the technique's [`HairEntry`]s).
    pub fn draw_hair(&mut self, draw: HairDrawPass<'_>, timestamp: &str) {
        let timestamps = self
            .timer
            .as_mut()
            .and_then(|t| t.pass(Phase::EyeHair, timestamp));
        self.hair.record(&mut self.encoder, draw, timestamps);
    }
}

/// What the renderer lends a technique to draw shaded hair: the shadow method, the scene and the hair pass.
pub struct HairDraw<'a> {
    pub(crate) pass: &'a mut HairPass,
    pub(crate) scene: HairScene<'a>,
}

impl HairDraw<'_> {
    fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        draw: HairDrawPass<'_>,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        self.pass.record(&self.scene, encoder, draw, timestamps)
    }
}

/// A colour attachment cleared to `clear` and stored.
pub fn cleared(view: &wgpu::TextureView, clear: [f64; 4]) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color {
                r: clear[0],
                g: clear[1],
                b: clear[2],
                a: clear[3],
            }),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// Blend of the additive float targets (One/One on colour and alpha).
pub const ADDITIVE: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// Blend of a resolve that outputs `(H, 1 - T)`, premultiplied hair colour `H` and transmittance `T`:
/// `C = H + T · B` over the opaque image `B`.
pub const PREMULTIPLIED_OVER: wgpu::BlendState = wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING;
