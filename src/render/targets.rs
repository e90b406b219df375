//! The eye-view render targets every eye transparency technique shares: the final colour image (what the
//! viewport shows and screenshots save) and the opaque meshes' depth. A technique's own targets are its own
//! (`render::transparency`).

pub struct EyeTargets {
    pub color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    /// The colour image viewed as plain `Rgba8Unorm`: egui blends in gamma space and wants the sRGB-encoded bytes.
    pub display_view: wgpu::TextureView,
    /// Depth of the opaque meshes (hair does not write depth); copyable for visibility tests of hair points.
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    /// A never-written colour target ([`EyeTargets::NULL`]) that sets the render area of the eye passes that
    /// only write storage and test the meshes by hand (a pass needs an attachment).
    pub null_view: wgpu::TextureView,
    pub width: u32,
    pub height: u32,
}

impl EyeTargets {
    pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
    pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
    /// The pipeline target state of `null_view`: nothing written.
    pub const NULL: wgpu::ColorTargetState = wgpu::ColorTargetState {
        format: crate::render::passes::NULL_TARGET_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::empty(),
    };

    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> EyeTargets {
        let make = |label, format, usage, view_formats: &[wgpu::TextureFormat]| {
            eye_texture(device, label, (width, height), format, usage, view_formats)
        };
        let color = make(
            "hairlab.eye.color",
            Self::COLOR,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
            &[Self::COLOR.remove_srgb_suffix()],
        );
        let depth = make(
            "hairlab.eye.depth",
            Self::DEPTH,
            // Bound as a texture by the passes that test it by hand (`common/mesh_depth.wgsl`).
            wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING,
            &[],
        );
        let null = make(
            "hairlab.eye.null_target",
            crate::render::passes::NULL_TARGET_FORMAT,
            wgpu::TextureUsages::empty(),
            &[],
        );
        EyeTargets {
            null_view: null.create_view(&Default::default()),
            color_view: color.create_view(&Default::default()),
            display_view: color.create_view(&wgpu::TextureViewDescriptor {
                label: Some("hairlab.eye.color_display"),
                format: Some(Self::COLOR.remove_srgb_suffix()),
                ..Default::default()
            }),
            color,
            depth_view: depth.create_view(&Default::default()),
            depth,
            width,
            height,
        }
    }

    /// Bytes of GPU memory the targets hold (colour, depth and the null target).
    pub fn bytes(&self) -> u64 {
        self.width as u64 * self.height as u64 * (4 + 4 + 1)
    }

    /// `null_view` as an attachment: loaded, discarded.
    pub fn null_attachment(&self) -> Option<wgpu::RenderPassColorAttachment<'_>> {
        Some(wgpu::RenderPassColorAttachment {
            view: &self.null_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Discard,
            },
        })
    }
}

/// Format of the capture target: a technique's resolve drawn onto it (cleared to zero) instead of the colour
/// image records the hair's premultiplied colour `H` and coverage `1 - T` in f32, what the GPU = CPU tests
/// compare with the CPU models.
pub const CAPTURE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// A viewport-sized 2D render target `hairlab.<…>` (`label`) of `format`, usable as `usage` too: the eye targets and
/// every transparency technique's targets.
pub fn eye_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    view_formats: &[wgpu::TextureFormat],
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | usage,
        view_formats,
    })
}
