//! The GPU passes of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): [`density`], the undercoat's volume
//! generated on the GPU, [`shell_gpu`], its shell ray march into the eye lists, and [`typed`], the eye
//! transparency technique of typed per-pixel lists that combines its fragments with the guard hairs', [`held`]
//! the fur that technique holds between frames (shell, settings, resolve uniforms); [`state`] is the fur as the
//! scene's content and as that technique reports it. The CPU model they equal is
//! [`crate::fur`].

pub mod density;
pub mod held;
pub mod shell_gpu;
pub mod state;
pub mod typed;

use crate::gpu::GpuError;
use crate::render::Renderer;

/// The scene's fur as renderer input.
impl Renderer {
    /// Gives the scene `fur` (its shell, volume and settings; `None`, or a mode of off: no fur). The technique
    /// that shows fur builds its GPU state from it at the next frame; a frame with another technique is refused.
    pub fn set_fur(
        &mut self,
        fur: Option<(
            &crate::fur::settings::FurScene,
            &crate::fur::settings::FurSettings,
        )>,
    ) -> Result<(), GpuError> {
        self.fur = fur
            .filter(|(_, s)| s.mode != crate::fur::settings::FurMode::Off)
            .map(|(scene, settings)| {
                self.fur_generation += 1;
                state::SceneFur {
                    scene: scene.clone(),
                    settings: settings.clone(),
                    generation: self.fur_generation,
                }
            });
        Ok(())
    }

    /// Changes the fur's rendering (mode, blending, `a`, `k`, march) without rebuilding its shell: the caller keeps
    /// the shell's own settings (height, layers, levels, noise) those it was built with.
    pub fn set_fur_rendering(&mut self, settings: &crate::fur::settings::FurSettings) {
        if let Some(f) = &mut self.fur {
            f.settings = settings.clone();
        }
    }

    /// The fur the last frame's technique shows (its shell, its last lists, the volume's build time).
    pub fn fur_state(&self) -> Option<state::FurState<'_>> {
        self.transparency.as_ref().and_then(|(_, t)| t.fur())
    }
}
