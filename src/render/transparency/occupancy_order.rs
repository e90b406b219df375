//! Occupancy-ordered blending (Sintorn & Assarsson 2009 §3.4): the Occupancy Maps of the light-space method
//! built from the camera give each hair fragment an approximate number `o` of fragments in front of it, so
//! unsorted fragments can be blended additively with their back-to-front weights. The CPU model is
//! `transparency::occupancy_order`.
//!
//! Three geometry passes over the strands, all with the shared eye vertex stage and tested `Less` against the
//! meshes' depth without writing (the hair pass's depth state, so every pass sees the same fragments; the
//! occupancy pass tests by hand, `common/mesh_depth.wgsl`, before its atomics):
//! 1. `eye: depth range`: the pixel's nearest and furthest eye depth, two R32Float targets cleared to (big, 0)
//!    with Min / Max blending (spec A.3 #7: the paper's two depth-test passes in one);
//! 2. `eye: occupancy + slabs`: the 128-slice occupancy bitmap and the 4 slab counts of the pixel, `atomicOr` /
//!    `atomicAdd` into two storage buffers of four u32 per pixel, exactly the light-space pass on eye pixels
//!    (relative depth `(depth - near_p) / (far_p - near_p)` with the step convention of a zero range);
//! 3. `eye: hair`: each shaded fragment adds `(w c, w)`, `w = exp(-o b̄) ᾱ`, into an Rgba32Float (or, to show
//!    why the paper needs 32 bits, Rgba16Float) One/One target; `ᾱ` is the global hair alpha
//!    (`frame.hair_alpha`) and `b̄ = -ln(1 - min(ᾱ, 1 - 1e-6))`: each fragment's own alpha is not used (the paper
//!    assumes one alpha, spec A.3 #4).
//!    In `render.alpha = "coverage"` mode `ᾱ` is still `render.hair_alpha` (there the material opacity).
//!
//! The resolve (`eye: resolve`) sums the four slab counts to `n`, puts `T = exp(-n b̄)` on the background and
//! `Λ = 1 - T` of hair over it; with the correction on the colour is rescaled to `rgb · Λ / acc.a` (the reading
//! of A.3 #1 that makes the total weight Λ), output `(rgb, Λ)` with [`PREMULTIPLIED_OVER`]. Pixels without
//! fragments are left untouched.
//!
//! Memory: 4 + 4 (depth range) + 16 (bitmap) + 16 (slabs) + 16 (accumulation) = 56 bytes per pixel at f32, 48 at
//! f16. The buffers must fit the device's storage binding size (128 MiB on lavapipe: 8,388,608 pixels).

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry,
    PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::{self, LinePass, Resolve};
use crate::render::eye::pipelines::{self, DepthTest, GeometryPass, additive};
use crate::render::eye::targets::{self, Textures};
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role, UniformMirror, value};
use crate::render::passes::abuffer::copy_out;
use crate::render::passes::shader_module;
use crate::render::targets::EyeTargets;
use crate::transparency::occupancy_order::OccupancyOrderParams;
use crate::transparency::{Compositor, ModelContext};
use crate::visibility::OccupancyVariant;
use bytemuck::{Pod, Zeroable};

