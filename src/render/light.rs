//! The light side of a frame: the shared light-depth pass, the opaque meshes' shadow map and the selected shadow
//! method's maps, every light pipeline built for the frame's light caster stage ([`crate::render::caster`]); and
//! the exact reference's passes (A-buffer, depth peeling), built for the same stage so that they see the
//! fragments the methods see.

use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError};
use crate::render::caster::{LightCaster, LightStage, LightStrands};
use crate::render::frame_bindings::FrameBindings;
use crate::render::method::{LightMethod, MethodContext, MethodGpu};
use crate::render::passes::abuffer::ABuffer;
use crate::render::passes::depth_peel::DepthPeel;
use crate::render::passes::light_depth::{LightDepthMaps, LightDepthPass};
use crate::render::passes::shadow_map::{ShadowMap, ShadowMapPass};
use crate::render::scene_gpu::SceneGpu;
use crate::render::{FrameInput, ts};

/// Side of the opaque meshes' shadow map.
pub const SHADOW_MAP_RESOLUTION: u32 = 2048;

pub struct LightSide {
    /// How the strands are drawn from the light, and the stage every light pipeline below is built for.
    strands: LightStrands,
    pub stage: LightStage,
    depth_pass: LightDepthPass,
    pub maps: LightDepthMaps,
    shadow_pass: ShadowMapPass,
    pub shadow_map: ShadowMap,
    /// The GPU state of the method of the last frame; another method (or caster stage) evicts it.
    pub method: Option<(&'static str, Box<dyn MethodGpu>)>,
    /// The exact reference's fragment lists ([`crate::render::Renderer::reference_lists`]), created on first use.
    pub reference: Option<ABuffer>,
    pub peel: Option<DepthPeel>,
}

impl LightSide {
    /// The maps a renderer's frame bindings are made over, before the passes (which need the bindings' layout).
    pub fn maps(gpu: &Gpu, map_resolution: u32) -> Result<(LightDepthMaps, ShadowMap), GpuError> {
        let device = &gpu.device;
        gpu.check_texture_size("light map", map_resolution)?;
        let shadow = SHADOW_MAP_RESOLUTION.min(device.limits().max_texture_dimension_2d);
        Ok((
            LightDepthMaps::new(device, map_resolution),
            ShadowMap::new(device, shadow),
        ))
    }

    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        ribbon_layout: &wgpu::BindGroupLayout,
        (maps, shadow_map): (LightDepthMaps, ShadowMap),
    ) -> LightSide {
        let strands = LightStrands::default();
        let stage = LightStage {
            caster: strands.stage(),
            ribbon_layout: ribbon_layout.clone(),
        };
        LightSide {
            depth_pass: LightDepthPass::new(device, frame_layout, &stage),
            shadow_pass: ShadowMapPass::new(device, frame_layout),
            strands,
            stage,
            maps,
            shadow_map,
            method: None,
            reference: None,
            peel: None,
        }
    }

    /// The strands as the light passes draw them.
    pub fn strands(&self) -> LightStrands {
        self.strands
    }

    /// Rebuilds every light pipeline for `strands`' caster stage when it changed: the light-depth pass now, the
    /// method's and the reference's with their states.
    pub fn ensure_stage(
        &mut self,
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        strands: LightStrands,
    ) {
        if self.strands != strands {
            self.strands = strands;
            self.stage.caster = strands.stage();
            self.depth_pass = LightDepthPass::new(device, frame_layout, &self.stage);
            self.method = None;
            self.reference = None;
            self.peel = None;
        }
    }

    /// Rebuilds every light pipeline from the shaders now in use (`crate::shaders::live`): the light-depth and
    /// shadow-map passes now, the method's and the reference's with their states.
    pub fn reload_shaders(&mut self, device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) {
        self.depth_pass = LightDepthPass::new(device, frame_layout, &self.stage);
        self.shadow_pass = ShadowMapPass::new(device, frame_layout);
        self.method = None;
        self.reference = None;
        self.peel = None;
    }

    /// Records the light-depth pass of `casters` into `enc`.
    pub fn record_depth(
        &self,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        casters: &[&dyn LightCaster],
        timer: &mut Option<GpuTimer>,
    ) {
        let timestamps = ts(timer, Phase::SharedLight, "light depth");
        self.depth_pass
            .record(enc, &self.maps, frame, casters, timestamps);
    }

    /// Records the frame's light side: light depth, the meshes' shadow map, and `f.method`'s passes (its state
    /// created first when the last frame's was another method's). Returns whether a method state was created.
    pub fn record(
        &mut self,
        gpu: &Gpu,
        bindings: &FrameBindings,
        scene: &SceneGpu,
        f: &FrameInput,
        enc: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) -> Result<bool, GpuError> {
        let casters = scene.casters(self.strands)?;
        self.record_depth(enc, &bindings.frame_group, &casters, timer);
        let timestamps = ts(timer, Phase::SharedLight, "mesh shadow map");
        self.shadow_pass
            .record(enc, &self.shadow_map, &bindings.frame_group, scene, timestamps);
        let ctx = MethodContext {
            gpu,
            frame_layout: &bindings.frame_layout,
            frame_bind_group: &bindings.frame_group,
            casters: &casters,
            light: &self.stage,
            light_maps: &self.maps,
            values: f.method_params,
            hair_alpha: f.render.hair_alpha,
        };
        let name = f.method.name();
        let created = self.method.as_ref().is_none_or(|(n, _)| *n != name);
        if created {
            // Evict the previous method's maps before the new method allocates its own.
            self.method = None;
            self.method = Some((name, f.method.create_gpu(&ctx)?));
        }
        if let Some((_, state)) = &mut self.method {
            state.prepare(&ctx, timer)?;
            state.record(&ctx, enc, timer);
        }
        Ok(created)
    }

    /// The held method state if it is `method`'s, or an error saying that `method` is not the last frame's.
    pub fn held(&self, method: &dyn LightMethod) -> Result<&dyn MethodGpu, GpuError> {
        self.method
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
}
