//! Fourier Opacity Mapping (Jansen & Bavoil, I3D 2010): the absorption density along each light ray as a
//! Fourier series of `K` terms (1..=16) over the strands' whole fitted light range; `V(z)` integrates the
//! series from 0 to `z`. The CPU model (and the exact f32 expressions) is `visibility::fom`.
//!
//! GPU: the `2K + 1` coefficients live in an RGBA32F array texture (4 per layer, `ceil((2K + 1) / 4)` layers:
//! 16 bytes per texel for K = 1, 32 for K = 3 (the default), 48 for K = 4, 80 for K = 8, 144 for K = 16), filled
//! by additive light passes of at most 8 layers (32 coefficients) each: one geometry pass up to K = 15, two for
//! K = 16. The lookup reads no shared map. The GPU side is `methods::opacity_layers` with this method's shader
//! and uniforms. `SWEEP_TERMS` (2, 3, 4, 8, 16) are the bench's term counts, each with both windows; the GPU =
//! CPU tolerance (2e-5) is stated with its measurement at `INFO`.

use super::opacity_layers::{LayerBuild, LayerMethod, LayerSetup, LayersGpu};
use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::GpuError;
use crate::visibility::TexelModel;
use crate::visibility::fom::{DEFAULT_TERMS, FomParams, FomWindow, MAX_TERMS};
use bytemuck::{Pod, Zeroable};

const TERMS: ParamSpec = ParamSpec {
    key: "terms",
    label: "Fourier terms",
    help: "Fourier terms K of the absorption density (2K + 1 coefficients; the paper's 7 coefficients are K = 3)",
    kind: ParamKind::Int {
        min: 1,
        max: MAX_TERMS as i32,
    },
    default: DEFAULT_TERMS as f32,
};
const WINDOW: ParamSpec = ParamSpec {
    key: "window",
    label: "window",
    help: "plain: the paper's plain truncation (rings around sharp absorbers); fejer: weights 1 - k/(K+1), a \
           monotone but blurrier reconstruction",
    kind: ParamKind::Choice {
        options: &["plain", "fejer"],
    },
    default: 1.0,
};
const PARAMS: &[ParamSpec] = &[TERMS, WINDOW];

pub struct Fom;

static INFO: MethodInfo = MethodInfo {
    name: "fom",
    label: "Fourier opacity maps",
    paper: "Jansen & Bavoil 2010 (Fourier Opacity Mapping, I3D)",
    role: Role::Approximation,
    lookup_wgsl: "methods/fom.wgsl",
    light_wgsl: &["fom.wgsl"],
    params: PARAMS,
    color: [57, 59, 121],
    // The GPU's sin/cos and the blending order of the coefficient sums differ from the CPU's in the last bits,
    // and each coefficient sums them over every fragment of the texel. Measured on lavapipe (tests/it/gpu_fom.rs):
    // max |ΔV| 1.0e-6 over 25,810 samples at 64², 3.2e-6 with every fragment of 300 strands in one texel;
    // 2e-5 leaves 6x. (Vulkan allows hardware sin/cos an absolute error of 2^-11: a hardware GPU can differ
    // more.)
    gpu_tolerance: 2e-5,
    gpu_outliers: 0.0,
};

/// The bench's term counts, each with both windows.
const SWEEP_TERMS: &[u32] = &[2, 3, 4, 8, 16];

fn fom_params(values: &ParamValues) -> FomParams {
    FomParams {
        terms: value(values, &TERMS) as u32,
        window: FomWindow::from_index(value(values, &WINDOW) as u32),
    }
}

fn config(terms: u32, window: FomWindow) -> ParamValues {
    ParamValues::from([
        (TERMS.key.to_string(), terms as f32),
        (WINDOW.key.to_string(), window.index() as f32),
    ])
}

impl LightMethod for Fom {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "FomUniforms",
            FomUniforms {
                terms,
                window,
                pad0,
                pad1
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        let method = LayerMethod {
            name: INFO.name,
            unit: "coefficients",
            shader: "fom.wgsl",
            setup: fom_setup,
        };
        Ok(Box::new(LayersGpu::create(ctx, method)?))
    }
}

impl ShadowMethod for Fom {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(fom_params(values))
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        [FomWindow::None, FomWindow::Fejer]
            .iter()
            .flat_map(|&w| SWEEP_TERMS.iter().map(move |&k| (k, w)))
            .map(|(k, w)| SweepPoint {
                values: config(k, w),
                analysed: false,
            })
            .collect()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::new()]
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![
            config(DEFAULT_TERMS, FomWindow::Fejer),
            config(4, FomWindow::None),
            config(16, FomWindow::None),
        ]
    }
}

/// Mirrors `FomUniforms` in `shaders/common/fom_uniforms.wgsl` (included by the light pass and the lookup).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FomUniforms {
    /// `K`, in `1..=16`.
    pub terms: u32,
    /// 0 plain, 1 Fejér ([`FomWindow::index`]).
    pub window: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// The coefficient count and uniforms for `values` (the map holds `ceil((2K + 1) / 4)` RGBA layers).
fn fom_setup(values: &ParamValues) -> LayerSetup<FomUniforms> {
    let p = fom_params(values);
    LayerSetup {
        values: p.coefficient_count() as u32,
        depth_maps: 0,
        build: LayerBuild::Targets,
        uniforms: FomUniforms {
            terms: p.term_count() as u32,
            window: p.window.index(),
            ..Zeroable::zeroed()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setup_counts_coefficients_and_clamps_terms() {
        let s = fom_setup(&config(16, FomWindow::None));
        assert_eq!((s.values, s.uniforms.terms, s.uniforms.window), (33, 16, 0));
        let s = fom_setup(&ParamValues::new());
        assert_eq!((s.values, s.uniforms.terms, s.uniforms.window), (7, 3, 1));
        assert_eq!(fom_setup(&config(40, FomWindow::Fejer)).values, 33);
    }

    #[test]
    fn sweep_has_both_windows_at_every_term_count() {
        let sweep = Fom.sweep();
        assert_eq!(sweep.len(), 2 * SWEEP_TERMS.len());
        assert_eq!(sweep[0].values, config(2, FomWindow::None));
        assert_eq!(sweep.last().unwrap().values, config(16, FomWindow::Fejer));
    }
}