/// Format of the two depth-range targets.
pub const RANGE: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Bytes per pixel of each of the two storage buffers (four u32).
pub const BUFFER_BYTES_PER_PIXEL: u64 = 16;
/// Largest per-channel |C_gpu - C_cpu| with `precision = f16`: the model rounds to f16 after every blend in
/// submission order, the GPU's blend order differs; measured 5.4e-4 on lavapipe (tests/it/transparency_occupancy.rs).
pub const F16_GPU_TOLERANCE: f32 = 1e-3;
/// The depth-range targets' clear value of `near` (beyond any eye depth; `far` clears to 0).
const NEAR_CLEAR: f64 = 1e30;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        key: "variant",
        label: "variant",
        help: "slab-map: occupancy map + slab map (4 slabs of 32 slices, the paper's method); occupancy-only: the \
               occupancy map with one count for the whole range",
        kind: ParamKind::Choice {
            options: &["slab-map", "occupancy-only"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "correction",
        label: "Λ correction",
        help: "on: rescale the hair colour so its total weight is Λ = 1 - (1 - α)^n (S&A §3.4); off: the plain sum",
        kind: ParamKind::Choice {
            options: &["on", "off"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "order_bias",
        label: "order bias",
        help: "paper: the paper's estimate; half: subtract ½ from every order estimate (clamped at 0), the \
               estimate's mean bias",
        kind: ParamKind::Choice {
            options: &["paper", "half"],
        },
        default: 0.0,
    },
    ParamSpec {
        key: "precision",
        label: "accumulation",
        help: "f32: Rgba32Float accumulation (the paper's 32-bit target); f16: Rgba16Float, to show why it is needed",
        kind: ParamKind::Choice {
            options: &["f32", "f16"],
        },
        default: 0.0,
    },
];

/// The technique's parameters from `values` (missing keys take their defaults).
fn params(values: &ParamValues) -> OccupancyOrderParams {
    let on = |i: usize| value(values, &PARAMS[i]) >= 0.5;
    OccupancyOrderParams {
        variant: if on(0) {
            OccupancyVariant::OccupancyOnly
        } else {
            OccupancyVariant::SlabMap
        },
        lambda_correction: !on(1),
        order_bias: if on(2) { -0.5 } else { 0.0 },
        half_precision: on(3),
    }
}

static ACCUM_F32: [wgpu::ColorTargetState; 1] =
    [additive(wgpu::TextureFormat::Rgba32Float, wgpu::ColorWrites::ALL)];
static ACCUM_F16: [wgpu::ColorTargetState; 1] =
    [additive(wgpu::TextureFormat::Rgba16Float, wgpu::ColorWrites::ALL)];

static HAIR: [HairEntry; 2] = [
    HairEntry {
        entry: "fs_main",
        targets: &ACCUM_F32,
        depth: EntryDepth::Meshes,
        geometry: HairGeometry::Lines,
    },
    HairEntry {
        entry: "fs_half",
        targets: &ACCUM_F16,
        depth: EntryDepth::Meshes,
        geometry: HairGeometry::Lines,
    },
];

static INFO: TechniqueInfo = TechniqueInfo {
    name: "occupancy-order",
    label: "Occupancy-ordered blending",
    paper: "Sintorn & Assarsson 2009, Hair Self Shadowing and Transparency Depth Ordering Using Occupancy Maps, §3.4",
    role: Role::Approximation,
    hair_wgsl: "transparency/occupancy_order.wgsl",
    hair_entries: &HAIR,
    pass_wgsl: &[
        "transparency/occupancy_order_maps.wgsl",
        "transparency/occupancy_order_resolve.wgsl",
    ],
    params: PARAMS,
    color: [86, 180, 233],
    // f32 sums of the same f32 weights in another order: measured 8.9e-8 on lavapipe (tests/it/transparency_gpu.rs,
    // 160×120, deepest pixel 50). The f16 accumulation has its own bound, F16_GPU_TOLERANCE.
    gpu_tolerance: 1e-6,
};

pub struct OccupancyOrder;

/// The WGSL mirror of [`OccupancyOrderUniforms`] (`common/occupancy_order_uniforms.wgsl`), for the layout test.
pub fn uniform_mirror() -> UniformMirror {
    crate::uniform_mirror!(
        "OccupancyOrderUniforms",
        OccupancyOrderUniforms {
            variant,
            correction,
            order_bias,
            hair_alpha
        }
    )
}

/// Mirrors `OccupancyOrderUniforms` in `shaders/common/occupancy_order_uniforms.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct OccupancyOrderUniforms {
    /// 0: slab map, 1: occupancy only.
    pub variant: u32,
    /// 1: the Λ correction on.
    pub correction: u32,
    /// Added to every order estimate before clamping at 0.
    pub order_bias: f32,
    /// The global hair alpha.
    pub hair_alpha: f32,
}

impl OccupancyOrderUniforms {
    fn new(p: &OccupancyOrderParams, hair_alpha: f32) -> Self {
        Self {
            variant: u32::from(p.variant == OccupancyVariant::OccupancyOnly),
            correction: u32::from(p.lambda_correction),
            order_bias: p.order_bias,
            hair_alpha,
        }
    }
}

impl EyeTransparency for OccupancyOrder {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(OccupancyOrderGpu::new(setup)?))
    }

    fn model(&self, values: &ParamValues, ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(params(values).model(ctx))
    }

    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(uniform_mirror())
    }

    /// The paper's method and each option on its own: occupancy only, no Λ correction, the −½ bias, f16.
    fn sweep(&self) -> Vec<ParamValues> {
        let one = |key: &str| ParamValues::from([(key.to_string(), 1.0)]);
        vec![
            ParamValues::new(),
            one("variant"),
            one("correction"),
            one("order_bias"),
            one("precision"),
        ]
    }
}

