//! The GPU passes of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): [`shell_gpu`], the undercoat's shell ray
//! march into the eye lists, and [`typed`], the typed per-pixel lists that combine its fragments with the guard
//! hairs'. The CPU model they equal is [`crate::fur`].

pub mod shell_gpu;
pub mod typed;
