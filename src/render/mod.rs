//! The renderer: light passes, the selected shadow method, the eye passes and the selected eye transparency
//! technique's resolve, into one colour texture that the window shows and screenshots save. The GUI and
//! `hairlab render` use the same code path.

pub mod caster;
pub mod eye;
pub mod frame;
pub mod frame_bindings;
pub mod fur;
pub mod geometry;
pub mod inspect;
pub mod light_frame;
pub mod maps;
pub mod memory;
pub mod method;
pub mod passes;
pub mod pipelines;
pub mod render_settings;
pub mod scene_gpu;
pub mod targets;
pub mod transparency;
pub mod uniforms;

use crate::gpu::timing::{GpuTimer, PassTime, Phase};
use crate::gpu::{Gpu, GpuError, readback};
use crate::scene::{Camera, Light, Scene};
use frame_bindings::FrameBindings;
use glam::{Mat4, Vec3};
use light_frame::LightFrame;
use method::{LightMethod, MethodContext, MethodGpu};
use passes::depth_peel::DepthPeel;
use passes::hair::HairPass;
use passes::light_depth::{LightDepthMaps, LightDepthPass};
use passes::mesh::MeshPass;
use passes::shadow_map::{ShadowMap, ShadowMapPass};
use scene_gpu::SceneGpu;

pub use frame::{FrameInput, footprint_per_w};
pub use memory::{Creations, MemoryReport};
pub use render_settings::{AlphaMode, DEFAULT_STRAND_WIDTH, RenderSettings};
use targets::EyeTargets;
use transparency::{EyeTransparency, TransparencyGpu};
use uniforms::FrameUniforms;

/// The held method state if it is `method`'s, or an error saying that `method` is not the last frame's.
fn held<'a>(
    state: &'a Option<(&'static str, Box<dyn MethodGpu>)>,
    method: &dyn LightMethod,
) -> Result<&'a dyn MethodGpu, GpuError> {
    state
        .as_ref()
        .filter(|(n, _)| *n == method.name())
        .map(|(_, m)| m.as_ref())
        .ok_or_else(|| {
            GpuError::Readback(format!(
                "method '{}' is not the method of the last frame rendered",
                method.name()
            ))
        })
}

/// Side of the opaque meshes' shadow map.
pub const SHADOW_MAP_RESOLUTION: u32 = 2048;

