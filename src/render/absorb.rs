//! Beer–Lambert attenuation along the segments of the tree that run inside
//! an absorbing object (docs/physics.md §11): each segment keeps
//! `exp(−τ)` of its wave's intensity, `τ = w_o α_o(λ) + w_e α_e(λ)`, the
//! weights from the segment's length, wave and direction
//! ([`segment_weights`]) and the coefficients per wavelength
//! ([`super::integrator::WavelengthMedia::absorption`]). A tree that
//! shares its paths between wavelengths shares the weights and applies
//! each wavelength's coefficients; the bound pruning tests uses the
//! wavelength that keeps most.

use crate::material::absorption::extraordinary_weights;
use crate::optics::modes::WaveKind;
use crate::optics::Medium;
use glam::DVec3;

/// The weights `[w_o, w_e]` (scene units) of a segment of `length` scene
/// units along the unit ray direction `dir` of a wave of `kind` in
/// `medium`: the whole length on `α_o` for an isotropic medium's wave and
/// an ordinary wave (E ⊥ c), the mixture of
/// [`extraordinary_weights`] for an extraordinary one.
#[inline]
pub(super) fn segment_weights(
    medium: &Medium,
    kind: WaveKind,
    dir: DVec3,
    length: f64,
) -> [f64; 2] {
    match (medium, kind) {
        (Medium::Uniaxial { n_o, n_e, axis }, WaveKind::Extraordinary) => {
            let (w_o, w_e) = extraordinary_weights(*n_o, *n_e, dir.dot(*axis));
            [w_o * length, w_e * length]
        }
        _ => [length, 0.0],
    }
}

/// Optical depth `τ` of a segment of weights `w` at coefficients `alpha`
/// (per scene unit).
#[inline]
pub(super) fn depth(w: [f64; 2], alpha: [f64; 2]) -> f64 {
    w[0] * alpha[0] + w[1] * alpha[1]
}

/// Length of a segment from `anchor` (the surface point it leaves) along
/// the unit direction `dir` to the plane through `far` (the traced hit)
/// with normal `normal`: the exact path's length, where the traced ray,
/// started a little off the surface, is shorter or longer by its offset
/// (as [`super::coherent`] measures phases). Falls back to `|far − anchor|`
/// for a ray nearly in the plane.
#[inline]
pub(super) fn segment_length(anchor: DVec3, dir: DVec3, far: DVec3, normal: DVec3) -> f64 {
    let denom = dir.dot(normal);
    let s = (far - anchor).dot(normal) / denom;
    if s.is_finite() && s > 0.0 && denom.abs() > 1e-12 {
        s
    } else {
        (far - anchor).length()
    }
}
