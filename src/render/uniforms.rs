//! `FrameUniforms`, mirrored field for field by `shaders/common/frame.wgsl` (a test compares the layouts).

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub world_to_clip: [[f32; 4]; 4],
    pub world_to_light_view: [[f32; 4]; 4],
    pub world_to_light_clip: [[f32; 4]; 4],
    pub world_to_shadow_clip: [[f32; 4]; 4],
    pub eye_position: [f32; 4],
    pub to_light: [f32; 4],
    pub light_position: [f32; 4],
    pub light_color: [f32; 4],
    pub hair_color: [f32; 4],
    pub light_range: [f32; 4],
    pub method_params: [f32; 4],
    pub viewport: [f32; 4],
}

/// Field names and byte offsets, in declaration order, for the layout test.
pub const FRAME_UNIFORMS_FIELDS: &[(&str, usize)] = &[
    (
        "world_to_clip",
        std::mem::offset_of!(FrameUniforms, world_to_clip),
    ),
    (
        "world_to_light_view",
        std::mem::offset_of!(FrameUniforms, world_to_light_view),
    ),
    (
        "world_to_light_clip",
        std::mem::offset_of!(FrameUniforms, world_to_light_clip),
    ),
    (
        "world_to_shadow_clip",
        std::mem::offset_of!(FrameUniforms, world_to_shadow_clip),
    ),
    ("eye_position", std::mem::offset_of!(FrameUniforms, eye_position)),
    ("to_light", std::mem::offset_of!(FrameUniforms, to_light)),
    (
        "light_position",
        std::mem::offset_of!(FrameUniforms, light_position),
    ),
    ("light_color", std::mem::offset_of!(FrameUniforms, light_color)),
    ("hair_color", std::mem::offset_of!(FrameUniforms, hair_color)),
    ("light_range", std::mem::offset_of!(FrameUniforms, light_range)),
    (
        "method_params",
        std::mem::offset_of!(FrameUniforms, method_params),
    ),
    ("viewport", std::mem::offset_of!(FrameUniforms, viewport)),
];
