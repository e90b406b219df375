//! The fur the typed-lists technique ([`super::typed`]) holds between frames: the shell built on the GPU from the
//! scene's fur when its generation changes (Table 1 row 2: its build time), the fur's settings and march, the
//! resolve's uniforms (Andersen et al. 2016 §4: the blending, the attenuation per unit, what the view shows) and
//! the typed fragments read back from the lists as the CPU blend ([`crate::fur::blend`]) takes them.

use std::time::Instant;

use crate::fur::blend::{self, Typed};
use crate::fur::march::MarchParams;
use crate::fur::settings::{Blending, FurSettings, FurView};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::lists::EyeNode;
use crate::scene::Light;

use super::shell_gpu::ShellGpu;
use super::state::SceneFur;

/// Mirrors `FurResolveUniforms` in `shaders/fur/resolve.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable, PartialEq)]
pub struct FurResolveUniforms {
    pub blending: u32,
    pub attenuation: f32,
    pub view: u32,
    pub deepest: u32,
}

impl FurResolveUniforms {
    /// The resolve of lists at most `deepest` fragments deep under `settings`.
    pub fn new(settings: &FurSettings, deepest: u32) -> FurResolveUniforms {
        FurResolveUniforms {
            blending: match settings.blending {
                Blending::Naive => 0,
                Blending::Simplified => 1,
                Blending::Virtual => 2,
            },
            attenuation: settings.attenuation_per_unit(),
            view: match settings.view {
                FurView::Shaded => 0,
                FurView::Types => 1,
                FurView::Fragments => 2,
            },
            deepest,
        }
    }
}

/// The shell on the GPU, the generation of the scene's fur it was built from and its build time.
pub struct HeldShell {
    pub gpu: ShellGpu,
    pub generation: u64,
    pub volume_ms: f64,
}

/// The scene's fur as the technique holds it; the defaults without fur.
#[derive(Default)]
pub struct HeldFur {
    pub shell: Option<HeldShell>,
    /// The fur's settings and march of the next frame (light from the frame).
    pub settings: FurSettings,
    march: Option<MarchParams>,
}

impl HeldFur {
    /// Brings the shell up to the scene's fur: built when its generation is new, dropped when the scene has none.
    pub fn sync(
        &mut self,
        gpu: &Gpu,
        frame_layout: &wgpu::BindGroupLayout,
        fur: Option<&SceneFur>,
    ) -> Result<(), GpuError> {
        let Some(fur) = fur else {
            *self = HeldFur::default();
            return Ok(());
        };
        if self.shell.as_ref().map(|s| s.generation) != Some(fur.generation) {
            self.shell = None;
            let start = Instant::now();
            let shell = ShellGpu::new(gpu, frame_layout, &fur.scene.shell, &fur.scene.volume)?;
            self.shell = Some(HeldShell {
                gpu: shell,
                generation: fur.generation,
                volume_ms: start.elapsed().as_secs_f64() * 1e3,
            });
        }
        self.settings = fur.settings.clone();
        self.march = Some(
            fur.settings
                .march_params(&fur.scene.shell, glam::Vec3::Y, glam::Vec3::ONE),
        );
        Ok(())
    }

    /// Writes the march's parameters under the frame's `light`.
    pub fn light(&self, queue: &wgpu::Queue, light: &Light) {
        if let (Some(held), Some(march)) = (&self.shell, &self.march) {
            held.gpu.set_params(
                queue,
                &MarchParams {
                    to_light: light.to_light(),
                    light: glam::Vec3::from_array(light.color) * light.intensity,
                    ..*march
                },
            );
        }
    }
}

/// A pixel's list nodes as typed fragments, front to back.
pub fn typed_fragments(nodes: Vec<EyeNode>) -> Vec<Typed> {
    let mut out: Vec<Typed> = nodes
        .into_iter()
        .map(|n| Typed {
            depth: n.depth,
            id: n.segment,
            kind: n.kind,
            colour: glam::Vec3::new(n.r, n.g, n.b),
            alpha: n.alpha,
        })
        .collect();
    blend::front_to_back(&mut out);
    out
}
