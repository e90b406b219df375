//! Moment-based order-independent transparency (Münstermann, Krumpen, Klein & Peters 2018), 4 or 6 power
//! moments of the absorbance. Pass 1 (`eye: moments`, depth-tested against the meshes like the hair pass)
//! adds `b_0 = Σ b` and `Σ b x^j` (`x = 2z − 1`, `z` the depth normalised over the frame's eye range) into two
//! additive RGBA32F targets; pass 2, the shaded hair entry, reconstructs each fragment's transmittance `T(z)`
//! from them with the moment shadow map's bound (`common/msm_bound.wgsl`) and adds `(a c T, a T)` into a third;
//! the resolve covers the normalised colour with the exact `1 − exp(−b_0)`. Two geometry passes, 48 B per pixel.
//! CPU model: [`crate::transparency::Mboit`].

use super::{
    EntryDepth, EyeFrame, EyeSetup, EyeTransparency, HairDrawPass, HairEntry, HairGeometry,
    PREMULTIPLIED_OVER, TechniqueInfo, TransparencyGpu, cleared,
};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::{self, LinePass, Resolve};
use crate::render::eye::pipelines::{self, DepthTest, GeometryPass, additive};
use crate::render::eye::targets::Textures;
use crate::render::method::{ParamKind, ParamSpec, ParamValues, Role, value};
use crate::transparency::{Compositor, MboitParams, ModelContext};
use crate::visibility::msm::DEFAULT_OVERESTIMATION;
use bytemuck::{Pod, Zeroable};

/// Format of the moment targets and the weighted colour sum.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

const ADD: wgpu::ColorTargetState = additive(FORMAT, wgpu::ColorWrites::ALL);

static HAIR: HairEntry = HairEntry {
    entry: "fs_main",
    targets: &[ADD],
    depth: EntryDepth::Meshes,
    geometry: HairGeometry::Lines,
};

const MOMENTS: ParamSpec = ParamSpec {
    key: "moments",
    label: "moments",
    help: "power moments of the absorbance beyond b0 (MBOIT-4 or MBOIT-6, each at MBOIT's f32 moment bias)",
    kind: ParamKind::Choice { options: &["4", "6"] },
    default: 0.0,
};
const OVERESTIMATION: ParamSpec = ParamSpec {
    key: "overestimation",
    label: "overestimation",
    help: "weight of the support point at the fragment's own depth: 0 the lower bound, 1 the upper (MBOIT: 0.25)",
    kind: ParamKind::Float {
        min: 0.0,
        max: 1.0,
        log: false,
    },
    default: DEFAULT_OVERESTIMATION,
};

static INFO: TechniqueInfo = TechniqueInfo {
    name: "mboit",
    label: "Moment-based OIT",
    paper: "Münstermann, Krumpen, Klein & Peters 2018, Moment-Based Order-Independent Transparency",
    role: Role::Approximation,
    hair_wgsl: "transparency/mboit.wgsl",
    hair_entries: std::slice::from_ref(&HAIR),
    pass_wgsl: &[
        "transparency/mboit_moments.wgsl",
        "transparency/mboit_resolve.wgsl",
    ],
    params: &[MOMENTS, OVERESTIMATION],
    color: [170, 68, 153],
    // The bound amplifies the f32 rounding of the moment sums, which the GPU adds in another order (see
    // `transparency::mboit`). Measured on lavapipe, 160x120 head (tests/it/transparency_gpu.rs): 3.7e-4 at the
    // defaults (4 moments); 1.4e-4 with 6; 5.5e-4 with 4 and overestimation 0; 2.2e-4 with 6 and 1.
    gpu_tolerance: 1e-3,
};

/// The model's parameters from `values`.
fn params(values: &ParamValues) -> MboitParams {
    let mut p = MboitParams::with_moments(if value(values, &MOMENTS) >= 1.0 { 6 } else { 4 });
    p.moments.overestimation = value(values, &OVERESTIMATION);
    p
}

pub struct MomentBasedOit;

impl EyeTransparency for MomentBasedOit {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(MboitGpu::new(setup)))
    }

    fn model(&self, values: &ParamValues, ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(params(values).model(ctx))
    }

    fn uniform_mirror(&self) -> Option<crate::render::method::UniformMirror> {
        Some(crate::uniform_mirror!(
            "MboitUniforms",
            MboitUniforms {
                near,
                far,
                moments,
                bias,
                overestimation,
                pad0,
                pad1,
                pad2
            }
        ))
    }
}

/// Mirrors `MboitUniforms` in `shaders/common/mboit.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct MboitUniforms {
    pub near: f32,
    pub far: f32,
    pub moments: u32,
    pub bias: f32,
    pub overestimation: f32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