/// The maps' group: the two depth ranges, the bitmap, the slab counts and the uniforms; group 2 of the hair
/// pass (read-only), or group 1 of the occupancy pass (writable, and the meshes' depth it tests by hand).
fn maps_group(occupancy_pass: bool) -> &'static [Binding] {
    use Binding::{MeshDepth, StorageRo, StorageRw, Texture, Uniform};
    if occupancy_pass {
        &[Texture, Texture, StorageRw, StorageRw, Uniform, MeshDepth]
    } else {
        &[Texture, Texture, StorageRo, StorageRo, Uniform]
    }
}

/// Occupancy-ordered blending's GPU state, created with its maps (so they always exist).
pub struct OccupancyOrderGpu {
    range_pipeline: wgpu::RenderPipeline,
    slabs_pipeline: wgpu::RenderPipeline,
    pass_layout: wgpu::BindGroupLayout,
    hair_layout: wgpu::BindGroupLayout,
    resolve: Resolve,
    uniforms: wgpu::Buffer,
    /// The two depth ranges and the accumulation.
    targets: Textures,
    bits: wgpu::Buffer,
    slabs: wgpu::Buffer,
}

/// The occupancy bitmap and the slab counts for a `size` viewport; refused beyond the device's storage binding
/// size.
fn map_buffers(gpu: &Gpu, (width, height): (u32, u32)) -> Result<[wgpu::Buffer; 2], GpuError> {
    let what = format!(
        "occupancy-order's occupancy bitmap and slab map at the {width}×{height} viewport \
         ({BUFFER_BYTES_PER_PIXEL} bytes per pixel each; make the viewport smaller)"
    );
    let bytes = width as u64 * height as u64 * BUFFER_BYTES_PER_PIXEL;
    Ok([
        targets::storage(gpu, INFO.name, "bitmap", &what, bytes)?,
        targets::storage(gpu, INFO.name, "slabs", &what, bytes)?,
    ])
}

