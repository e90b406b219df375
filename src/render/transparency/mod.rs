//! The eye transparency contract: how the hair pass stores its shaded fragments and how they are resolved onto
//! the opaque colour image. A technique is a constant description ([`TechniqueInfo`]: its store function, its
//! resolve shader, the hair pass's colour targets) and a GPU state ([`TransparencyGpu`]: its targets, sized to
//! the viewport, and its resolve pass). The renderer defines the contract and holds one technique's state at a
//! time; `registry.rs` is the one list of techniques.
//!
//! The store function, pasted into `hair.wgsl` at `#include_technique` (as a method's lookup is pasted at
//! `#include_method`), defines the hair pass's fragment outputs and fills them from one shaded fragment:
//!
//! ```wgsl
//! struct HairOutput { @location(0) ..., }
//! // color: shaded linear radiance (not premultiplied); alpha: coverage in [0, 1]; depth: distance from the eye
//! // in units of the camera-to-target distance (scale-free, 1 at the orbit target).
//! fn store_hair(color: vec3<f32>, alpha: f32, depth: f32) -> HairOutput
//! ```

pub mod registry;
pub mod wboit;

/// A technique's constants: the registry, the pipelines and the tests read them.
#[derive(Debug)]
pub struct TechniqueInfo {
    /// Stable identifier used in `render.transparency` (kebab-case).
    pub name: &'static str,
    /// Human-readable name for the UI.
    pub label: &'static str,
    /// The paper the technique follows.
    pub paper: &'static str,
    /// The WGSL file under `shaders/` defining `struct HairOutput` and `fn store_hair` (see the module docs).
    pub store_wgsl: &'static str,
    /// The WGSL pass under `shaders/` of the resolve onto the colour image.
    pub resolve_wgsl: &'static str,
    /// Colour target states (formats, blending, write masks) of the hair pass, in `HairOutput`'s location order.
    pub hair_targets: &'static [wgpu::ColorTargetState],
}

/// What the renderer asks of an eye transparency technique.
pub trait EyeTransparency: Sync {
    fn info(&self) -> &'static TechniqueInfo;
    fn name(&self) -> &'static str {
        self.info().name
    }
    /// Creates the technique's targets for a `width`×`height` viewport and its resolve pass.
    fn create_gpu(&self, device: &wgpu::Device, width: u32, height: u32) -> Box<dyn TransparencyGpu>;
}

/// A technique's GPU side: its eye targets and its resolve.
pub trait TransparencyGpu: Send {
    /// Re-creates the targets for a `width`×`height` viewport (nothing when the size is unchanged).
    fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32);
    /// The hair pass's colour attachments, cleared for a new frame, in [`TechniqueInfo::hair_targets`] order.
    fn hair_attachments(&self) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>>;
    /// Records the resolve of the hair pass's targets onto `color` (the opaque image of the mesh pass).
    fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    );
    /// GPU memory held by the targets, in bytes.
    fn memory_bytes(&self) -> u64;
}
