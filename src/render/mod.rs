//! The renderer: light passes, the selected shadow method, the eye passes and the selected eye transparency
//! technique's resolve, into one colour texture that the window shows and screenshots save. The GUI and
//! `hairlab render` use the same code path.
//!
//! This file is the frame, top down ([`Renderer::render`]): the uniforms, the light side ([`light`]: light
//! depth, the meshes' shadow map, the method's passes, all built for the frame's light caster), the opaque meshes,
//! then the technique's passes and resolve over the eye targets. What the renderer is asked or read back lives in
//! [`inspect`]; the scene's fur as input in [`fur`].

pub mod caster;
pub mod eye;
pub mod frame;
pub mod frame_bindings;
pub mod fur;
pub mod geometry;
pub mod inspect;
pub mod light;
pub mod maps;
pub mod memory;
pub mod method;
pub mod passes;
pub mod pipelines;
pub mod probe_cache;
pub mod render_settings;
pub mod scene_gpu;
pub mod targets;
pub mod transparency;
pub mod uniforms;

use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError, readback};
use crate::scene::{Camera, Light, Scene};
use frame_bindings::FrameBindings;
use glam::Vec3;
use light::LightSide;
use passes::hair::HairPass;
use passes::light_depth::LightDepthMaps;
use passes::mesh::MeshPass;
use scene_gpu::SceneGpu;

pub use frame::{FrameInput, footprint_per_w};
pub use light::SHADOW_MAP_RESOLUTION;
pub use memory::{Creations, MemoryReport};
pub use render_settings::{AlphaMode, DEFAULT_STRAND_WIDTH, LightStrands, Raster, RenderSettings};
use targets::EyeTargets;
use transparency::{EyeTransparency, TransparencyGpu};
use uniforms::FrameUniforms;

pub struct Renderer {
    gpu: Gpu,
    /// Group 0 of every pass and the eye passes' scene group.
    bindings: FrameBindings,
    /// Group [`geometry::RIBBON_GROUP`] of the ribbon pipelines, shared by every scene's geometry.
    ribbon_layout: wgpu::BindGroupLayout,
    scene: SceneGpu,
    /// Light depth, the meshes' shadow map, the method's maps and the reference's passes.
    light: LightSide,
    mesh_pass: MeshPass,
    hair_pass: HairPass,
    evaluate: passes::evaluate::EvaluatePass,
    /// The targets and resolve of the eye transparency technique of the last frame; another technique evicts
    /// them.
    transparency: Option<(&'static str, Box<dyn TransparencyGpu>)>,
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
    /// Whether the path-traced probe is baked on another thread ([`Renderer::set_background_probes`]).
    background_probes: bool,
}

impl Renderer {
    pub fn new(gpu: &Gpu, scene: &Scene, map_resolution: u32) -> Result<Renderer, GpuError> {
        let device = &gpu.device;
        let maps = LightSide::maps(gpu, map_resolution)?;
        let bindings = FrameBindings::new(device, &gpu.queue, &maps.0, &maps.1);
        let targets = EyeTargets::new(device, 16, 16);
        let ribbon_layout = geometry::ribbon_layout(device);
        let scene = SceneGpu::upload(gpu, scene, &ribbon_layout)?;
        Ok(Renderer {
            gpu: gpu.clone(),
            light: LightSide::new(device, &bindings.frame_layout, &ribbon_layout, maps),
            mesh_pass: MeshPass::new(&bindings.scene_layout),
            hair_pass: HairPass::new(&bindings.scene_layout),
            evaluate: passes::evaluate::EvaluatePass::new(device, &bindings.scene_layout),
            transparency: None,
            capture: None,
            targets_generation: 0,
            fur: None,
            fur_generation: 0,
            background_probes: false,
            timer: GpuTimer::new(device, &gpu.queue),
            creations: Creations {
                scene_uploads: 1,
                ..Creations::default()
            },
            bindings,
            ribbon_layout,
            scene,
            targets,
        })
    }

