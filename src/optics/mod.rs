//! The optics kernel (f64): conventions, coherence matrices, Fresnel
//! equations, uniaxial eigenwaves and the interface solver.
//!
//! This module imports nothing from scenes, acceleration structures or the
//! native libraries.

pub mod medium;

pub use medium::Medium;
