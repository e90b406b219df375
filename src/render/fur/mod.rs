//! The GPU passes of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): [`density`], the undercoat's volume
//! generated on the GPU, [`shell_gpu`], its shell ray march into the eye lists, and [`typed`], the typed
//! per-pixel lists that combine its fragments with the guard hairs'. The CPU model they equal is [`crate::fur`].

pub mod density;
pub mod shell_gpu;
pub mod typed;
