//! Wave vectors from directions and back, for every medium: the wave
//! vector of a given wave normal, the ray of a wave vector, the wave vector
//! of a given ray (docs/physics.md §4.3, §4.8). Isotropic and uniaxial media
//! in closed form, biaxial ones through [`super::anisotropic`].

use super::anisotropic;
use super::medium::Medium;
use super::modes::WaveKind;
use glam::DVec3;

/// The (unnormalized) ray direction `M k` of a real wave vector on the
/// sheet of `kind`: `k/n²` for isotropic and ordinary waves,
/// `k/n_e² + κ (k·c) c` for the extraordinary wave (docs/physics.md §4.3).
#[inline]
pub fn ray_vector(medium: &Medium, kind: WaveKind, k: DVec3) -> DVec3 {
    match (*medium, kind) {
        (Medium::Isotropic { n }, _) | (Medium::Uniaxial { n_o: n, .. }, WaveKind::Ordinary) => {
            k / (n * n)
        }
        (Medium::Uniaxial { n_o, n_e, axis }, _) => {
            let kappa = 1.0 / (n_o * n_o) - 1.0 / (n_e * n_e);
            k / (n_e * n_e) + axis * (kappa * k.dot(axis))
        }
        // A biaxial wave: the unit Poynting direction (not scaled as M k).
        (Medium::Biaxial { .. }, _) => anisotropic::ray_direction(medium, k),
    }
}

/// The wave vector on the sheet of `kind` whose wave normal is along `dir`
/// (any non-zero length): `n(θ) d̂` with `1/n(θ)² = d̂ᵀ M d̂`.
#[inline]
pub fn k_from_wave_normal(medium: &Medium, kind: WaveKind, dir: DVec3) -> DVec3 {
    if medium.is_biaxial() {
        return anisotropic::k_from_wave_normal(medium, kind, dir);
    }
    let d = dir.normalize();
    // d̂ᵀ M d̂ = (M d̂)·d̂ for the symmetric M.
    d / ray_vector(medium, kind, d).dot(d).sqrt()
}

/// The wave vector on the sheet of `kind` whose ray (energy) direction is
/// along `ray` (any non-zero length): `k = M⁻¹ S / sqrt(Sᵀ M⁻¹ S)` with
/// `M⁻¹ = n_e² I + (n_o² − n_e²) c cᵀ` for the extraordinary wave and
/// `n² I` otherwise (inverting `S ∝ M k`, docs/physics.md §4.3).
#[inline]
pub fn k_from_ray(medium: &Medium, kind: WaveKind, ray: DVec3) -> DVec3 {
    let r = ray.normalize();
    match (*medium, kind) {
        (Medium::Isotropic { n }, _) | (Medium::Uniaxial { n_o: n, .. }, WaveKind::Ordinary) => {
            r * n
        }
        (Medium::Uniaxial { n_o, n_e, axis }, _) => {
            let v = r * (n_e * n_e) + axis * ((n_o * n_o - n_e * n_e) * axis.dot(r));
            v / v.dot(r).sqrt()
        }
        (Medium::Biaxial { .. }, _) => anisotropic::k_from_ray(medium, kind, r),
    }
}
