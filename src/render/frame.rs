//! One frame's inputs and the matrices and uniforms packed from them: [`FrameInput`], the camera's projection
//! fitted to the scene's bounds, the light frames under the fit policy (`light.fit`, applied by
//! [`SceneGpu::light_fit`]), the eye depth range, pixel and texel footprints, and [`FrameUniforms`] — pure
//! functions of the scene on the GPU and the frame's settings.

use super::method::{LightMethod, ParamValues};
use super::render_settings::{AlphaMode, RenderSettings};
use super::scene_gpu::SceneGpu;
use super::transparency::EyeTransparency;
use super::uniforms::FrameUniforms;
use crate::scene::light_frame::LightFrame;
use crate::scene::{Camera, Light, LightFit, LightKind};
use glam::{Mat4, Vec3};

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

/// `[near, far]` of the strands' distances from `camera`'s eye, in units of the camera distance (the depth the
/// eye techniques store): the distance to the strands' bounding box and to its farthest corner.
pub fn eye_depth_range(scene: &SceneGpu, camera: &Camera) -> [f32; 2] {
    let eye = camera.eye();
    let b = &scene.bounds().strands;
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

/// The light frame of the hair maps of `resolution` texels a side: fitted to the strands under `light.fit`
/// ([`SceneGpu::light_fit`]; [`LightFrame::stable`] under `stable`, whose snap is to this resolution's texels).
pub fn hair_light_frame(scene: &SceneGpu, light: &Light, resolution: u32) -> LightFrame {
    let (hair, around) = scene.light_fit(light.fit);
    match light.fit {
        LightFit::Stable => LightFrame::stable(light, &hair, &around, resolution),
        LightFit::PerFrame | LightFit::Bound => LightFrame::fit(light, &around, &hair),
    }
}

/// The light frame of the meshes' shadow map: fitted to the whole scene, a spot placed where the hair maps'
/// frame places it (around [`SceneGpu::light_fit`]'s box), so the meshes' shadows and the hair's light come
/// from one point under every fit.
pub fn shadow_light_frame(scene: &SceneGpu, light: &Light) -> LightFrame {
    let (_, around) = scene.light_fit(light.fit);
    LightFrame::fit(light, &around, &scene.bounds().all)
}

/// The camera's projection for an image of `width`×`height`, its depth range fitted to the scene.
pub fn view_to_clip(scene: &SceneGpu, camera: &Camera, width: u32, height: u32) -> Mat4 {
    let aspect = width as f32 / height.max(1) as f32;
    let all = &scene.bounds().all;
    let r = all.radius().max(1e-3);
    let dist = camera.eye().distance(all.center());
    let near = (dist - 2.0 * r).max(r * 0.01).max(camera.distance * 0.01);
    let far = dist + 2.0 * r;
    Mat4::perspective_rh(camera.fov_y_deg.to_radians(), aspect, near, far)
}

/// Camera matrices for an image of `width`×`height`.
pub fn world_to_clip(scene: &SceneGpu, camera: &Camera, width: u32, height: u32) -> Mat4 {
    view_to_clip(scene, camera, width, height) * camera.world_to_view()
}

/// What a frame's uniforms are packed from besides the scene.
pub struct UniformInputs<'a> {
    pub camera: &'a Camera,
    pub light: &'a Light,
    pub render: &'a RenderSettings,
    /// The eye image's size.
    pub size: (u32, u32),
    /// The shadow method's packed parameters (`LightMethod::uniform_params`).
    pub method_params: [f32; 4],
    /// Sides of the hair light maps as built (`render.map_resolution × render.light_supersample`) and of the
    /// meshes' shadow map.
    pub light_map_resolution: u32,
    pub shadow_map_resolution: u32,
}

/// The frame uniforms every pass binds at group 0 (`shaders/common/frame.wgsl`).
pub fn uniforms(scene: &SceneGpu, f: &UniformInputs) -> FrameUniforms {
    let (width, height) = f.size;
    let hair = hair_light_frame(scene, f.light, f.light_map_resolution);
    let shadow = shadow_light_frame(scene, f.light);
    let resolution = f.light_map_resolution;
    let intensity = f.light.intensity;
    FrameUniforms {
        world_to_clip: world_to_clip(scene, f.camera, width, height).to_cols_array_2d(),
        world_to_light_view: hair.world_to_view.to_cols_array_2d(),
        world_to_light_clip: hair.world_to_clip().to_cols_array_2d(),
        world_to_shadow_clip: shadow.world_to_clip().to_cols_array_2d(),
        eye_position: f.camera.eye().to_array(),
        camera_distance: f.camera.distance.max(1e-4),
        to_light: hair.to_light.to_array(),
        light_is_spot: u32::from(f.light.kind == LightKind::Spot),
        light_position: hair.position.to_array(),
        spot_cos_half_angle: (f.light.cone_deg.to_radians() * 0.5).cos(),
        light_color: f.light.color.map(|c| c * intensity),
        light_min_width: f.render.light_min_width,
        hair_color: f.render.hair_color,
        hair_alpha: f.render.opacity(),
        light_near: hair.near,
        light_far: hair.far,
        light_map_resolution: resolution,
        lookup_flags: u32::from(f.render.pcf) | (u32::from(f.render.jitter) << 1),
        method_params: f.method_params,
        viewport_size: [width as f32, height as f32],
        shadow_map_resolution: f.shadow_map_resolution,
        shadow_bias: 1e-4,
        alpha_mode: u32::from(f.render.alpha_mode() == AlphaMode::Coverage),
        strand_width: f.render.strand_width,
        eye_footprint: footprint_per_w(&view_to_clip(scene, f.camera, width, height), width, height),
        light_footprint: footprint_per_w(&hair.view_to_clip, resolution, resolution),
        shading_model: f.render.shading.uniform(),
        guard_sigma: 0.0,
        guard_shell_height: 0.0,
        env_count: 0,
        light_supersample: f.render.light_supersample.max(1),
        hair_ambient: f.render.ambient_scale() * crate::shading::HAIR_AMBIENT,
        mesh_ambient: f.render.ambient_scale() * crate::shading::MESH_AMBIENT,
        hair_model: f.render.hair_model.uniform(),
        env_to_light: [[0.0; 4]; crate::fur::environment::MAX_ENV_LIGHTS],
        env_radiance: [[0.0; 4]; crate::fur::environment::MAX_ENV_LIGHTS],
        bounce_min: [0.0; 4],
        bounce_max: [0.0; 4],
        bounce_grid: [[0.0; 4]; crate::render::uniforms::BOUNCE_VECTORS],
    }
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
}
