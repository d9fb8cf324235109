//! A medium as the interface solver sees it: its indices at one wavelength.
//!
//! Dispersion lives in [`crate::material`]; by the time a wave meets an
//! interface the wavelength is fixed and a medium is just numbers.

use glam::{DMat3, DVec3};

/// Optical description of a non-magnetic, lossless medium at one wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Medium {
    /// Isotropic medium of refractive index `n` (air, glass, diamond).
    Isotropic { n: f64 },
    /// Uniaxial crystal: ordinary index `n_o`, extraordinary index `n_e`,
    /// optic axis `axis` (a unit vector, in the same frame as the interface
    /// normal and the wave vectors).
    Uniaxial { n_o: f64, n_e: f64, axis: DVec3 },
    /// Any non-absorbing anisotropic medium (biaxial crystal): principal
    /// indices `n = [n_x, n_y, n_z]` along the crystal axes `x`, `y = z × x`
    /// and `z` (unit, orthogonal; [`Medium::biaxial`] builds them from any
    /// two vectors). The dielectric tensor is `ε = Σ n_i² a_i a_iᵀ`.
    Biaxial { n: [f64; 3], x: DVec3, z: DVec3 },
}

impl Medium {
    /// Vacuum/air with index exactly 1.
    pub const VACUUM: Medium = Medium::Isotropic { n: 1.0 };

    /// True for an isotropic medium.
    pub fn is_isotropic(&self) -> bool {
        matches!(self, Medium::Isotropic { .. })
    }

    /// True for a [`Medium::Biaxial`] medium.
    pub fn is_biaxial(&self) -> bool {
        matches!(self, Medium::Biaxial { .. })
    }

    /// A biaxial medium with principal indices `n` along crystal `x`, `y`,
    /// `z`, the crystal's `z` along `z` and its `x` along the part of `x`
    /// orthogonal to `z` (Gram–Schmidt). `None` when `z` is zero or not
    /// finite, or `x` is (nearly, within 1e-9 rad) parallel to it.
    pub fn biaxial(n: [f64; 3], z: DVec3, x: DVec3) -> Option<Medium> {
        let (z, x) = orthonormal_axes(z, x)?;
        Some(Medium::Biaxial { n, x, z })
    }

    /// The dielectric tensor `ε` (relative permittivity, `n²` on the
    /// principal axes) in the frame of the interface.
    pub fn epsilon(&self) -> DMat3 {
        match *self {
            Medium::Isotropic { n } => DMat3::from_diagonal(DVec3::splat(n * n)),
            // ε = n_o² (I − c cᵀ) + n_e² c cᵀ (docs/physics.md §4.3).
            Medium::Uniaxial { n_o, n_e, axis } => {
                DMat3::from_diagonal(DVec3::splat(n_o * n_o))
                    + outer(axis, axis) * (n_e * n_e - n_o * n_o)
            }
            // ε = Σ n_i² a_i a_iᵀ over the crystal axes.
            Medium::Biaxial { n, x, z } => {
                let y = z.cross(x);
                outer(x, x) * (n[0] * n[0])
                    + outer(y, y) * (n[1] * n[1])
                    + outer(z, z) * (n[2] * n[2])
            }
        }
    }
}

/// `a bᵀ`.
#[inline]
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The crystal x of a biaxial medium whose z alone is given (`--axis`
/// without `--axis-x`, `crystal_axes` without `x`, `axis_x=None`): +x, or
/// +y when `z` lies within 45° of ±x (`|ẑ·x̂| > √½`), so the part of it
/// orthogonal to `z` (what [`orthonormal_axes`] keeps) is never shorter
/// than √½ and never ill-conditioned. Deterministic; zero or non-finite
/// `z` gives +x (the caller's check of `z` reports it).
pub fn default_crystal_x(z: DVec3) -> DVec3 {
    let l = z.length();
    if l > 0.0 && l.is_finite() && (z.x / l).abs() > std::f64::consts::FRAC_1_SQRT_2 {
        DVec3::Y
    } else {
        DVec3::X
    }
}

/// Unit `z` and the unit part of `x` orthogonal to it, or `None` (see
/// [`Medium::biaxial`]).
pub fn orthonormal_axes(z: DVec3, x: DVec3) -> Option<(DVec3, DVec3)> {
    let lz = z.length();
    let lx = x.length();
    if !(lz > 0.0 && lz.is_finite() && lx > 0.0 && lx.is_finite()) {
        return None;
    }
    let z = z / lz;
    let x = x / lx;
    let xp = x - z * x.dot(z);
    let l = xp.length();
    if !(l > 1e-9) {
        return None;
    }
    Some((z, xp / l))
}
