//! `FrameUniforms`, mirrored field for field by `shaders/common/frame.wgsl` (a test compares the layouts). Every
//! `[f32; 3]` is followed by a 4-byte field, as the WGSL `vec3<f32>` (16-byte aligned) requires.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub world_to_clip: [[f32; 4]; 4],
    /// Hair light frame: fitted tightly to the strand bounds.
    pub world_to_light_view: [[f32; 4]; 4],
    pub world_to_light_clip: [[f32; 4]; 4],
    /// Opaque shadow-map frame: fitted to the whole scene (meshes and hair).
    pub world_to_shadow_clip: [[f32; 4]; 4],
    pub eye_position: [f32; 3],
    /// Camera distance to its orbit target.
    pub camera_distance: f32,
    /// Unit vector towards a directional light; a spot's axis.
    pub to_light: [f32; 3],
    /// 0: directional light, 1: spot.
    pub light_is_spot: u32,
    pub light_position: [f32; 3],
    pub spot_cos_half_angle: f32,
    /// Light colour times intensity.
    pub light_color: [f32; 3],
    /// Least width of a light-space ribbon, in light texels (`render.light_min_width`).
    pub light_min_width: f32,
    /// Hair colour for strands without per-point colour.
    pub hair_color: [f32; 3],
    pub hair_alpha: f32,
    /// Light-view distances of the hair frame's near and far planes.
    pub light_near: f32,
    pub light_far: f32,
    /// Texels per side of the hair light maps.
    pub light_map_resolution: u32,
    /// 1: 3x3 PCF, 2: half-texel jitter (`shaders/common/method_lookup.wgsl`).
    pub lookup_flags: u32,
    /// The selected method's `ShadowMethod::uniform_params`.
    pub method_params: [f32; 4],
    /// Eye image width and height in pixels.
    pub viewport_size: [f32; 2],
    /// Texels per side of the opaque shadow map.
    pub shadow_map_resolution: u32,
    /// Depth bias of the opaque shadow-map comparison.
    pub shadow_bias: f32,
    /// 0: constant alpha, 1: coverage alpha ([`crate::render::AlphaMode`]).
    pub alpha_mode: u32,
    /// World width of a strand of thickness 1 (`render.strand_width`).
    pub strand_width: f32,
    /// World size of one eye pixel per unit of eye clip w ([`crate::render::footprint_per_w`]).
    pub eye_footprint: f32,
    /// World size of one hair light-map texel per unit of light clip w.
    pub light_footprint: f32,
    /// The strand shading model, [`crate::shading::ShadingModel::uniform`] (`render.shading`).
    pub shading_model: u32,
    /// Guard hairs' base darkening ([`crate::fur::darkening`]): `fur.base_darkening` times the undercoat's
    /// extinction per world unit, 0 without guard hairs (`fur.mode` off or implicit).
    pub guard_sigma: f32,
    /// The undercoat's height `h_0` the darkening is measured from.
    pub guard_shell_height: f32,
    /// Lights of the guard hairs' environment ([`crate::fur::environment`]): 0 or 1 for the scene's light alone.
    pub env_count: u32,
    /// Light-map supersampling `s` (`render.light_supersample`): the hair maps are `s` times
    /// `render.map_resolution` a side and the eye lookup averages the `s × s` sub-texels of the point's base
    /// texel ([`crate::visibility::lookup`]); 0 reads as 1.
    pub light_supersample: u32,
    /// The raster's ambient terms (`render.ambient` × [`crate::shading::HAIR_AMBIENT`] and
    /// [`crate::shading::MESH_AMBIENT`]): what every hair and mesh fragment adds, times its colour.
    pub hair_ambient: f32,
    pub mesh_ambient: f32,
    /// [`crate::shading::HairModel::uniform`] (`render.hair_model`): 1 takes each fragment's alpha from its
    /// coverage at material opacity 1 and carries light through fibres (`shaders/common/fibre_transport.wgsl`).
    pub hair_model: u32,
    /// Per environment light: the unit direction towards it (xyz) and its radiance (xyz), w unused.
    pub env_to_light: [[f32; 4]; crate::fur::environment::MAX_ENV_LIGHTS],
    pub env_radiance: [[f32; 4]; crate::fur::environment::MAX_ENV_LIGHTS],
    /// Under the fibres model, the probe of the light the meshes bounce and the fibres scatter onto the hair
    /// ([`crate::shading::mesh_bounce::Grid`]): its lattice's corners (xyz; `bounce_min.w` 1 where the probe
    /// holds the light the fibres scatter, `render.probe = traced`, else 0, `bounce_max.w` unused) and its
    /// nodes' light and the hair's cover there, five vectors a node ([`crate::shading::probe_light::packed`]); zeros under the absorber
    /// model.
    pub bounce_min: [f32; 4],
    pub bounce_max: [f32; 4],
    pub bounce_grid: [[f32; 4]; BOUNCE_VECTORS],
}

