//! What tests, the inspector, the window and `measure` read back from the renderer or ask it: the method's GPU
//! lookup at chosen texels and depths, the exact references' lists (light space and eye space), the depth peel,
//! the images and depth maps of the last frame, its eye depth complexity, the memory held by part, the GPU
//! timings, the frame's matrices and light frame, and the renderer's sizes, generations and creation counts.

use super::caster::Raster;
use super::caster::raster_model::RasterFragment;
use super::method::{LightMethod, MethodGpu, ParamValues};
use super::passes::abuffer::RefFragment;
use super::passes::depth_peel::DepthPeel;
use super::passes::evaluate::Sample;
use super::scene_gpu::SceneGpu;
use super::transparency::{self, TransparencyGpu};
use super::uniforms::FrameUniforms;
use super::{Creations, FrameInput, MemoryReport, RenderSettings, Renderer, frame, passes};
use crate::gpu::Gpu;
use crate::gpu::timing::PassTime;
use crate::gpu::{GpuError, readback};
use crate::scene::light_frame::LightFrame;
use crate::scene::{Camera, Light};
use glam::{Mat4, Vec3};

impl Renderer {
    /// The exact eye reference's per-pixel fragment lists of `f`'s view (row-major pixels, each front to back
    /// on (depth, segment)): `f` rendered with the reference technique, its lists read back.
    pub fn eye_lists(
        &mut self,
        f: &FrameInput,
    ) -> Result<Vec<Vec<crate::transparency::EyeFragment>>, GpuError> {
        let empty = ParamValues::new();
        let reference = FrameInput {
            technique: transparency::registry::reference(),
            technique_params: &empty,
            ..*f
        };
        self.render(&reference)?;
        match self
            .transparency
            .as_ref()
            .and_then(|(_, t)| t.read_lists(&self.gpu))
        {
            Some(lists) => lists,
            None => Err(GpuError::Readback(
                "the reference technique keeps no lists".into(),
            )),
        }
    }

    /// The eye depth complexity (deepest pixel, total fragments) of the last frame, when its technique counts it.
    pub fn eye_depth_complexity(&self) -> Option<(u32, u64)> {
        self.transparency.as_ref().and_then(|(_, t)| t.depth_complexity())
    }

    /// Geometry passes the last frame's technique drew.
    pub fn eye_geometry_passes(&self) -> u32 {
        self.transparency.as_ref().map_or(0, |(_, t)| t.geometry_passes())
    }

    /// Evaluates the method's GPU lookup (`visibility_at`) at `(texel x, texel y, light depth)` samples, on the
    /// maps of the last frame rendered with `method`.
    pub fn evaluate(&mut self, method: &dyn LightMethod, samples: &[[f32; 3]]) -> Result<Vec<f32>, GpuError> {
        let samples: Vec<Sample> = samples.iter().map(|&s| Sample::Texel(s)).collect();
        self.evaluate_samples(method, &samples)
    }

    /// Evaluates the eye lookup `hair_visibility` (`shaders/common/method_lookup.wgsl`: the frame's PCF,
    /// jitter and light-map supersampling over the method's `visibility_at`) at world points, on the maps and
    /// frame uniforms of the last frame rendered with `method`.
    pub fn evaluate_points(
        &mut self,
        method: &dyn LightMethod,
        points: &[Vec3],
    ) -> Result<Vec<f32>, GpuError> {
        let samples: Vec<Sample> = points.iter().map(|p| Sample::World(p.to_array())).collect();
        self.evaluate_samples(method, &samples)
    }

    /// The evaluate pass over `samples` on the held maps of `method`.
    fn evaluate_samples(
        &mut self,
        method: &dyn LightMethod,
        samples: &[Sample],
    ) -> Result<Vec<f32>, GpuError> {
        let method_gpu = self.light.held(method)?;
        self.evaluate
            .run(&self.gpu, method, method_gpu, &self.bindings.scene_group, samples)
    }

