//! The path-traced reference's core: round fibres and mesh triangles in a BVH, Chiang et al. 2016's fibre BSDF,
//! a CPU path tracer and ray-traced texel visibility. It knows no settings: `crate::path_scene` builds its scene
//! from a preset's settings and exports it to Mitsuba 3.

pub mod accumulation;
pub mod bsdf;
pub mod bvh;
pub mod composite;
pub mod effects;
pub mod fibre;
pub mod integrator;
pub mod light;
pub mod masks;
pub mod mesh_rays;
pub mod probe;
pub mod triangle;
pub mod visibility;