impl OccupancyOrderGpu {
    fn new(setup: &EyeSetup) -> Result<OccupancyOrderGpu, GpuError> {
        let device = &setup.gpu.device;
        let pass_layout = bindings::layout(device, "hairlab.occupancy-order.pass_layout", maps_group(true));
        let module = shader_module(
            device,
            "hairlab.occupancy-order.maps_shader",
            INFO.pass_wgsl[0],
            None,
        );
        let range_target = |op| {
            Some(wgpu::ColorTargetState {
                format: RANGE,
                blend: Some(wgpu::BlendState {
                    color: wgpu::BlendComponent {
                        src_factor: wgpu::BlendFactor::One,
                        dst_factor: wgpu::BlendFactor::One,
                        operation: op,
                    },
                    alpha: wgpu::BlendComponent::REPLACE,
                }),
                write_mask: wgpu::ColorWrites::RED,
            })
        };
        let pass = |label, layouts, fragment, targets, depth| {
            pipelines::geometry(
                device,
                &GeometryPass {
                    label,
                    module: &module,
                    layouts,
                    geometry: HairGeometry::Lines,
                    fragment,
                    targets,
                    depth,
                },
            )
        };
        let size = (setup.width, setup.height);
        let [bits, slabs] = map_buffers(setup.gpu, size)?;
        Ok(OccupancyOrderGpu {
            range_pipeline: pass(
                "hairlab.occupancy-order.range_pipeline",
                &[setup.frame_layout],
                "fs_range",
                &[
                    range_target(wgpu::BlendOperation::Min),
                    range_target(wgpu::BlendOperation::Max),
                ],
                Some(DepthTest::Meshes),
            ),
            // The slabs' entry tests the meshes' depth by hand, before its atomics.
            slabs_pipeline: pass(
                "hairlab.occupancy-order.slabs_pipeline",
                &[setup.frame_layout, &pass_layout],
                "fs_slabs",
                &[Some(EyeTargets::NULL)],
                None,
            ),
            pass_layout,
            hair_layout: bindings::layout(device, "hairlab.occupancy-order.hair_layout", maps_group(false)),
            resolve: Resolve::new(
                device,
                INFO.name,
                INFO.pass_wgsl[1],
                &[Binding::Texture, Binding::StorageRo, Binding::Uniform],
                PREMULTIPLIED_OVER,
            ),
            uniforms: bindings::uniform(
                device,
                "hairlab.occupancy-order.uniforms",
                std::mem::size_of::<OccupancyOrderUniforms>() as u64,
            ),
            targets: Textures::new(
                device,
                INFO.name,
                &[
                    ("near", RANGE),
                    ("far", RANGE),
                    ("accum", HAIR[0].targets[0].format),
                ],
                size,
            ),
            bits,
            slabs,
        })
    }

    /// The slab counts of the last frame, four u32 per pixel, row-major (occupancy-only: the total in the first):
    /// `n` of a pixel is their sum.
    pub fn read_slabs(&self, gpu: &Gpu) -> Result<Vec<[u32; 4]>, GpuError> {
        Ok(bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.slabs)?))
    }

    /// A group of [`maps_group`] over the maps; for the occupancy pass with the meshes' depth.
    fn maps_bind_group(
        &self,
        device: &wgpu::Device,
        mesh_depth: Option<&wgpu::TextureView>,
    ) -> wgpu::BindGroup {
        let (label, layout) = match mesh_depth {
            Some(_) => ("hairlab.occupancy-order.pass_bind_group", &self.pass_layout),
            None => ("hairlab.occupancy-order.hair_bind_group", &self.hair_layout),
        };
        let mut resources = vec![
            wgpu::BindingResource::TextureView(self.targets.view(0)),
            wgpu::BindingResource::TextureView(self.targets.view(1)),
            self.bits.as_entire_binding(),
            self.slabs.as_entire_binding(),
            self.uniforms.as_entire_binding(),
        ];
        resources.extend(mesh_depth.map(wgpu::BindingResource::TextureView));
        bindings::group(device, label, layout, &resources)
    }
}

