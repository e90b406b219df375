//! What tests, the inspector and `measure` read back from the renderer: the method's GPU lookup at chosen
//! texels and depths, the exact references' lists (light space and eye space), the depth peel, the images and
//! depth maps of the last frame, its eye depth complexity, and the memory held by part.

use super::method::{LightMethod, MethodGpu, ParamValues};
use super::passes::abuffer::RefFragment;
use super::passes::depth_peel::DepthPeel;
use super::transparency::{self, TransparencyGpu};
use super::{FrameInput, MemoryReport, RenderSettings, Renderer, held, passes, ts};
use crate::gpu::timing::Phase;
use crate::gpu::{GpuError, readback};
use crate::scene::{Camera, Light};

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
        let method_gpu = held(&self.method, method)?;
        self.evaluate
            .run(&self.gpu, method, method_gpu, &self.bindings.scene_group, samples)
    }

    /// The exact reference's per-texel fragment lists (row-major texels, each sorted by depth then segment) of
    /// the strands' light view under `light` at `render.map_resolution`: the light-depth pass and the A-buffer's
    /// counting and filling passes, submitted and read back in this one call.
    pub fn reference_lists(
        &mut self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
    ) -> Result<Vec<Vec<RefFragment>>, GpuError> {
        self.ensure_map_size(render.map_resolution)?;
        let u = self.frame_uniforms(camera, light, render, (1, 1), [0.0; 4]);
        self.gpu
            .queue
            .write_buffer(&self.bindings.buffer, 0, bytemuck::bytes_of(&u));
        let gpu = self.gpu.clone();
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.reference_lists.encoder"),
            });
        self.light_depth.record(
            &mut enc,
            &self.light_maps,
            &self.bindings.frame_group,
            &self.scene.casters(),
            ts(&mut self.timer, Phase::SharedLight, "light depth"),
        );
        let mut abuffer = match self.reference.take() {
            Some(a) => a,
            None => passes::abuffer::ABuffer::new(&gpu, &self.bindings.frame_layout),
        };
        let casters = self.scene.casters();
        let resolution = self.light_maps.near.width();
        let prepared = abuffer.prepare(&gpu, &self.bindings.frame_group, &casters, resolution, &mut None);
        if prepared.is_ok() {
            abuffer.record(&self.bindings.frame_group, &casters, &mut enc, &mut self.timer);
            self.submit(enc);
        }
        let lists = prepared.and_then(|()| abuffer.read_lists(&gpu));
        self.reference = Some(abuffer);
        lists
    }

    /// Depth-peels the strands of the last frame's light view (the slow exact reference; see
    /// [`passes::depth_peel`]).
    pub fn depth_peel(&mut self, max_layers: u32) -> Result<passes::depth_peel::Peeled, GpuError> {
        let peel = self
            .peel
            .get_or_insert_with(|| DepthPeel::new(&self.gpu, &self.bindings.frame_layout));
        peel.peel(
            &self.gpu,
            &self.bindings.frame_group,
            &self.scene.casters(),
            self.light_maps.near.width(),
            max_layers,
        )
    }

    /// The GPU state of `method`, when it is the method of the last frame.
    pub fn method_gpu(&self, method: &dyn LightMethod) -> Option<&dyn MethodGpu> {
        held(&self.method, method).ok()
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
            &self.light_maps.far
        } else {
            &self.light_maps.near
        };
        Ok(bytemuck::pod_collect_to_vec(&readback::read_texture(
            &self.gpu, t, 4,
        )?))
    }

    /// GPU memory by part; the method and the eye transparency technique are the last frame's (their states are
    /// the only ones held).
    pub fn memory(&self) -> MemoryReport {
        let (method_name, method, shared, build) = self.method.as_ref().map_or(("", 0, 0, 0), |(n, m)| {
            (*n, m.memory_bytes(), m.shared_bytes(), m.build_bytes())
        });
        let (transparency_name, transparency_targets) = self
            .transparency
            .as_ref()
            .map_or(("", 0), |(n, t)| (*n, t.memory_bytes()));
        MemoryReport {
            geometry: self.scene.bytes,
            light_depth_maps: self.light_maps.bytes(),
            shadow_map: self.shadow_map.bytes(),
            eye_targets: self.targets.bytes() + transparency_targets,
            transparency_name,
            transparency_targets,
            method_name,
            method_owned: method.saturating_sub(shared),
            method_shared: shared,
            method_build: build,
            reference_lists: self.reference.as_ref().map_or(0, |a| a.memory_bytes()),
        }
    }

    /// The GPU state of the eye transparency technique of the last frame, for a technique's own readbacks in
    /// tests (downcast to its type).
    pub fn transparency_gpu(&self) -> Option<&dyn TransparencyGpu> {
        self.transparency.as_ref().map(|(_, t)| t.as_ref())
    }
}
