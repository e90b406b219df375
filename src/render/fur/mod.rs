//! The GPU passes of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): [`density`], the undercoat's volume
//! generated on the GPU, [`shell_gpu`], its shell ray march into the eye lists, and [`typed`], the eye
//! transparency technique of typed per-pixel lists that combines its fragments with the guard hairs'; [`state`]
//! is the fur as the scene's content and as that technique reports it. The CPU model they equal is
//! [`crate::fur`].

pub mod density;
pub mod shell_gpu;
pub mod state;
pub mod typed;
