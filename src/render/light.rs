//! The light side of a frame: the shared light-depth pass, the opaque meshes' shadow map and the selected shadow
//! method's maps, every light pipeline built for the frame's light caster stage ([`crate::render::caster`]); and
//! the exact reference's passes (A-buffer, depth peeling), built for the same stage so that they see the
//! fragments the methods see.

use crate::gpu::timing::{GpuTimer, Phase};
use crate::gpu::{Gpu, GpuError};
use crate::render::caster::compute::{ComputeRaster, StrandPoints};
use crate::render::caster::{LightCaster, LightStage, LightStrands, Raster};
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
    /// How the strand lines become texels.
    raster: Raster,
    pub stage: LightStage,
    /// The compute rasteriser's state under [`Raster::Compute`], created on first use.
    compute: Option<ComputeRaster>,
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
        let strands = LightStrands::Lines;
        let stage = LightStage {
            caster: strands.stage(),
            ribbon_layout: ribbon_layout.clone(),
        };
        LightSide {
            depth_pass: LightDepthPass::new(device, frame_layout, &stage),
            shadow_pass: ShadowMapPass::new(device, frame_layout),
            strands,
            raster: Raster::default(),
            stage,
            compute: None,
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

    /// How the strand lines become texels.
    pub fn raster(&self) -> Raster {
        self.raster
    }

    /// Rebuilds every light pipeline for the caster stage of `strands` under `raster` when it changed: the
    /// light-depth pass now, the method's and the reference's with their states. An undrawn combination is a
    /// setting error naming the keys.
    pub fn ensure_stage(
        &mut self,
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        strands: LightStrands,
        raster: Raster,
    ) -> Result<(), GpuError> {
        if (self.strands, self.raster) != (strands, raster) {
            let caster = raster.stage(strands).map_err(GpuError::Setting)?;
            self.strands = strands;
            self.raster = raster;
            if raster != Raster::Compute {
                self.compute = None;
            }
            self.stage.caster = caster;
            self.depth_pass = LightDepthPass::new(device, frame_layout, &self.stage);
            self.method = None;
            self.reference = None;
            self.peel = None;
        }
        Ok(())
    }

    /// Runs the compute rasteriser over `scene` under the frame uniforms bound in `frame` (written before),
    /// when the frame's strands are rasterised in compute: before any light pass of the frame draws them.
    /// `raster` is the maps' side as built and `render.raster_tile`.
    pub fn prepare_casters(
        &mut self,
        gpu: &Gpu,
        bindings: &FrameBindings,
        scene: &SceneGpu,
        raster: (u32, u32),
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        if self.raster == Raster::Compute {
            let compute = self.compute.get_or_insert_with(|| {
                ComputeRaster::new(gpu, &bindings.frame_layout, &self.stage.ribbon_layout)
            });
            let strands = StrandPoints {
                vertices: &scene.hair_vertices,
                indices: &scene.hair_indices,
                segments: scene.segment_count() as u64,
            };
            compute.prepare(gpu, &bindings.frame_group, strands, raster, timer)?;
        }
        Ok(())
    }

    /// What the light passes of a frame draw: the scene's casters of the strands, or under [`Raster::Compute`]
    /// the compute rasteriser's stream (prepared by [`LightSide::prepare_casters`]).
    pub fn casters<'a>(&'a self, scene: &'a SceneGpu) -> Result<[&'a dyn LightCaster; 1], GpuError> {
        casters_of(self.raster, self.compute.as_ref(), scene, self.strands)
    }

    /// The compute rasteriser's state, once it has run.
    pub fn compute_raster(&self) -> Option<&ComputeRaster> {
        self.compute.as_ref()
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
        let casters = casters_of(self.raster, self.compute.as_ref(), scene, self.strands)?;
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
            hair_alpha: f.render.light_opacity(),
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

/// [`LightSide::casters`] over its fields (so that the method state can be replaced while they are drawn).
fn casters_of<'a>(
    raster: Raster,
    compute: Option<&'a ComputeRaster>,
    scene: &'a SceneGpu,
    strands: LightStrands,
) -> Result<[&'a dyn LightCaster; 1], GpuError> {
    match (raster, compute) {
        (Raster::Hardware, _) => scene.casters(strands),
        (Raster::Compute, Some(c)) => Ok([c]),
        (Raster::Compute, None) => Err(GpuError::Setting(
            "render.raster = compute: the compute rasteriser has not run for this frame".into(),
        )),
    }
}
