//! Path-traced reference (issue 33): fibre geometry, Chiang et al. 2016's BSDF, and a CPU path tracer.

pub mod bsdf;
pub mod bvh;
pub mod fibre;
pub mod integrator;
pub mod visibility;