impl TransparencyGpu for OccupancyOrderGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if self.targets.size() != (width, height) {
            [self.bits, self.slabs] = map_buffers(gpu, (width, height))?;
            self.targets.resize(&gpu.device, (width, height));
        }
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let p = params(frame.values);
        let hair = &HAIR[usize::from(p.half_precision)];
        self.targets
            .set_format(&frame.gpu.device, 2, hair.targets[0].format);
        frame.gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&OccupancyOrderUniforms::new(&p, frame.model.hair_alpha)),
        );
        let [near, far, accum] = [0, 1, 2].map(|i| self.targets.view(i));
        passes::record_lines(
            frame,
            LinePass {
                label: "hairlab.occupancy-order.range_pass",
                timer: "eye: depth range",
                pipeline: &self.range_pipeline,
                group: None,
                attachments: &[cleared(near, [NEAR_CLEAR, 0.0, 0.0, 0.0]), cleared(far, [0.0; 4])],
                mesh_depth: true,
            },
        );
        frame.encoder.clear_buffer(&self.bits, 0, None);
        frame.encoder.clear_buffer(&self.slabs, 0, None);
        // The meshes' depth is tested by hand before the atomics (a fixed-function test after the shader would
        // not undo them); the depth view is the frame's, so the group is too.
        let pass_group = self.maps_bind_group(&frame.gpu.device, Some(&frame.targets.depth_view));
        passes::record_line_count(
            frame,
            "hairlab.occupancy-order.slabs_pass",
            "eye: occupancy + slabs",
            &self.slabs_pipeline,
            &pass_group,
        );
        let hair_group = self.maps_bind_group(&frame.gpu.device, None);
        frame.draw_hair(
            HairDrawPass {
                entry: hair,
                attachments: &[cleared(accum, [0.0; 4])],
                depth: None,
                group: Some((&self.hair_layout, &hair_group)),
                rows: None,
            },
            "eye: hair",
        );
        self.resolve.record(
            frame,
            &[
                wgpu::BindingResource::TextureView(accum),
                self.slabs.as_entire_binding(),
                self.uniforms.as_entire_binding(),
            ],
        );
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.targets.bytes() + self.bits.size() + self.slabs.size()
    }

    fn geometry_passes(&self) -> u32 {
        3
    }
}

/// The slab counts of the last frame `renderer` drew with occupancy-order (see [`OccupancyOrderGpu::read_slabs`]).
pub fn read_slabs(renderer: &crate::render::Renderer) -> Result<Vec<[u32; 4]>, GpuError> {
    let state = renderer.transparency_gpu().map(|t| t as &dyn std::any::Any);
    state
        .and_then(|t| t.downcast_ref::<OccupancyOrderGpu>())
        .ok_or_else(|| {
            GpuError::Setting("transparency.name: the last frame was not drawn with occupancy-order".into())
        })?
        .read_slabs(renderer.gpu())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(pairs: &[(&str, &str)]) -> OccupancyOrderParams {
        let values: ParamValues = pairs
            .iter()
            .map(|(k, v)| {
                let spec = PARAMS.iter().find(|p| p.key == *k).unwrap();
                (k.to_string(), spec.parse(v).unwrap())
            })
            .collect();
        params(&values)
    }

    #[test]
    fn defaults_are_the_papers_method() {
        assert_eq!(parsed(&[]), OccupancyOrderParams::default());
        let u = OccupancyOrderUniforms::new(&parsed(&[]), 0.35);
        assert_eq!(
            u,
            OccupancyOrderUniforms {
                variant: 0,
                correction: 1,
                order_bias: 0.0,
                hair_alpha: 0.35
            }
        );
    }

    #[test]
    fn every_word_reaches_the_model_and_the_uniforms() {
        let p = parsed(&[
            ("variant", "occupancy-only"),
            ("correction", "off"),
            ("order_bias", "half"),
            ("precision", "f16"),
        ]);
        assert_eq!(
            p,
            OccupancyOrderParams {
                variant: OccupancyVariant::OccupancyOnly,
                lambda_correction: false,
                order_bias: -0.5,
                half_precision: true,
            }
        );
        let u = OccupancyOrderUniforms::new(&p, 0.2);
        assert_eq!((u.variant, u.correction, u.order_bias), (1, 0, -0.5));
        assert_eq!(
            HAIR[usize::from(p.half_precision)].targets[0].format,
            wgpu::TextureFormat::Rgba16Float
        );
    }
}
