//! A medium as the interface solver sees it: its indices at one wavelength.
//!
//! Dispersion lives in [`crate::material`]; by the time a wave meets an
//! interface the wavelength is fixed and a medium is just numbers.

use glam::DVec3;

/// Optical description of a non-magnetic, lossless medium at one wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Medium {
    /// Isotropic medium of refractive index `n` (air, glass, diamond).
    Isotropic { n: f64 },
    /// Uniaxial crystal: ordinary index `n_o`, extraordinary index `n_e`,
    /// optic axis `axis` (a unit vector, in the same frame as the interface
    /// normal and the wave vectors).
    Uniaxial { n_o: f64, n_e: f64, axis: DVec3 },
}

impl Medium {
    /// Vacuum/air with index exactly 1.
    pub const VACUUM: Medium = Medium::Isotropic { n: 1.0 };

    /// True for an isotropic medium.
    pub fn is_isotropic(&self) -> bool {
        matches!(self, Medium::Isotropic { .. })
    }
}