pub struct Renderer {
    gpu: Gpu,
    /// Group 0 of every pass and the eye passes' scene group.
    bindings: FrameBindings,
    /// Group [`geometry::RIBBON_GROUP`] of the ribbon pipelines, shared by every scene's geometry.
    ribbon_layout: wgpu::BindGroupLayout,
    scene: SceneGpu,
    light_depth: LightDepthPass,
    light_maps: LightDepthMaps,
    shadow_map_pass: ShadowMapPass,
    shadow_map: ShadowMap,
    mesh_pass: MeshPass,
    hair_pass: HairPass,
    evaluate: passes::evaluate::EvaluatePass,
    /// The GPU state of the method of the last frame; another method evicts it.
    method: Option<(&'static str, Box<dyn MethodGpu>)>,
    /// The targets and resolve of the eye transparency technique of the last frame; another technique evicts
    /// them.
    transparency: Option<(&'static str, Box<dyn TransparencyGpu>)>,
    /// The exact reference's fragment lists ([`Renderer::reference_lists`]), created on first use.
    reference: Option<passes::abuffer::ABuffer>,
    peel: Option<DepthPeel>,
    /// The float target of [`Renderer::render_capture`], created on first use.
    capture: Option<wgpu::Texture>,
    targets: EyeTargets,
    targets_generation: u64,
    timer: Option<GpuTimer>,
    creations: Creations,
    /// The scene's fur ([`Renderer::set_fur`]): scene content that a technique which shows fur builds its GPU
    /// state from; a technique that cannot show it is refused.
    fur: Option<fur::state::SceneFur>,
    fur_generation: u64,
}

impl Renderer {
    pub fn new(gpu: &Gpu, scene: &Scene, map_resolution: u32) -> Result<Renderer, GpuError> {
        let device = &gpu.device;
        gpu.check_texture_size("light map", map_resolution)?;
        let light_maps = LightDepthMaps::new(device, map_resolution);
        let shadow_map = ShadowMap::new(
            device,
            SHADOW_MAP_RESOLUTION.min(device.limits().max_texture_dimension_2d),
        );
        let bindings = FrameBindings::new(device, &light_maps, &shadow_map);
        let targets = EyeTargets::new(device, 16, 16);
        let ribbon_layout = geometry::ribbon_layout(device);
        let scene = SceneGpu::upload(gpu, scene, &ribbon_layout)?;
        Ok(Renderer {
            gpu: gpu.clone(),
            light_depth: LightDepthPass::new(device, &bindings.frame_layout),
            shadow_map_pass: ShadowMapPass::new(device, &bindings.frame_layout),
            mesh_pass: MeshPass::new(&bindings.scene_layout),
            hair_pass: HairPass::new(&bindings.scene_layout),
            evaluate: passes::evaluate::EvaluatePass::new(device, &bindings.scene_layout),
            method: None,
            transparency: None,
            capture: None,
            reference: None,
            peel: None,
            targets_generation: 0,
            fur: None,
            fur_generation: 0,
            timer: GpuTimer::new(device, &gpu.queue),
            creations: Creations {
                scene_uploads: 1,
                ..Creations::default()
            },
            bindings,
            ribbon_layout,
            scene,
            light_maps,
            shadow_map,
            targets,
        })
    }

    /// Replaces the scene (buffers re-sized from the new scene, a new generation).
    pub fn set_scene(&mut self, scene: &Scene) -> Result<(), GpuError> {
        self.scene = SceneGpu::upload(&self.gpu, scene, &self.ribbon_layout)?;
        self.creations.scene_uploads += 1;
        Ok(())
    }

    /// Moves the strands' points ([`SceneGpu::update_points`], the one write path for moving hair): the next
    /// frame draws them, with every light frame and map refitted, and nothing re-created.
    pub fn update_points(&mut self, points: &[Vec3]) -> Result<(), GpuError> {
        Ok(self.scene.update_points(&self.gpu, points)?)
    }

    /// The bound [`crate::scene::LightFit::Bound`] fits the hair maps to ([`SceneGpu::set_fit_bound`]).
    pub fn set_fit_bound(&mut self, bound: Option<crate::scene::Aabb>) {
        self.scene.set_fit_bound(bound);
    }

    /// The scene's generation ([`SceneGpu::generation`]): what caches of the geometry key on.
    pub fn scene_generation(&self) -> u64 {
        self.scene.generation()
    }

    /// How many GPU states the renderer has created so far, by kind.
    pub fn creations(&self) -> Creations {
        Creations {
            pipelines: self.mesh_pass.pipelines_built() + self.hair_pass.pipelines_built(),
            ..self.creations
        }
    }

    fn ensure_map_size(&mut self, map_resolution: u32) -> Result<(), GpuError> {
        let device = &self.gpu.device;
        if self.light_maps.near.width() != map_resolution {
            self.gpu.check_texture_size("light map", map_resolution)?;
            self.light_maps = LightDepthMaps::new(device, map_resolution);
            self.bindings
                .rebind_scene(device, &self.light_maps, &self.shadow_map);
        }
        Ok(())
    }

    fn ensure_eye_size(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        if self.targets.width != width || self.targets.height != height {
            self.gpu.check_texture_size("viewport", width.max(height))?;
            self.targets = EyeTargets::new(&self.gpu.device, width, height);
            self.targets_generation += 1;
        }
        Ok(())
    }

    /// Gives the scene `fur` (its shell, volume and settings; `None`, or a mode of off: no fur). The technique
    /// that shows fur builds its GPU state from it at the next frame; a frame with another technique is refused.
    pub fn set_fur(
        &mut self,
        fur: Option<(
            &crate::fur::settings::FurScene,
            &crate::fur::settings::FurSettings,
        )>,
    ) -> Result<(), GpuError> {
        self.fur = fur
            .filter(|(_, s)| s.mode != crate::fur::settings::FurMode::Off)
            .map(|(scene, settings)| {
                self.fur_generation += 1;
                fur::state::SceneFur {
                    scene: scene.clone(),
                    settings: settings.clone(),
                    generation: self.fur_generation,
                }
            });
        Ok(())
    }

    /// Changes the fur's rendering (mode, blending, `a`, `k`, march) without rebuilding its shell: the caller keeps
    /// the shell's own settings (height, layers, levels, noise) those it was built with.
    pub fn set_fur_rendering(&mut self, settings: &crate::fur::settings::FurSettings) {
        if let Some(f) = &mut self.fur {
            f.settings = settings.clone();
        }
    }

    /// The fur the last frame's technique shows (its shell, its last lists, the volume's build time).
    pub fn fur_state(&self) -> Option<fur::state::FurState<'_>> {
        self.transparency.as_ref().and_then(|(_, t)| t.fur())
    }

    /// Makes the held technique state `technique`'s, sized to the eye targets.
    fn ensure_technique(&mut self, technique: &dyn EyeTransparency) -> Result<(), GpuError> {
        let (width, height) = (self.targets.width, self.targets.height);
        match &mut self.transparency {
            Some((name, state)) if *name == technique.name() => state.update(&transparency::EyeSetup {
                gpu: &self.gpu,
                frame_layout: &self.bindings.frame_layout,
                width,
                height,
                scene_fur: self.fur.as_ref(),
            }),
            _ => {
                // Evict the previous technique's state before the new technique allocates its own.
                self.transparency = None;
                let setup = transparency::EyeSetup {
                    gpu: &self.gpu,
                    frame_layout: &self.bindings.frame_layout,
                    width,
                    height,
                    scene_fur: self.fur.as_ref(),
                };
                self.transparency = Some((technique.name(), technique.create_gpu(&setup)?));
                self.creations.technique_states += 1;
                self.hair_pass.forget_technique(technique.name());
                Ok(())
            }
        }
    }

    /// Increases whenever the output texture is re-created (a viewer must re-register it).
    pub fn targets_generation(&self) -> u64 {
        self.targets_generation
    }

    /// `[near, far]` of the strands' distances from `camera`'s eye ([`frame::eye_depth_range`]).
    pub fn eye_depth_range(&self, camera: &Camera) -> [f32; 2] {
        frame::eye_depth_range(&self.scene, camera)
    }

    /// The light frame of the hair maps under `light.fit` ([`frame::hair_light_frame`]).
    pub fn hair_light_frame(&self, light: &Light) -> LightFrame {
        frame::hair_light_frame(&self.scene, light)
    }

    /// Camera matrices for an image of `width`×`height`.
    pub fn world_to_clip(&self, camera: &Camera, width: u32, height: u32) -> Mat4 {
        frame::world_to_clip(&self.scene, camera, width, height)
    }

    fn frame_uniforms(
        &self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
        size: (u32, u32),
        method_params: [f32; 4],
    ) -> FrameUniforms {
        frame::uniforms(
            &self.scene,
            &frame::UniformInputs {
                camera,
                light,
                render,
                size,
                method_params,
                light_map_resolution: self.light_maps.near.width(),
                shadow_map_resolution: self.shadow_map.texture.width(),
            },
        )
    }

    fn uniforms(&self, f: &FrameInput) -> FrameUniforms {
        self.frame_uniforms(
            f.camera,
            f.light,
            f.render,
            (f.width, f.height),
            f.method.uniform_params(f.method_params),
        )
    }

    /// Records and submits one frame. Timings of earlier frames become available through [`Renderer::timings`].
    pub fn render(&mut self, f: &FrameInput) -> Result<(), GpuError> {
        self.render_frame(f, false)
    }

    /// Renders `f` with the technique's resolve drawn onto a float target cleared to zero instead of the colour
    /// image, and reads it back: per pixel the hair's premultiplied colour `H` and coverage `1 - T` (row-major),
    /// what the technique's CPU model gives over black (`H`) and white (`H + T`). The colour image holds the
    /// opaque meshes alone afterwards ([`Renderer::read_output`]: the background each pixel's hair is over).
    pub fn render_capture(&mut self, f: &FrameInput) -> Result<Vec<[f32; 4]>, GpuError> {
        self.render_frame(f, true)?;
        let Some(capture) = &self.capture else {
            return Err(GpuError::Readback("no capture target".into()));
        };
        let bytes = readback::read_texture(&self.gpu, capture, 16)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    fn render_frame(&mut self, f: &FrameInput, capture: bool) -> Result<(), GpuError> {
        self.ensure_eye_size(f.width.max(1), f.height.max(1))?;
        let technique = f.technique;
        if let Some(fur) = self.fur.as_ref().filter(|_| !technique.shows_fur()) {
            return Err(GpuError::Setting(format!(
                "transparency.name: the scene has fur (fur.mode = {}) and '{}' cannot show it; choose '{}'",
                fur.settings.mode.word(),
                technique.name(),
                transparency::registry::fur().name()
            )));
        }
        self.ensure_technique(technique)?;
        let mut enc = self.record_light_passes(f)?;
        let device = self.gpu.device.clone();
        let method_gpu = held(&self.method, f.method)?;
        self.mesh_pass.record(
            &device,
            &mut enc,
            f.method,
            method_gpu,
            &self.targets,
            f.render.background,
            &self.bindings.scene_group,
            &self.scene,
            ts(&mut self.timer, Phase::Meshes, "eye: meshes"),
        );
        let model = crate::transparency::ModelContext {
            hair_alpha: f.render.hair_alpha,
            depth_range: self.eye_depth_range(f.camera),
        };
        if capture {
            let size = (self.targets.width, self.targets.height);
            if self
                .capture
                .as_ref()
                .is_none_or(|c| (c.width(), c.height()) != size)
            {
                self.capture = Some(targets::eye_texture(
                    &device,
                    "hairlab.eye.capture",
                    size,
                    targets::CAPTURE_FORMAT,
                    wgpu::TextureUsages::COPY_SRC,
                    &[],
                ));
            }
        }
        let capture_view = self
            .capture
            .as_ref()
            .filter(|_| capture)
            .map(|c| c.create_view(&Default::default()));
        if let Some(view) = &capture_view {
            enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlab.eye.capture_clear"),
                color_attachments: &[transparency::cleared(view, [0.0; 4])],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        }
        let output = match &capture_view {
            Some(v) => (v, targets::CAPTURE_FORMAT),
            None => (&self.targets.color_view, EyeTargets::COLOR),
        };
        let Some((_, technique_gpu)) = self.transparency.as_mut() else {
            return Err(GpuError::Setting(format!(
                "transparency.name: no state for '{}'",
                technique.name()
            )));
        };
        let mut frame = transparency::EyeFrame {
            gpu: &self.gpu,
            encoder: enc,
            timer: &mut self.timer,
            frame_bind_group: &self.bindings.frame_group,
            geometry: &self.scene,
            targets: &self.targets,
            output,
            values: f.technique_params,
            model,
            light: f.light,
            hair: transparency::HairDraw {
                pass: &mut self.hair_pass,
                scene: passes::hair::HairScene {
                    device: &device,
                    method: f.method,
                    method_gpu,
                    technique: passes::hair::HairTechnique {
                        name: technique.name(),
                        hair_wgsl: technique.info().hair_wgsl,
                    },
                    scene: &self.bindings.scene_group,
                    geometry: &self.scene,
                    targets: &self.targets,
                },
            },
        };
        let recorded = technique_gpu.record(&mut frame);
        let enc = frame.encoder;
        self.submit(enc);
        recorded
    }

    /// Renders only the light-space side of a frame (light depth, mesh shadow map, the method's maps) and
    /// submits it: what [`Renderer::evaluate`] and the reference read.
    pub fn render_light(&mut self, f: &FrameInput) -> Result<(), GpuError> {
        let enc = self.record_light_passes(f)?;
        self.submit(enc);
        Ok(())
    }

    fn submit(&mut self, mut enc: wgpu::CommandEncoder) {
        if let Some(t) = self.timer.as_mut() {
            t.resolve(&mut enc);
        }
        self.gpu.queue.submit([enc.finish()]);
        if let Some(t) = self.timer.as_mut() {
            t.after_submit();
        }
    }

    fn record_light_passes(&mut self, f: &FrameInput) -> Result<wgpu::CommandEncoder, GpuError> {
        self.ensure_map_size(f.render.map_resolution)?;
        let u = self.uniforms(f);
        self.gpu
            .queue
            .write_buffer(&self.bindings.buffer, 0, bytemuck::bytes_of(&u));
        let device = self.gpu.device.clone();
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.frame.encoder"),
        });
        self.light_depth.record(
            &mut enc,
            &self.light_maps,
            &self.bindings.frame_group,
            &self.scene.casters(),
            ts(&mut self.timer, Phase::SharedLight, "light depth"),
        );
        self.shadow_map_pass.record(
            &mut enc,
            &self.shadow_map,
            &self.bindings.frame_group,
            &self.scene,
            ts(&mut self.timer, Phase::SharedLight, "mesh shadow map"),
        );
        let gpu = self.gpu.clone();
        let casters = self.scene.casters();
        let ctx = MethodContext {
            gpu: &gpu,
            frame_layout: &self.bindings.frame_layout,
            frame_bind_group: &self.bindings.frame_group,
            casters: &casters,
            light_maps: &self.light_maps,
            values: f.method_params,
            hair_alpha: f.render.hair_alpha,
        };
        let name = f.method.name();
        if self.method.as_ref().is_none_or(|(n, _)| *n != name) {
            // Evict the previous method's maps before the new method allocates its own.
            self.method = None;
            self.method = Some((name, f.method.create_gpu(&ctx)?));
            self.creations.method_states += 1;
        }
        if let Some((_, state)) = &mut self.method {
            state.prepare(&ctx, &mut self.timer)?;
            state.record(&ctx, &mut enc, &mut self.timer);
        }
        Ok(enc)
    }

