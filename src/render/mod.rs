//! The renderer: light passes, the selected shadow method, the eye passes and the selected eye transparency
//! technique's resolve, into one colour texture that the window shows and screenshots save. The GUI and
//! `hairlab render` use the same code path.

pub mod caster;
pub mod fur;
pub mod geometry;
pub mod light_frame;
pub mod maps;
pub mod method;
pub mod passes;
pub mod pipelines;
pub mod scene_gpu;
pub mod targets;
pub mod transparency;
pub mod uniforms;

use crate::gpu::timing::{GpuTimer, PassTime, Phase};
use crate::gpu::{Gpu, GpuError, readback};
use crate::scene::{Camera, Light, LightKind, Scene};
use glam::{Mat4, Vec3};
use light_frame::LightFrame;
use method::{LightMethod, MethodContext, MethodGpu, ParamValues};
use passes::abuffer::RefFragment;
use passes::depth_peel::DepthPeel;
use passes::hair::HairPass;
use passes::light_depth::{LightDepthMaps, LightDepthPass};
use passes::mesh::MeshPass;
use passes::shadow_map::{ShadowMap, ShadowMapPass};
use scene_gpu::SceneGpu;
use serde::{Deserialize, Serialize};
use targets::EyeTargets;
use transparency::{EyeTransparency, TransparencyGpu};
use uniforms::FrameUniforms;

/// How a frame is rendered: output size, light-map resolution, hair material, filtering of the lookups.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderSettings {
    /// Output size of `hairlab render` (the window uses its viewport size).
    pub width: u32,
    pub height: u32,
    /// Side of the square light-space hair maps, 1..=4096.
    pub map_resolution: u32,
    /// Global hair opacity in (0, 1]: every fragment's alpha in `constant` mode, the strands' material opacity
    /// in `coverage` mode.
    pub hair_alpha: f32,
    /// How a fragment's alpha is found ([`AlphaMode`]).
    pub alpha: AlphaMode,
    /// World width of a strand of thickness 1 (`coverage` mode): the width of strands without a thickness array
    /// (the generated ones; a `.hair` header's default thickness is not applied) and the scale on a `.hair`
    /// file's thickness array (1 takes it in the file's units). The default, 1.2 mm, is about one pixel at the
    /// default head's distance at 640×480, so the default head in `coverage` mode looks much as in `constant`
    /// mode, at the same `hair_alpha`.
    pub strand_width: f32,
    /// Colour of strands without their own colour (linear RGB).
    pub hair_color: [f32; 3],
    pub background: [f32; 3],
    /// 3x3 percentage-closer filtering of the shadow method's visibility in the eye passes.
    pub pcf: bool,
    /// Half-texel jitter of the light-map coordinate before every lookup (Sintorn & Assarsson 2009 §3.3).
    pub jitter: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            map_resolution: 512,
            hair_alpha: 0.35,
            alpha: AlphaMode::Constant,
            strand_width: DEFAULT_STRAND_WIDTH,
            hair_color: [0.30, 0.18, 0.09],
            background: [0.12, 0.13, 0.15],
            pcf: false,
            jitter: false,
        }
    }
}

/// How a fragment's alpha is found, in the two vertex stages every light-space and eye-space pass shares
/// (`strand_alpha` in `shaders/common/frame.wgsl`), so every technique and shadow method sees the same alphas.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AlphaMode {
    /// The point's alpha times `hair_alpha`, whatever the strand's width and the view.
    #[default]
    Constant,
    /// The strand's coverage of the pixel (eye) or light texel: `clamp(hair_alpha · width / footprint, 0, 1)` times
    /// the point's alpha, width = thickness × `strand_width`, footprint from [`footprint_per_w`] at the
    /// point's depth.
    Coverage,
}

/// Default [`RenderSettings::strand_width`], in world units (metres for the generated scenes).
pub const DEFAULT_STRAND_WIDTH: f32 = 1.2e-3;

/// World size of one pixel of a `width`×`height` image under the projection `view_to_clip`, per unit of clip w:
/// the side of the square of a pixel's area at view depth 1 for a perspective (`2 d tan(fov_y/2) / height` at
/// depth d, clip w = d), everywhere for an orthographic projection (clip w = 1; frustum width / width for a
/// square frustum).
pub fn footprint_per_w(view_to_clip: &Mat4, width: u32, height: u32) -> f32 {
    let sx = view_to_clip.x_axis.x.abs() * width.max(1) as f32;
    let sy = view_to_clip.y_axis.y.abs() * height.max(1) as f32;
    2.0 / (sx * sy).sqrt()
}