    /// The exact reference's per-texel fragment lists (row-major texels, each sorted by depth then segment) of
    /// the strands' light view under `light` at the maps' side as built (`render.map_resolution ×
    /// render.light_supersample`): the light-depth pass and the A-buffer's
    /// counting and filling passes, submitted and read back in this one call.
    pub fn reference_lists(
        &mut self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
    ) -> Result<Vec<Vec<RefFragment>>, GpuError> {
        self.prepare_light_view(camera, light, render)?;
        let gpu = self.gpu.clone();
        let mut abuffer = match self.light.reference.take() {
            Some(a) => a,
            None => passes::abuffer::ABuffer::new(&gpu, &self.bindings.frame_layout, &self.light.stage),
        };
        let casters = self.light.casters(&self.scene)?;
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.reference_lists.encoder"),
            });
        self.light
            .record_depth(&mut enc, &self.bindings.frame_group, &casters, &mut self.timer);
        let resolution = self.light.maps.near.width();
        let prepared = abuffer.prepare(&gpu, &self.bindings.frame_group, &casters, resolution, &mut None);
        if prepared.is_ok() {
            abuffer.record(&self.bindings.frame_group, &casters, &mut enc, &mut self.timer);
            self.submit(enc);
        }
        let lists = prepared.and_then(|()| abuffer.read_lists(&gpu));
        self.light.reference = Some(abuffer);
        lists
    }

    /// Depth-peels the strands of the last frame's light view (the slow exact reference; see
    /// [`passes::depth_peel`]).
    pub fn depth_peel(&mut self, max_layers: u32) -> Result<passes::depth_peel::Peeled, GpuError> {
        let peel = match self.light.peel.take() {
            Some(p) => p,
            None => DepthPeel::new(&self.gpu, &self.bindings.frame_layout, &self.light.stage),
        };
        let peeled = self.light.casters(&self.scene).and_then(|casters| {
            peel.peel(
                &self.gpu,
                &self.bindings.frame_group,
                &casters,
                self.light.maps.near.width(),
                max_layers,
            )
        });
        self.light.peel = Some(peel);
        peeled
    }

    /// The frame uniforms of the strands' light view under `light` at the maps' side as built, written, and
    /// the light stage and casters made ready for them (the compute rasteriser run under `render.raster =
    /// compute`).
    fn prepare_light_view(
        &mut self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
    ) -> Result<FrameUniforms, GpuError> {
        self.ensure_map_size(render.light_map_side(), render.light_supersample)?;
        let device = self.gpu.device.clone();
        self.light.ensure_stage(
            &device,
            &self.bindings.frame_layout,
            render.strands_drawn(),
            render.raster,
        )?;
        let u = self.frame_uniforms(camera, light, render, (1, 1), [0.0; 4]);
        self.gpu
            .queue
            .write_buffer(&self.bindings.buffer, 0, bytemuck::bytes_of(&u));
        let raster = (render.light_map_side(), render.raster_tile);
        self.light
            .prepare_casters(&self.gpu, &self.bindings, &self.scene, raster, &mut None)?;
        Ok(u)
    }

    /// The compute rasteriser's fragment stream of the strands' light view under `light` at
    /// the maps' side as built (`render.raster` taken as `compute`), read back, with the frame uniforms its CPU
    /// model ([`crate::render::caster::raster_model::rasterise`]) takes.
    pub fn raster_stream(
        &mut self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
    ) -> Result<(Vec<RasterFragment>, FrameUniforms), GpuError> {
        let render = RenderSettings {
            raster: Raster::Compute,
            ..render.clone()
        };
        let u = self.prepare_light_view(camera, light, &render)?;
        let stream = match self.light.compute_raster() {
            Some(c) => c.read_stream(&self.gpu)?,
            None => Vec::new(),
        };
        Ok((stream, u))
    }

    /// The tiles' segment lists of the last binned compute rasterisation (`render.raster_tile` > 0), read back:
    /// per tile (row-major), the segments (indices) in the order the bin pass listed them; empty when none ran.
    pub fn raster_tile_lists(&self) -> Result<Vec<Vec<u32>>, GpuError> {
        match self.light.compute_raster() {
            Some(c) => c.read_tile_lists(&self.gpu),
            None => Ok(Vec::new()),
        }
    }

    /// The GPU state of `method`, when it is the method of the last frame.
    pub fn method_gpu(&self, method: &dyn LightMethod) -> Option<&dyn MethodGpu> {
        self.light.held(method).ok()
    }

    /// Reads the final image back as tightly packed sRGB RGBA8.
    pub fn read_output(&self) -> Result<image::RgbaImage, GpuError> {
        let bytes = readback::read_texture_rgba8(&self.gpu, &self.targets.color)?;
        image::RgbaImage::from_raw(self.targets.width, self.targets.height, bytes)
            .ok_or_else(|| GpuError::Readback("output size mismatch".into()))
    }

    /// Reads the eye depth buffer of the last frame (opaque meshes only; 1 where none), row-major.
    pub fn read_eye_depth(&self) -> Result<Vec<f32>, GpuError> {
        Ok(bytemuck::pod_collect_to_vec(&readback::read_texture(
            &self.gpu,
            &self.targets.depth,
            4,
        )?))
    }

    /// Reads a light-depth map back (`far == false`: nearest depths).
    pub fn read_light_depth(&self, far: bool) -> Result<Vec<f32>, GpuError> {
        let t = if far {
            &self.light.maps.far
        } else {
            &self.light.maps.near
        };
        Ok(bytemuck::pod_collect_to_vec(&readback::read_texture(
            &self.gpu, t, 4,
        )?))
    }

    /// GPU memory by part; the method and the eye transparency technique are the last frame's (their states are
    /// the only ones held).
    pub fn memory(&self) -> MemoryReport {
        let (method_name, method, shared, build) =
            self.light.method.as_ref().map_or(("", 0, 0, 0), |(n, m)| {
                (*n, m.memory_bytes(), m.shared_bytes(), m.build_bytes())
            });
        let (transparency_name, transparency_targets) = self
            .transparency
            .as_ref()
            .map_or(("", 0), |(n, t)| (*n, t.memory_bytes()));
        MemoryReport {
            geometry: self.scene.bytes,
            light_depth_maps: self.light.maps.bytes(),
            shadow_map: self.light.shadow_map.bytes(),
            eye_targets: self.targets.bytes() + transparency_targets,
            transparency_name,
            transparency_targets,
            method_name,
            method_owned: method.saturating_sub(shared),
            method_shared: shared,
            method_build: build,
            reference_lists: self.light.reference.as_ref().map_or(0, |a| a.memory_bytes()),
            raster_stream: self.light.compute_raster().map_or(0, |c| c.memory_bytes()),
        }
    }

    /// The GPU state of the eye transparency technique of the last frame, for a technique's own readbacks in
    /// tests (downcast to its type).
    pub fn transparency_gpu(&self) -> Option<&dyn TransparencyGpu> {
        self.transparency.as_ref().map(|(_, t)| t.as_ref())
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

    /// Increases whenever the output texture is re-created (a viewer must re-register it).
    pub fn targets_generation(&self) -> u64 {
        self.targets_generation
    }

    /// `[near, far]` of the strands' distances from `camera`'s eye ([`frame::eye_depth_range`]).
    pub fn eye_depth_range(&self, camera: &Camera) -> [f32; 2] {
        frame::eye_depth_range(&self.scene, camera)
    }

    /// The light frame of the hair maps (as built, [`Renderer::map_resolution`] texels a side) under
    /// `light.fit` ([`frame::hair_light_frame`]).
    pub fn hair_light_frame(&self, light: &Light) -> LightFrame {
        frame::hair_light_frame(&self.scene, light, self.map_resolution())
    }

    /// The light frame of the meshes' shadow map ([`frame::shadow_light_frame`]).
    pub fn shadow_light_frame(&self, light: &Light) -> LightFrame {
        frame::shadow_light_frame(&self.scene, light)
    }

    /// Camera matrices for an image of `width`×`height`.
    pub fn world_to_clip(&self, camera: &Camera, width: u32, height: u32) -> Mat4 {
        frame::world_to_clip(&self.scene, camera, width, height)
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

    /// Side of the hair light maps as built (`render.map_resolution × render.light_supersample`).
    pub fn map_resolution(&self) -> u32 {
        self.light.maps.near.width()
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