/// Vectors of [`FrameUniforms::bounce_grid`].
pub const BOUNCE_VECTORS: usize = crate::shading::probe_light::PACKED;

/// Field names and byte offsets, in declaration order, for the layout test.
pub const FRAME_UNIFORMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("world_to_clip", offset_of!(FrameUniforms, world_to_clip)),
        (
            "world_to_light_view",
            offset_of!(FrameUniforms, world_to_light_view),
        ),
        (
            "world_to_light_clip",
            offset_of!(FrameUniforms, world_to_light_clip),
        ),
        (
            "world_to_shadow_clip",
            offset_of!(FrameUniforms, world_to_shadow_clip),
        ),
        ("eye_position", offset_of!(FrameUniforms, eye_position)),
        ("camera_distance", offset_of!(FrameUniforms, camera_distance)),
        ("to_light", offset_of!(FrameUniforms, to_light)),
        ("light_is_spot", offset_of!(FrameUniforms, light_is_spot)),
        ("light_position", offset_of!(FrameUniforms, light_position)),
        (
            "spot_cos_half_angle",
            offset_of!(FrameUniforms, spot_cos_half_angle),
        ),
        ("light_color", offset_of!(FrameUniforms, light_color)),
        ("light_min_width", offset_of!(FrameUniforms, light_min_width)),
        ("hair_color", offset_of!(FrameUniforms, hair_color)),
        ("hair_alpha", offset_of!(FrameUniforms, hair_alpha)),
        ("light_near", offset_of!(FrameUniforms, light_near)),
        ("light_far", offset_of!(FrameUniforms, light_far)),
        (
            "light_map_resolution",
            offset_of!(FrameUniforms, light_map_resolution),
        ),
        ("lookup_flags", offset_of!(FrameUniforms, lookup_flags)),
        ("method_params", offset_of!(FrameUniforms, method_params)),
        ("viewport_size", offset_of!(FrameUniforms, viewport_size)),
        (
            "shadow_map_resolution",
            offset_of!(FrameUniforms, shadow_map_resolution),
        ),
        ("shadow_bias", offset_of!(FrameUniforms, shadow_bias)),
        ("alpha_mode", offset_of!(FrameUniforms, alpha_mode)),
        ("strand_width", offset_of!(FrameUniforms, strand_width)),
        ("eye_footprint", offset_of!(FrameUniforms, eye_footprint)),
        ("light_footprint", offset_of!(FrameUniforms, light_footprint)),
        ("shading_model", offset_of!(FrameUniforms, shading_model)),
        ("guard_sigma", offset_of!(FrameUniforms, guard_sigma)),
        (
            "guard_shell_height",
            offset_of!(FrameUniforms, guard_shell_height),
        ),
        ("env_count", offset_of!(FrameUniforms, env_count)),
        ("light_supersample", offset_of!(FrameUniforms, light_supersample)),
        ("hair_ambient", offset_of!(FrameUniforms, hair_ambient)),
        ("mesh_ambient", offset_of!(FrameUniforms, mesh_ambient)),
        ("hair_model", offset_of!(FrameUniforms, hair_model)),
        ("env_to_light", offset_of!(FrameUniforms, env_to_light)),
        ("env_radiance", offset_of!(FrameUniforms, env_radiance)),
        ("bounce_min", offset_of!(FrameUniforms, bounce_min)),
        ("bounce_max", offset_of!(FrameUniforms, bounce_max)),
        ("bounce_grid", offset_of!(FrameUniforms, bounce_grid)),
    ]
};

impl FrameUniforms {
    /// The light of these uniforms as `light_dir` and `light_radiance` of `shaders/common/frame.wgsl` give it
    /// (the spot's cone edge a smoothstep over the outer 15 % of the cosine, no falloff over distance), for the
    /// probe's bake (`pathtrace::probe::bake`).
    pub fn raster_light(&self) -> crate::pathtrace::effects::RasterLight {
        use glam::Vec3;
        let to_light = Vec3::from(self.to_light);
        crate::pathtrace::effects::RasterLight {
            radiance: Vec3::from(self.light_color),
            to_light,
            spot: (self.light_is_spot != 0).then(|| {
                (
                    Vec3::from(self.light_position),
                    -to_light,
                    self.spot_cos_half_angle,
                )
            }),
        }
    }
}
