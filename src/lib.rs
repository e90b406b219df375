//! hairlab: a workbench for real-time hair self-shadowing methods, side by side on the same strands.
#![allow(clippy::too_many_arguments)]

pub mod app;
pub mod bench;
pub mod cli;
pub mod fur;
pub mod gpu;
pub mod io;
pub mod measure;
pub mod methods;
pub mod motion;
pub mod render;
pub mod rng;
pub mod scene;
pub mod settings;
pub mod shaders;
pub mod soak;
pub mod transparency;
pub mod visibility;