    /// With `true` (the window), a frame under the fibres model whose path-traced probe is not kept asks for it
    /// on another thread and is drawn meanwhile with the path-traced probe used last, or the voxel probe where
    /// none was ([`Renderer::probe_pending`] says so until it is kept); with `false`, the default, it is baked
    /// before the frame is drawn, so a measurement's image is the one its settings give.
    pub fn set_background_probes(&mut self, background: bool) {
        self.background_probes = background;
    }

    /// Whether a probe asked for by a frame is being baked on another thread (draw again once it is not).
    pub fn probe_pending(&self) -> bool {
        self.scene.probe_pending()
    }

    /// Replaces the scene (buffers re-sized from the new scene, a new generation).
    pub fn set_scene(&mut self, scene: &Scene) -> Result<(), GpuError> {
        self.scene = SceneGpu::upload(&self.gpu, scene, &self.ribbon_layout)?;
        self.creations.scene_uploads += 1;
        Ok(())
    }

    /// Rebuilds every pipeline from the shaders now in use ([`crate::shaders::live`]): the light, mesh, hair and
    /// evaluation passes now, the method's and the transparency technique's states on the next frame.
    pub fn reload_shaders(&mut self) {
        let device = &self.gpu.device;
        self.light.reload_shaders(device, &self.bindings.frame_layout);
        self.mesh_pass = MeshPass::new(&self.bindings.scene_layout);
        self.hair_pass = HairPass::new(&self.bindings.scene_layout);
        self.evaluate = passes::evaluate::EvaluatePass::new(device, &self.bindings.scene_layout);
        self.transparency = None;
    }

    /// Moves the strands' points ([`SceneGpu::update_points`], the one write path for moving hair): the next
    /// frame draws them, with every light frame and map refitted, and nothing re-created.
    pub fn update_points(&mut self, points: &[Vec3]) -> Result<(), GpuError> {
        Ok(self.scene.update_points(&self.gpu, points)?)
    }

    /// Moves the meshes `moving` (indices into the scene's meshes) rigidly by `transform` from their rest pose
    /// ([`SceneGpu::pose_meshes`], the write path for meshes on a moving root frame): every pass that draws
    /// meshes draws them there from the next frame on.
    pub fn pose_meshes(&mut self, moving: &[usize], transform: glam::Affine3A) -> Result<(), GpuError> {
        self.scene.pose_meshes(&self.gpu, moving, transform)
    }

    /// The mesh vertex positions the GPU holds (posed by [`Renderer::pose_meshes`]).
    pub fn read_mesh_positions(&self) -> Result<Vec<Vec3>, GpuError> {
        self.scene.read_mesh_positions(&self.gpu)
    }

    /// The bound [`crate::scene::LightFit::Bound`] fits the hair maps to ([`SceneGpu::set_fit_bound`]).
    pub fn set_fit_bound(&mut self, bound: Option<crate::scene::Aabb>) {
        self.scene.set_fit_bound(bound);
    }

    /// The box the hair maps' light frame is fitted to under `fit` ([`SceneGpu::light_fit`]).
    pub fn fit_box(&self, fit: crate::scene::LightFit) -> crate::scene::Aabb {
        self.scene.light_fit(fit).0
    }

    /// The box a spot light is placed around under `fit` ([`SceneGpu::light_fit`],
    /// [`crate::scene::Light::spot_position`]): what the path tracer of a posed frame takes so that both draw
    /// one light (`path_scene::PathScene::placed`).
    pub fn light_around(&self, fit: crate::scene::LightFit) -> crate::scene::Aabb {
        self.scene.light_fit(fit).1
    }

