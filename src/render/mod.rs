//! The renderer: camera, deterministic sampling, the backward ray-tree
//! integrator and the film.

pub mod camera;
pub mod sampling;
