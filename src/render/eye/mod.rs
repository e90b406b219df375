//! The eye toolkit: what the eye transparency techniques and the fur's typed lists build their passes from —
//! one binding vocabulary ([`bindings`]: a pass declares its group as a list of [`bindings::Binding`]s and the
//! layout is derived), base pipeline descriptors ([`pipelines`]: an eye geometry pass over the strands, a
//! full-screen resolve) and one per-pixel list type ([`lists::PixelLists`]: count → plan → fill → resolve, the
//! resolve instantiated per sort size) used by the exact reference and the fur's typed lists. Nothing here
//! knows a technique.

pub mod bindings;
pub mod complexity;
pub mod lists;
pub mod one_pass;
pub mod passes;
pub mod pipelines;
pub mod targets;
