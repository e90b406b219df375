//! The eye toolkit: what the eye transparency techniques and the fur's typed lists build their passes from —
//! one binding vocabulary ([`bindings`]: a pass declares its group as a list of [`bindings::Binding`]s and the
//! layout is derived), base pipeline descriptors ([`pipelines`]: an eye geometry pass over the strands, a
//! storage-only count pass, a full-screen resolve, the common colour targets), the recording of the passes every
//! technique has ([`passes`]: a pass over the strands as lines, the resolve onto the frame's output), the
//! viewport-sized targets and storage ([`targets`]), the GPU state of a technique of one hair pass and a resolve
//! ([`one_pass`]), the eye depth complexity counted on the GPU ([`complexity`]), and one per-pixel list type
//! ([`lists::PixelLists`]: count → plan → fill → resolve, the resolve instantiated per sort size) used by the
//! exact reference and the fur's typed lists. Nothing here knows a technique.

pub mod bindings;
pub mod complexity;
pub mod lists;
pub mod one_pass;
pub mod passes;
pub mod pipelines;
pub mod targets;
