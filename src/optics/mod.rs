//! The optics kernel (f64): conventions, coherence matrices, Fresnel
//! equations, uniaxial eigenwaves and the interface solver.
//!
//! This module imports nothing from scenes, acceleration structures or the
//! native libraries.

pub mod coherence;
pub mod jones;
pub mod medium;
pub mod polarimetry;

pub use coherence::{Coherence, Handedness, Stokes};
pub use jones::Jones;
pub use medium::Medium;
pub use polarimetry::{Polarimetry, PolarizationMap};