    /// Newest per-pass GPU times (non-blocking; empty without timestamp support).
    pub fn timings(&mut self) -> Vec<PassTime> {
        match self.timer.as_mut() {
            Some(t) => t.poll(&self.gpu.device).to_vec(),
            None => Vec::new(),
        }
    }

    /// Waits for the GPU and returns the last frame's per-pass times.
    pub fn wait_timings(&mut self) -> Vec<PassTime> {
        match self.timer.as_mut() {
            Some(t) => t.wait(&self.gpu.device).to_vec(),
            None => Vec::new(),
        }
    }

    /// The final image of the last frame (Rgba8UnormSrgb).
    pub fn output(&self) -> &wgpu::Texture {
        &self.targets.color
    }

    /// The final image as egui should sample it (sRGB bytes, no decode).
    pub fn display_view(&self) -> &wgpu::TextureView {
        &self.targets.display_view
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Side of the hair light maps.
    pub fn map_resolution(&self) -> u32 {
        self.light_maps.near.width()
    }

    /// The scene on the GPU: buffers, bounds, generation.
    pub fn scene_gpu(&self) -> &SceneGpu {
        &self.scene
    }

    /// The eye image's size.
    pub fn eye_size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }

    pub fn segment_count(&self) -> usize {
        self.scene.segment_count()
    }

    /// The layout the light passes bind (the frame uniforms alone).
    pub fn frame_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bindings.frame_layout
    }
}

/// Timestamp writes for the next pass, when timing is on.
fn ts<'a>(
    timer: &'a mut Option<GpuTimer>,
    phase: Phase,
    name: &str,
) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
    timer.as_mut().and_then(|t| t.pass(phase, name))
}
