//! Spectra and colour: wavelength sets with quadrature weights, the CIE 1931
//! 2° observer and D65, XYZ ↔ sRGB, and RGB → spectrum for textures.
//!
//! No optics and no geometry here. Wavelengths are in nanometres.
//!
//! - [`WavelengthSet`]: what a render integrates over (a grid, a list, one
//!   wavelength, or hero-wavelength samples).
//! - [`cie`]: the colour matching functions and D65, interpolated linearly.
//! - [`Observer`]: spectral samples → XYZ → white-balanced linear sRGB for a
//!   given set (D65 is white at any sampling).
//! - [`srgb`]: the IEC 61966-2-1 matrices and transfer function.
//! - [`SigmoidSpectrum`]: RGB → smooth spectrum (Jakob & Hanika 2019).

pub mod cie;
#[rustfmt::skip]
mod cie_tables;
pub mod observer;
pub mod rgb_to_spectrum;
pub mod srgb;
pub mod wavelengths;

pub use observer::Observer;
pub use rgb_to_spectrum::{RgbToSpectrumTable, SigmoidSpectrum};
pub use wavelengths::{WavelengthSet, LAMBDA_MAX_NM, LAMBDA_MIN_NM, LAMBDA_RANGE_NM};

/// What can go wrong when building wavelength sets and observers.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    #[error("a wavelength set needs at least one wavelength")]
    Empty,
    #[error("wavelength {0} nm is outside the visible range 380-780 nm")]
    WavelengthOutOfRange(f64),
    #[error("wavelength {0} nm is listed twice")]
    Duplicate(f64),
    #[error("{lambdas} wavelengths but {weights} weights")]
    WeightCount { lambdas: usize, weights: usize },
    #[error("quadrature weight {0} is not a finite non-negative number")]
    BadWeight(f64),
    #[error(
        "this wavelength set is too sparse to carry colour (D65 sampled by it has an sRGB \
         channel near zero); use more wavelengths, or one wavelength for grey"
    )]
    TooSparse,
}
