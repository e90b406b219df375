//! The path-traced reference: round fibres and mesh triangles in a BVH, Chiang et al. 2016's fibre BSDF, a CPU
//! path tracer, ray-traced texel visibility and the scene exported to Mitsuba 3.

pub mod accumulation;
pub mod bsdf;
pub mod bvh;
pub mod composite;
pub mod effects;
pub mod fibre;
pub mod integrator;
pub mod light;
pub mod masks;
pub mod mitsuba;
pub mod setup;
pub mod triangle;
pub mod visibility;