    /// Makes the light maps `side` texels a side: `render.map_resolution × render.light_supersample`
    /// ([`RenderSettings::light_map_side`]); a side the GPU cannot hold is one error naming both keys.
    fn ensure_map_size(&mut self, side: u32, supersample: u32) -> Result<(), GpuError> {
        let device = &self.gpu.device;
        if self.light.maps.near.width() != side {
            let limit = device.limits().max_texture_dimension_2d;
            if supersample <= 1 {
                self.gpu.check_texture_size("light map", side)?;
            } else if side > limit {
                return Err(GpuError::Setting(format!(
                    "render.light_supersample = {supersample}: the light maps would be {side} texels a side \
                     (render.map_resolution × render.light_supersample), above this GPU's largest texture side \
                     {limit}; lower render.light_supersample or render.map_resolution"
                )));
            }
            self.light.maps = LightDepthMaps::new(device, side);
            self.bindings
                .rebind_scene(device, &self.light.maps, &self.light.shadow_map);
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

    fn frame_uniforms(
        &self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
        size: (u32, u32),
        method_params: [f32; 4],
    ) -> FrameUniforms {
        let mut u = frame::uniforms(
            &self.scene,
            &frame::UniformInputs {
                camera,
                light,
                render,
                size,
                method_params,
                light_map_resolution: self.light.maps.near.width(),
                shadow_map_resolution: self.light.shadow_map.texture.width(),
            },
        );
        if render.hair_model == crate::shading::HairModel::Fibres {
            use crate::shading::mesh_bounce::Probe;
            use probe_cache::Answer;
            let (grid, probe) = match render.probe {
                Probe::Traced if self.background_probes => {
                    match self.scene.mesh_bounce_or_bake(&u, Probe::Traced) {
                        Answer::Kept(grid) | Answer::Baking(Some(grid)) => (grid, Probe::Traced),
                        Answer::Baking(None) => (self.scene.mesh_bounce(&u, Probe::Voxels), Probe::Voxels),
                    }
                }
                probe => (self.scene.mesh_bounce(&u, probe), probe),
            };
            let holds_scattering = probe == Probe::Traced;
            u.bounce_min = grid.min.extend(f32::from(u8::from(holds_scattering))).to_array();
            u.bounce_max = grid.max.extend(0.0).to_array();
            u.bounce_grid = crate::shading::probe_light::packed(&grid);
        }
        if let Some(f) = self.fur.as_ref().filter(|f| f.settings.mode.strands()) {
            u.guard_sigma = f.settings.guard_sigma();
            u.guard_shell_height = f.settings.height;
            let n = f.settings.env_lights as usize;
            if n > 1 {
                let n = n.min(crate::fur::environment::MAX_ENV_LIGHTS);
                let radiance = glam::Vec3::from_array(light.color) * light.intensity;
                let lights = match &f.scene.env_map {
                    Some(map) => map.lights(n, radiance),
                    None => crate::fur::environment::Sky {
                        to_sun: light.to_light(),
                        radiance,
                    }
                    .lights(n),
                };
                u.env_count = lights.len() as u32;
                for (i, l) in lights.iter().enumerate() {
                    u.env_to_light[i] = l.to_light.extend(0.0).to_array();
                    u.env_radiance[i] = l.radiance.extend(0.0).to_array();
                }
            }
        }
        u
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
        let method_gpu = self.light.held(f.method)?;
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
            hair_alpha: f.render.opacity(),
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
        self.ensure_map_size(f.render.light_map_side(), f.render.light_supersample)?;
        let device = self.gpu.device.clone();
        self.light.ensure_stage(
            &device,
            &self.bindings.frame_layout,
            f.render.strands_drawn(),
            f.render.raster,
        )?;
        let u = self.uniforms(f);
        self.gpu
            .queue
            .write_buffer(&self.bindings.buffer, 0, bytemuck::bytes_of(&u));
        let raster = (f.render.light_map_side(), f.render.raster_tile);
        self.light
            .prepare_casters(&self.gpu, &self.bindings, &self.scene, raster, &mut self.timer)?;
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.frame.encoder"),
        });
        let (gpu, bindings) = (&self.gpu, &self.bindings);
        if self
            .light
            .record(gpu, bindings, &self.scene, f, &mut enc, &mut self.timer)?
        {
            self.creations.method_states += 1;
        }
        Ok(enc)
    }
}

/// Timestamp writes for the next pass, when timing is on.
pub(crate) fn ts<'a>(
    timer: &'a mut Option<GpuTimer>,
    phase: Phase,
    name: &str,
) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
    timer.as_mut().and_then(|t| t.pass(phase, name))
}