/// Everything one frame depends on besides the scene.
pub struct FrameInput<'a> {
    pub camera: &'a Camera,
    pub light: &'a Light,
    pub render: &'a RenderSettings,
    pub method: &'a dyn LightMethod,
    pub method_params: &'a ParamValues,
    /// The eye transparency technique and its parameters.
    pub technique: &'a dyn EyeTransparency,
    pub technique_params: &'a ParamValues,
    pub width: u32,
    pub height: u32,
}

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

/// What [`Renderer::frame_uniforms`] reads of a frame.
struct FrameParts<'a> {
    camera: &'a Camera,
    light: &'a Light,
    render: &'a RenderSettings,
    width: u32,
    height: u32,
}

/// Side of the opaque meshes' shadow map.
pub const SHADOW_MAP_RESOLUTION: u32 = 2048;

/// The fur a renderer holds, for the panel, `measure` and the tests.
pub struct FurState<'a> {
    pub shell: &'a fur::shell_gpu::ShellGpu,
    /// The typed lists of the last frame (none before the first fur frame).
    pub lists: Option<&'a fur::typed::FurGpu>,
    /// Table 1 row 2: the shell uploaded and its volume computed on the GPU (wall time of `ShellGpu::new`, ms).
    pub volume_ms: f64,
}

/// GPU memory held by the renderer, by part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MemoryReport {
    pub geometry: u64,
    pub light_depth_maps: u64,
    pub shadow_map: u64,
    /// The colour and depth images and the eye transparency technique's targets.
    pub eye_targets: u64,
    /// The technique whose targets are held (the last frame's), and their part of `eye_targets`.
    pub transparency_name: &'static str,
    pub transparency_targets: u64,
    /// The method whose state is held (the last frame's), and its maps: those it owns, and the shared
    /// light-depth maps its lookup reads (already counted in `light_depth_maps`).
    pub method_name: &'static str,
    pub method_owned: u64,
    pub method_shared: u64,
    /// What the method builds its maps from each frame (`MethodGpu::build_bytes`).
    pub method_build: u64,
    /// The exact reference's fragment lists, when the inspector or a measurement has read them.
    pub reference_lists: u64,
}

impl MemoryReport {
    /// Everything the renderer holds (the shared maps once).
    pub fn total(&self) -> u64 {
        self.geometry
            + self.light_depth_maps
            + self.shadow_map
            + self.eye_targets
            + self.method_owned
            + self.method_build
            + self.reference_lists
    }

    /// What the method costs, as the papers count it: its own maps and the shared ones it reads.
    pub fn method(&self) -> u64 {
        self.method_owned + self.method_shared
    }
}

/// GPU states a renderer has created, by kind: what a frame after [`Renderer::update_points`] must not add to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Creations {
    /// Scene uploads (buffers created from a scene).
    pub scene_uploads: u64,
    /// Shadow-method GPU states (each holds the method's maps and pipelines).
    pub method_states: u64,
    /// Eye transparency technique GPU states.
    pub technique_states: u64,
    /// Pipelines built by the eye passes' caches (meshes and hair, per method and technique).
    pub pipelines: u64,
}

pub struct Renderer {
    gpu: Gpu,
    frame_buffer: wgpu::Buffer,
    frame_layout: wgpu::BindGroupLayout,
    scene_layout: wgpu::BindGroupLayout,
    /// Group [`geometry::RIBBON_GROUP`] of the ribbon pipelines, shared by every scene's geometry.
    ribbon_layout: wgpu::BindGroupLayout,
    frame_bind_group: wgpu::BindGroup,
    scene_bind_group: wgpu::BindGroup,
    shadow_sampler: wgpu::Sampler,
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
    /// The scene's fur ([`Renderer::set_fur`]): when on, frames are drawn with the fur's typed lists.
    fur: Option<RendererFur>,
}