impl MboitUniforms {
    fn new(values: &ParamValues, ctx: &ModelContext) -> Self {
        let p = params(values).moments;
        MboitUniforms {
            near: ctx.depth_range[0],
            far: ctx.depth_range[1],
            moments: p.moment_count() as u32,
            bias: p.bias,
            overestimation: p.overestimation,
            ..Zeroable::zeroed()
        }
    }
}

struct MboitGpu {
    uniforms: wgpu::Buffer,
    moments_group: wgpu::BindGroup,
    moments_pipeline: wgpu::RenderPipeline,
    hair_layout: wgpu::BindGroupLayout,
    resolve: Resolve,
    /// The weighted colour sum, then the moments `(b_0, b x, b x², b x³)` and the higher ones.
    targets: Textures,
}

impl MboitGpu {
    fn new(setup: &EyeSetup) -> MboitGpu {
        let device = &setup.gpu.device;
        let uniforms = bindings::uniform(
            device,
            "hairlab.mboit.uniforms",
            std::mem::size_of::<MboitUniforms>() as u64,
        );
        let moments_layout = bindings::layout(device, "hairlab.mboit.moments_layout", &[Binding::Uniform]);
        let moments_group = bindings::group(
            device,
            "hairlab.mboit.moments_group",
            &moments_layout,
            &[uniforms.as_entire_binding()],
        );
        let module = crate::render::passes::shader_module(
            device,
            "hairlab.mboit.moments_shader",
            INFO.pass_wgsl[0],
            None,
        );
        // The hair pass's test: Less against the meshes, no write (no storage writes, so fixed function).
        let moments_pipeline = pipelines::geometry(
            device,
            &GeometryPass {
                label: "hairlab.mboit.moments_pipeline",
                module: &module,
                layouts: &[setup.frame_layout, &moments_layout],
                geometry: HairGeometry::Lines,
                fragment: "fs_main",
                targets: &[Some(ADD), Some(ADD)],
                depth: Some(DepthTest::Meshes),
            },
        );
        MboitGpu {
            moments_group,
            moments_pipeline,
            hair_layout: bindings::layout(
                device,
                "hairlab.mboit.hair_layout",
                &[Binding::Uniform, Binding::Texture, Binding::Texture],
            ),
            resolve: Resolve::of_textures(device, INFO.name, INFO.pass_wgsl[1], 2, PREMULTIPLIED_OVER),
            targets: Textures::new(
                device,
                INFO.name,
                &[
                    ("accum", FORMAT),
                    ("moments_low", FORMAT),
                    ("moments_high", FORMAT),
                ],
                (setup.width, setup.height),
            ),
            uniforms,
        }
    }
}

impl TransparencyGpu for MboitGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.targets.resize(&gpu.device, (width, height));
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let u = MboitUniforms::new(frame.values, &frame.model);
        frame
            .gpu
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let [accum, low, high] = [0, 1, 2].map(|i| self.targets.view(i));
        passes::record_lines(
            frame,
            LinePass {
                label: "hairlab.mboit.moments_pass",
                timer: "eye: moments",
                pipeline: &self.moments_pipeline,
                group: Some(&self.moments_group),
                attachments: &[cleared(low, [0.0; 4]), cleared(high, [0.0; 4])],
                mesh_depth: true,
            },
        );
        let hair_group = bindings::group(
            &frame.gpu.device,
            "hairlab.mboit.hair_group",
            &self.hair_layout,
            &[
                self.uniforms.as_entire_binding(),
                wgpu::BindingResource::TextureView(low),
                wgpu::BindingResource::TextureView(high),
            ],
        );
        frame.draw_hair(
            HairDrawPass {
                entry: &HAIR,
                attachments: &[cleared(accum, [0.0; 4])],
                depth: None,
                group: Some((&self.hair_layout, &hair_group)),
                rows: None,
            },
            "eye: hair",
        );
        self.resolve.record_textures(frame, &[accum, low]);
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.targets.bytes() + self.uniforms.size()
    }

    fn geometry_passes(&self) -> u32 {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_follow_the_model() {
        let six = ParamValues::from([
            (MOMENTS.key.to_string(), 1.0),
            (OVERESTIMATION.key.to_string(), 0.5),
        ]);
        let p = params(&six);
        assert_eq!(p.moments.moments, 6);
        assert_eq!(p.moments.bias, crate::visibility::msm::DEFAULT_BIAS_6);
        assert_eq!(p.moments.overestimation, 0.5);
        assert_eq!(params(&ParamValues::new()), MboitParams::with_moments(4));
    }
}
