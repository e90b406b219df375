//! Weighted blended order-independent transparency (McGuire & Bavoil 2013): one hair pass into two targets,
//! an accumulation of weighted premultiplied colour (Rgba16Float, One/One) and the revealage, the product of
//! `1 - alpha` (R16Float, Zero/OneMinusSrc), resolved as their weighted average colour over the opaque image with
//! coverage `1 - revealage`. Order-independent and one pass, at the price of an approximate colour where
//! fragments of different colours overlap (the depth weight favours the nearer ones).

use super::{EyeTransparency, TechniqueInfo, TransparencyGpu};
use crate::render::passes::composite::CompositePass;
use crate::render::targets::eye_texture;

pub const ACCUM: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const REVEALAGE: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

const ADDITIVE: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

const REVEAL: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::Zero,
    dst_factor: wgpu::BlendFactor::OneMinusSrc,
    operation: wgpu::BlendOperation::Add,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "wboit",
    label: "Weighted blended OIT",
    paper: "McGuire & Bavoil 2013, Weighted Blended Order-Independent Transparency",
    store_wgsl: "transparency/wboit.wgsl",
    resolve_wgsl: "transparency/wboit_resolve.wgsl",
    hair_targets: &[
        wgpu::ColorTargetState {
            format: ACCUM,
            blend: Some(wgpu::BlendState {
                color: ADDITIVE,
                alpha: ADDITIVE,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        },
        wgpu::ColorTargetState {
            format: REVEALAGE,
            blend: Some(wgpu::BlendState {
                color: REVEAL,
                alpha: REVEAL,
            }),
            write_mask: wgpu::ColorWrites::RED,
        },
    ],
};

pub struct Wboit;

impl EyeTransparency for Wboit {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, device: &wgpu::Device, width: u32, height: u32) -> Box<dyn TransparencyGpu> {
        let tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.wboit.resolve_bind_group_layout"),
            entries: &[tex(0), tex(1)],
        });
        let resolve = CompositePass::new(
            device,
            "hairlab.wboit.resolve",
            INFO.resolve_wgsl,
            &layout,
            wgpu::BlendState::ALPHA_BLENDING,
        );
        let targets = WboitTargets::new(device, &layout, width, height);
        Box::new(WboitGpu {
            layout,
            resolve,
            targets,
        })
    }
}

/// The two targets at one viewport size and the resolve's bind group reading them.
struct WboitTargets {
    accum: wgpu::TextureView,
    revealage: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    width: u32,
    height: u32,
}

impl WboitTargets {
    fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, width: u32, height: u32) -> WboitTargets {
        let view = |label, format| {
            eye_texture(
                device,
                label,
                (width, height),
                format,
                wgpu::TextureUsages::TEXTURE_BINDING,
                &[],
            )
            .create_view(&Default::default())
        };
        let accum = view("hairlab.wboit.accum", ACCUM);
        let revealage = view("hairlab.wboit.revealage", REVEALAGE);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.wboit.resolve_bind_group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&accum),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&revealage),
                },
            ],
        });
        WboitTargets {
            accum,
            revealage,
            bind_group,
            width,
            height,
        }
    }
}

struct WboitGpu {
    layout: wgpu::BindGroupLayout,
    resolve: CompositePass,
    targets: WboitTargets,
}

impl TransparencyGpu for WboitGpu {
    fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        if (self.targets.width, self.targets.height) != (width, height) {
            self.targets = WboitTargets::new(device, &self.layout, width, height);
        }
    }

    fn hair_attachments(&self) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
        let clear = |view, r: f64| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r,
                        g: 0.0,
                        b: 0.0,
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        // Nothing accumulated, everything revealed.
        vec![
            clear(&self.targets.accum, 0.0),
            clear(&self.targets.revealage, 1.0),
        ]
    }

    fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        self.resolve
            .record(encoder, color, &self.targets.bind_group, timestamps);
    }

    fn memory_bytes(&self) -> u64 {
        let texel: u64 = INFO
            .hair_targets
            .iter()
            .filter_map(|t| t.format.block_copy_size(None))
            .map(u64::from)
            .sum();
        self.targets.width as u64 * self.targets.height as u64 * texel
    }
}
