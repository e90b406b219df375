//! The GPU passes of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer): [`shell_gpu`], the undercoat's shell ray
//! march into the eye lists. The CPU model they equal is [`crate::fur`].

pub mod shell_gpu;
