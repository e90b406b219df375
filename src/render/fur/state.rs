//! What the eye side sees of a scene's fur: the fur as scene content ([`SceneFur`], what the renderer is given
//! and a technique that shows fur builds its GPU state from) and what such a technique reports back
//! ([`FurState`]: its shell, its last frame's typed lists, the volume's build time).

use crate::fur::blend::Typed;
use crate::fur::settings::{FurScene, FurSettings};
use crate::gpu::{Gpu, GpuError};

use super::shell_gpu::ShellGpu;

/// A scene's fur as the renderer holds it: the shell and volume built on the CPU, the settings of the next frame,
/// and a generation that changes when the shell or volume does (the settings alone change how a frame renders).
#[derive(Clone, Debug)]
pub struct SceneFur {
    pub scene: FurScene,
    pub settings: FurSettings,
    pub generation: u64,
}

/// The last frame's list figures, by fragment type (Table 1 rows 4 and 6).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FurListStats {
    /// Explicit (guard-hair) fragments.
    pub explicit: u64,
    /// Shell or virtual fragments.
    pub shell: u64,
    /// The deepest pixel's list.
    pub deepest: u32,
    /// Bands of rows the frame was filled and resolved in.
    pub bands: u32,
    /// Bytes of the largest band's nodes.
    pub node_bytes: u64,
}

/// The typed lists of a frame drawn with fur.
pub trait FurLists {
    /// The last frame's list figures.
    fn stats(&self) -> FurListStats;
    /// The last frame's typed lists (row-major, each front to back in the resolve's order).
    fn typed_lists(&self, gpu: &Gpu) -> Result<Vec<Vec<Typed>>, GpuError>;
}

/// The fur a technique shows, for the panel, `measure` and the tests.
pub struct FurState<'a> {
    pub shell: &'a ShellGpu,
    /// The typed lists of the last frame (none before the first fur frame).
    pub lists: Option<&'a dyn FurLists>,
    /// Table 1 row 2: the shell uploaded and its volume computed on the GPU (wall time of `ShellGpu::new`, ms).
    pub volume_ms: f64,
}
