//! The optics kernel (f64): conventions, coherence matrices, Fresnel
//! equations, uniaxial eigenwaves and the interface solver.
//!
//! This module imports nothing from scenes, acceleration structures or the
//! native libraries.

pub mod anisotropic;
pub mod backward;
pub mod coherence;
pub mod directions;
pub mod fresnel;
pub mod interface;
pub mod jones;
pub mod linalg;
pub mod medium;
pub mod modes;
pub mod near_isotropic;
pub mod polarimetry;

pub use backward::{Feeder, Feeders, WaveBasis};
pub use coherence::{Coherence, Handedness, Stokes};
pub use interface::{Interface, InterfaceError, Outgoing, Scattering};
pub use jones::Jones;
pub use medium::Medium;
pub use modes::{Eigenwave, Mode, Side, WaveKind};
pub use polarimetry::{Polarimetry, PolarizationMap};
