//! Ray–triangle intersection (`spar::accel`): the backends' conventions
//! and agreement, watertightness, scale invariance of the Rust BVH, and
//! Embree's ABI and hard cases. One test binary; each file is a module.

#[path = "../support/mod.rs"]
mod support;

mod abi_embree;
mod accel_agreement;
mod accel_conventions;
mod accel_scale;
mod accel_watertight;
mod embree_octahedron;