/// The fur the renderer holds: the shell's GPU state, the settings and the march before the frame's light.
struct RendererFur {
    shell: fur::shell_gpu::ShellGpu,
    settings: crate::fur::settings::FurSettings,
    march: crate::fur::march::MarchParams,
    /// Table 1 row 2: the shell uploaded and its volume computed on the GPU (wall time of `ShellGpu::new`, ms).
    volume_ms: f64,
}

impl Renderer {
    pub fn new(gpu: &Gpu, scene: &Scene, map_resolution: u32) -> Result<Renderer, GpuError> {
        let device = &gpu.device;
        gpu.check_texture_size("light map", map_resolution)?;
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.frame.uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform_entry = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniforms>() as u64),
            },
            count: None,
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.frame.bind_group_layout"),
            entries: &[uniform_entry],
        });
        let float_tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.scene.bind_group_layout"),
            entries: &[
                uniform_entry,
                float_tex(1),
                float_tex(2),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("hairlab.shadow_map.sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let frame_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.frame.bind_group"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buffer.as_entire_binding(),
            }],
        });
        let light_maps = LightDepthMaps::new(device, map_resolution);
        let shadow_map = ShadowMap::new(
            device,
            SHADOW_MAP_RESOLUTION.min(device.limits().max_texture_dimension_2d),
        );
        let scene_bind_group = Self::make_scene_bind_group(
            device,
            &scene_layout,
            &frame_buffer,
            &light_maps,
            &shadow_map,
            &shadow_sampler,
        );
        let targets = EyeTargets::new(device, 16, 16);
        let ribbon_layout = geometry::ribbon_layout(device);
        let scene = SceneGpu::upload(gpu, scene, &ribbon_layout)?;
        Ok(Renderer {
            gpu: gpu.clone(),
            light_depth: LightDepthPass::new(device, &frame_layout),
            shadow_map_pass: ShadowMapPass::new(device, &frame_layout),
            mesh_pass: MeshPass::new(&scene_layout),
            hair_pass: HairPass::new(&scene_layout),
            evaluate: passes::evaluate::EvaluatePass::new(device, &scene_layout),
            method: None,
            transparency: None,
            capture: None,
            reference: None,
            peel: None,
            targets_generation: 0,
            fur: None,
            timer: GpuTimer::new(device, &gpu.queue),
            creations: Creations {
                scene_uploads: 1,
                ..Creations::default()
            },
            frame_buffer,
            frame_layout,
            scene_layout,
            ribbon_layout,
            frame_bind_group,
            scene_bind_group,
            shadow_sampler,
            scene,
            light_maps,
            shadow_map,
            targets,
        })
    }

    fn make_scene_bind_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        frame: &wgpu::Buffer,
        maps: &LightDepthMaps,
        shadow: &ShadowMap,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.scene.bind_group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&maps.near_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&maps.far_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&shadow.view),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
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
            self.scene_bind_group = Self::make_scene_bind_group(
                device,
                &self.scene_layout,
                &self.frame_buffer,
                &self.light_maps,
                &self.shadow_map,
                &self.shadow_sampler,
            );
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

    /// Holds `fur`'s shell and volume on the GPU and draws the following frames with the fur's typed lists
    /// (`None`, or a mode of off: the selected eye transparency technique again).
    pub fn set_fur(
        &mut self,
        fur: Option<(
            &crate::fur::settings::FurScene,
            &crate::fur::settings::FurSettings,
        )>,
    ) -> Result<(), GpuError> {
        self.fur = None;
        let Some((scene, settings)) = fur.filter(|(_, s)| s.mode != crate::fur::settings::FurMode::Off)
        else {
            return Ok(());
        };
        let start = std::time::Instant::now();
        let shell =
            fur::shell_gpu::ShellGpu::new(&self.gpu, &self.frame_layout, &scene.shell, &scene.volume)?;
        self.fur = Some(RendererFur {
            shell,
            march: settings.march_params(&scene.shell, glam::Vec3::Y, glam::Vec3::ONE),
            settings: settings.clone(),
            volume_ms: start.elapsed().as_secs_f64() * 1e3,
        });
        Ok(())
    }

    /// Changes the held fur's rendering (mode, blending, `a`, `k`, march) without rebuilding its shell: the
    /// caller keeps the shell's own settings (height, layers, levels, noise) those it was built with.
    pub fn set_fur_rendering(
        &mut self,
        shell: &crate::fur::shell::Shell,
        settings: &crate::fur::settings::FurSettings,
    ) {
        if let Some(f) = &mut self.fur {
            f.march = settings.march_params(shell, glam::Vec3::Y, glam::Vec3::ONE);
            f.settings = settings.clone();
        }
    }

    /// The held fur's GPU state, its last frame's list figures and the volume's build time, when fur is on.
    pub fn fur_state(&self) -> Option<FurState<'_>> {
        let f = self.fur.as_ref()?;
        let lists = self
            .transparency
            .as_ref()
            .and_then(|(_, t)| (t.as_ref() as &dyn std::any::Any).downcast_ref::<fur::typed::FurGpu>());
        Some(FurState {
            shell: &f.shell,
            lists,
            volume_ms: f.volume_ms,
        })
    }

    /// Makes the held technique state `technique`'s, sized to the eye targets.
    fn ensure_technique(&mut self, technique: &dyn EyeTransparency) -> Result<(), GpuError> {
        let (width, height) = (self.targets.width, self.targets.height);
        match &mut self.transparency {
            Some((name, state)) if *name == technique.name() => state.resize(&self.gpu, width, height),
            _ => {
                // Evict the previous technique's state before the new technique allocates its own.
                self.transparency = None;
                let setup = transparency::EyeSetup {
                    gpu: &self.gpu,
                    frame_layout: &self.frame_layout,
                    width,
                    height,
                };
                self.transparency = Some((technique.name(), technique.create_gpu(&setup)?));
                self.creations.technique_states += 1;
                self.hair_pass.forget_technique(technique.name());
                Ok(())
            }
        }
    }

    /// `[near, far]` of the strands' distances from `camera`'s eye, in units of the camera distance (the depth
    /// the eye techniques store): the distance to the strands' bounding box and to its farthest corner.
    pub fn eye_depth_range(&self, camera: &Camera) -> [f32; 2] {
        let eye = camera.eye();
        let b = &self.scene.bounds().strands;
        let d = camera.distance.max(1e-4);
        let nearest = eye.clamp(b.min, b.max).distance(eye);
        let farthest = (0..8)
            .map(|i| {
                let pick = |bit: usize, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
                Vec3::new(
                    pick(1, b.min.x, b.max.x),
                    pick(2, b.min.y, b.max.y),
                    pick(4, b.min.z, b.max.z),
                )
                .distance(eye)
            })
            .fold(0.0f32, f32::max);
        [nearest / d, farthest / d]
    }

    /// Increases whenever the output texture is re-created (a viewer must re-register it).
    pub fn targets_generation(&self) -> u64 {
        self.targets_generation
    }

    /// The light frame of the hair maps: fitted to the strands under `light.fit` ([`SceneGpu::light_fit`]).
    pub fn hair_light_frame(&self, light: &Light) -> LightFrame {
        let (hair, around) = self.scene.light_fit(light.fit);
        LightFrame::fit(light, around.center(), around.radius(), &hair)
    }

    /// The light frame of the meshes' shadow map: fitted to the whole scene.
    fn shadow_light_frame(&self, light: &Light) -> LightFrame {
        let all = &self.scene.bounds().all;
        LightFrame::fit(light, all.center(), all.radius(), all)
    }

    /// Camera matrices for an image of `width`×`height`.
    pub fn world_to_clip(&self, camera: &Camera, width: u32, height: u32) -> Mat4 {
        self.view_to_clip(camera, width, height) * camera.world_to_view()
    }

    /// The camera's projection for an image of `width`×`height`.
    fn view_to_clip(&self, camera: &Camera, width: u32, height: u32) -> Mat4 {
        let aspect = width as f32 / height.max(1) as f32;
        let all = &self.scene.bounds().all;
        let r = all.radius().max(1e-3);
        let dist = camera.eye().distance(all.center());
        let near = (dist - 2.0 * r).max(r * 0.01).max(camera.distance * 0.01);
        let far = dist + 2.0 * r;
        Mat4::perspective_rh(camera.fov_y_deg.to_radians(), aspect, near, far)
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

    fn frame_uniforms(
        &self,
        camera: &Camera,
        light: &Light,
        render: &RenderSettings,
        (width, height): (u32, u32),
        method_params: [f32; 4],
    ) -> FrameUniforms {
        let f = FrameParts {
            camera,
            light,
            render,
            width,
            height,
        };
        let hair = self.hair_light_frame(f.light);
        let shadow = self.shadow_light_frame(f.light);
        let eye = f.camera.eye();
        let spot = f.light.kind == LightKind::Spot;
        let intensity = f.light.intensity;
        let resolution = self.light_maps.near.width();
        FrameUniforms {
            world_to_clip: self.world_to_clip(f.camera, f.width, f.height).to_cols_array_2d(),
            world_to_light_view: hair.world_to_view.to_cols_array_2d(),
            world_to_light_clip: hair.world_to_clip().to_cols_array_2d(),
            world_to_shadow_clip: shadow.world_to_clip().to_cols_array_2d(),
            eye_position: eye.to_array(),
            camera_distance: f.camera.distance.max(1e-4),
            to_light: hair.to_light.to_array(),
            light_is_spot: u32::from(spot),
            light_position: hair.position.to_array(),
            spot_cos_half_angle: (f.light.cone_deg.to_radians() * 0.5).cos(),
            light_color: f.light.color.map(|c| c * intensity),
            pad0: 0,
            hair_color: f.render.hair_color,
            hair_alpha: f.render.hair_alpha,
            light_near: hair.near,
            light_far: hair.far,
            light_map_resolution: resolution,
            lookup_flags: u32::from(f.render.pcf) | (u32::from(f.render.jitter) << 1),
            method_params,
            viewport_size: [f.width as f32, f.height as f32],
            shadow_map_resolution: self.shadow_map.texture.width(),
            shadow_bias: 1e-4,
            alpha_mode: u32::from(f.render.alpha == AlphaMode::Coverage),
            strand_width: f.render.strand_width,
            eye_footprint: footprint_per_w(
                &self.view_to_clip(f.camera, f.width, f.height),
                f.width,
                f.height,
            ),
            light_footprint: footprint_per_w(&hair.view_to_clip, resolution, resolution),
        }
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

    fn render_frame(&mut self, f: &FrameInput, capture: bool) -> Result<(), GpuError> {
        self.ensure_eye_size(f.width.max(1), f.height.max(1))?;
        let technique: &dyn EyeTransparency = match &self.fur {
            Some(_) => &fur::typed::FUR,
            None => f.technique,
        };
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
            &self.scene_bind_group,
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
        let fur_frame = self.fur.as_ref().map(|fur| fur::typed::FurFrame {
            shell: &fur.shell,
            settings: &fur.settings,
            march: crate::fur::march::MarchParams {
                to_light: f.light.to_light(),
                light: glam::Vec3::from_array(f.light.color) * f.light.intensity,
                ..fur.march
            },
        });
        let mut frame = transparency::EyeFrame {
            gpu: &self.gpu,
            encoder: enc,
            timer: &mut self.timer,
            frame_bind_group: &self.frame_bind_group,
            geometry: &self.scene,
            targets: &self.targets,
            output,
            values: f.technique_params,
            model,
            fur: fur_frame,
            hair: transparency::HairDraw {
                pass: &mut self.hair_pass,
                scene: passes::hair::HairScene {
                    device: &device,
                    method: f.method,
                    method_gpu,
                    technique,
                    scene: &self.scene_bind_group,
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
            .write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&u));
        let device = self.gpu.device.clone();
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlab.frame.encoder"),
        });
        self.light_depth.record(
            &mut enc,
            &self.light_maps,
            &self.frame_bind_group,
            &self.scene.casters(),
            ts(&mut self.timer, Phase::SharedLight, "light depth"),
        );
        self.shadow_map_pass.record(
            &mut enc,
            &self.shadow_map,
            &self.frame_bind_group,
            &self.scene,
            ts(&mut self.timer, Phase::SharedLight, "mesh shadow map"),
        );
        let gpu = self.gpu.clone();
        let casters = self.scene.casters();
        let ctx = MethodContext {
            gpu: &gpu,
            frame_layout: &self.frame_layout,
            frame_bind_group: &self.frame_bind_group,
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

    /// Evaluates the method's GPU lookup (`visibility_at`) at `(texel x, texel y, light depth)` samples, on the
    /// maps of the last frame rendered with `method`.
    pub fn evaluate(&mut self, method: &dyn LightMethod, samples: &[[f32; 3]]) -> Result<Vec<f32>, GpuError> {
        let method_gpu = held(&self.method, method)?;
        self.evaluate
            .run(&self.gpu, method, method_gpu, &self.scene_bind_group, samples)
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
            .write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&u));
        let gpu = self.gpu.clone();
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hairlab.reference_lists.encoder"),
            });
        self.light_depth.record(
            &mut enc,
            &self.light_maps,
            &self.frame_bind_group,
            &self.scene.casters(),
            ts(&mut self.timer, Phase::SharedLight, "light depth"),
        );
        let mut abuffer = match self.reference.take() {
            Some(a) => a,
            None => passes::abuffer::ABuffer::new(&gpu, &self.frame_layout),
        };
        let casters = self.scene.casters();
        let resolution = self.light_maps.near.width();
        let prepared = abuffer.prepare(&gpu, &self.frame_bind_group, &casters, resolution, &mut None);
        if prepared.is_ok() {
            abuffer.record(&self.frame_bind_group, &casters, &mut enc, &mut self.timer);
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
            .get_or_insert_with(|| DepthPeel::new(&self.gpu, &self.frame_layout));
        peel.peel(
            &self.gpu,
            &self.frame_bind_group,
            &self.scene.casters(),
            self.light_maps.near.width(),
            max_layers,
        )
    }

    /// The GPU state of `method`, when it is the method of the last frame.
    pub fn method_gpu(&self, method: &dyn LightMethod) -> Option<&dyn MethodGpu> {
        held(&self.method, method).ok()
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

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The GPU state of the eye transparency technique of the last frame, for a technique's own readbacks in
    /// tests (downcast to its type).
    pub fn transparency_gpu(&self) -> Option<&dyn TransparencyGpu> {
        self.transparency.as_ref().map(|(_, t)| t.as_ref())
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
        &self.frame_layout
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

#[cfg(test)]
mod tests {
    use super::footprint_per_w;
    use glam::Mat4;

    /// One pixel's world size against hand-computed cases: a 90° camera at 200×100 (2 · 2 · tan 45° / 100 =
    /// 0.04 at depth 2), a 60° spot at 512² (2 · 3 · tan 30° / 512 = 6.7658e-3 at depth 3) and a 2 × 0.5
    /// orthographic frustum at 100² (√(0.02 · 0.005) = 0.01 everywhere).
    #[test]
    fn footprints_match_hand_computed_cases() {
        let eye = Mat4::perspective_rh(90f32.to_radians(), 2.0, 0.1, 10.0);
        assert!((footprint_per_w(&eye, 200, 100) * 2.0 - 0.04).abs() < 1e-7);
        let spot = Mat4::perspective_rh(60f32.to_radians(), 1.0, 0.1, 10.0);
        assert!((footprint_per_w(&spot, 512, 512) * 3.0 - 6.7658e-3).abs() < 1e-7);
        let ortho = Mat4::orthographic_rh(-1.0, 1.0, -0.25, 0.25, 0.1, 10.0);
        assert!((footprint_per_w(&ortho, 100, 100) - 0.01).abs() < 1e-8);
    }

    /// Dependencies run one way: the renderer (and the GPU, scene and CPU-model modules under it) never import
    /// the shadow methods, the settings, the app, the bench or `measure`, which sit above it.
    #[test]
    fn lower_layers_import_nothing_above_them() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let above = [
            "crate::methods",
            "crate::settings",
            "crate::app",
            "crate::bench",
            "crate::measure",
        ];
        let mut checked = 0;
        let mut stack: Vec<_> = [
            "render",
            "gpu",
            "scene",
            "visibility",
            "transparency",
            "fur",
            "motion",
        ]
        .iter()
        .map(|d| root.join(d))
        .collect();
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap();
                for (i, line) in text.lines().enumerate() {
                    let code = line.trim_start();
                    if code.starts_with("//") || code.contains("\"crate::") {
                        continue;
                    }
                    for a in above {
                        assert!(!code.contains(a), "{}:{}: imports {a}", path.display(), i + 1);
                    }
                }
                checked += 1;
            }
        }
        assert!(checked > 20, "only {checked} files checked");
    }
}
