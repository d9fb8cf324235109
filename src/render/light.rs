//! Rectangular one-sided area lights and lights at infinity: emission spectrum (radiance scale ×
//! texture spectrum × D65) and polarization (unpolarized, an ideal linear
//! polarizer, or a virtual calcite plate that keeps one of its two waves).
//! `spar::scene::light` reads them from scene files.

use crate::optics::Coherence;
use crate::spectrum::{cie, SigmoidSpectrum};
use glam::DVec3;
use num_complex::Complex64;
use std::collections::HashMap;

/// Which wave a virtual calcite plate keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlateWave {
    Ordinary,
    Extraordinary,
}

/// The polarization of a light's emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Polarization {
    Unpolarized,
    /// Behind an ideal sheet polarizer with this transmission axis t (a unit
    /// vector in the light's plane): half the radiance, fully polarized
    /// along k × (N × t) for a ray along k (t itself at normal incidence).
    Linear {
        axis: DVec3,
    },
    /// Behind a virtual calcite plate of this optic axis that keeps only the
    /// ordinary (E ∥ k × c) or the extraordinary (E ⊥ that, in the plane of
    /// k and c) wave: half the radiance, polarized by the ray's direction.
    CalcitePlate {
        keep: PlateWave,
        axis: DVec3,
    },
}

/// Most distinct colours a texture may have for its spectra to be fitted
/// one by one instead of looked up in the table.
pub const DIRECT_FIT_LIMIT: usize = 1024;

/// An RGB texture as per-texel smooth reflectance spectra (Jakob & Hanika
/// 2019), row 0 along the light's first edge.
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<SigmoidSpectrum>,
}

impl Texture {
    /// The texture's spectra for linear RGB texels (row-major, row 0 first).
    ///
    /// Textures with few distinct colours (up to [`DIRECT_FIT_LIMIT`]) fit
    /// each colour directly, which is exact and costs well under a
    /// millisecond per colour; larger ones look colours up in the global
    /// coefficient table (built once per process, about a second).
    pub fn from_linear_rgb(width: usize, height: usize, rgb: &[[f64; 3]]) -> Texture {
        assert_eq!(rgb.len(), width * height);
        let mut distinct: HashMap<[u64; 3], SigmoidSpectrum> = HashMap::new();
        for c in rgb {
            distinct
                .entry(c.map(f64::to_bits))
                .or_insert(SigmoidSpectrum::constant(0.0));
            if distinct.len() > DIRECT_FIT_LIMIT {
                break;
            }
        }
        let direct = distinct.len() <= DIRECT_FIT_LIMIT;
        if direct {
            for (bits, spectrum) in distinct.iter_mut() {
                *spectrum = SigmoidSpectrum::fit(bits.map(f64::from_bits));
            }
        }
        let texels = rgb
            .iter()
            .map(|c| {
                if direct {
                    distinct[&c.map(f64::to_bits)]
                } else {
                    SigmoidSpectrum::from_linear_srgb(*c)
                }
            })
            .collect();
        Texture {
            width,
            height,
            texels,
        }
    }

    /// The texel spectrum at (s, t) ∈ [0, 1]² (nearest texel: a box filter
    /// at texel resolution).
    #[inline]
    pub fn at(&self, s: f64, t: f64) -> &SigmoidSpectrum {
        let x = ((s * self.width as f64) as usize).min(self.width - 1);
        let y = ((t * self.height as f64) as usize).min(self.height - 1);
        &self.texels[y * self.width + x]
    }
}

/// A rectangle c0 + s·u + t·v, (s, t) ∈ [0, 1]², emitting toward u × v.
#[derive(Clone, Debug)]
pub struct Light {
    pub origin: DVec3,
    pub u: DVec3,
    pub v: DVec3,
    /// Unit normal of the emitting side.
    pub normal: DVec3,
    pub radiance: f64,
    pub texture: Option<Texture>,
    pub polarization: Polarization,
}

impl Light {
    /// Where a ray from `o` along `d` meets the emitting face: (t, s, tt)
    /// with t the ray parameter and (s, tt) the face coordinates. Rays that
    /// meet the back face, or travel in its plane, see nothing.
    #[inline]
    pub fn hit(&self, o: DVec3, d: DVec3) -> Option<(f64, f64, f64)> {
        let den = d.dot(self.normal);
        if den >= 0.0 || !den.is_finite() {
            return None;
        }
        let t = (self.origin - o).dot(self.normal) / den;
        if !(t > 0.0) {
            return None;
        }
        let p = o + t * d - self.origin;
        // Solve p = s u + tt v in the plane (u and v need not be orthogonal).
        let (uu, uv, vv) = (self.u.dot(self.u), self.u.dot(self.v), self.v.dot(self.v));
        let (pu, pv) = (p.dot(self.u), p.dot(self.v));
        let det = uu * vv - uv * uv;
        let s = (pu * vv - pv * uv) / det;
        let tt = (pv * uu - pu * uv) / det;
        ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&tt)).then_some((t, s, tt))
    }

    /// Spectral radiance (in units of D65) at face coordinates (s, t),
    /// before any filter.
    #[inline]
    pub fn spectral_radiance(&self, s: f64, t: f64, lambda_nm: f64) -> f64 {
        let reflectance = self
            .texture
            .as_ref()
            .map_or(1.0, |tex| tex.at(s, t).eval(lambda_nm));
        self.radiance * reflectance * cie::d65(lambda_nm)
    }

    /// The coherence matrix of the light leaving face coordinates (s, t)
    /// along unit direction `k` (from the light into the scene), expressed
    /// in the orthonormal basis (x, y) transverse to `k`.
    pub fn emitted(
        &self,
        s: f64,
        t: f64,
        lambda_nm: f64,
        k: DVec3,
        x: DVec3,
        y: DVec3,
    ) -> Coherence {
        let l = self.spectral_radiance(s, t, lambda_nm);
        filtered(self.polarization, self.normal, self.u, l, k, x, y)
    }

    /// The polarization state of unit radiance leaving along `k`, in the
    /// basis (x, y) transverse to `k` ([`Self::emitted`] is this times
    /// [`Self::spectral_radiance`]).
    pub fn state(&self, k: DVec3, x: DVec3, y: DVec3) -> Coherence {
        filtered(self.polarization, self.normal, self.u, 1.0, k, x, y)
    }
}

/// The unit field a filter passes for a ray along unit `k`: `None` for
/// unpolarized light, the zero vector when the filter passes nothing
/// along `k`. `normal` is the filter's plane normal, `fallback` a vector
/// in its plane (for a calcite plate seen along its axis).
fn passed_field(
    polarization: Polarization,
    normal: DVec3,
    fallback: DVec3,
    k: DVec3,
) -> Option<DVec3> {
    let field = match polarization {
        Polarization::Unpolarized => return None,
        // A sheet (dichroic or wire-grid) polarizer absorbs the field
        // along its absorbing axis a = N × t in its plane and passes
        // E ∥ k × a (Korger et al. 2013; Mitsuba 3's `polarizer`); at
        // normal incidence that is the transmission axis t itself.
        Polarization::Linear { axis } => k.cross(normal.cross(axis)),
        Polarization::CalcitePlate { keep, axis } => {
            // Ordinary wave: E ∥ k × c (docs/physics.md §4.3); along the axis the
            // two waves are degenerate: take the filter's first edge.
            let mut e_o = k.cross(axis);
            if e_o.length_squared() < 1e-24 {
                e_o = fallback;
            }
            match keep {
                PlateWave::Ordinary => e_o,
                PlateWave::Extraordinary => k.cross(e_o),
            }
        }
    };
    Some((field - field.dot(k) * k).normalize_or_zero())
}

/// Light of radiance `l` through a filter ([`passed_field`]) along `k`,
/// as a coherence matrix in the basis (x, y) transverse to `k`: `l`
/// unpolarized, or half of it fully polarized (an ideal filter passes half
/// of unpolarized light).
fn filtered(
    polarization: Polarization,
    normal: DVec3,
    fallback: DVec3,
    l: f64,
    k: DVec3,
    x: DVec3,
    y: DVec3,
) -> Coherence {
    match passed_field(polarization, normal, fallback, k) {
        None => Coherence::unpolarized(l),
        // The filter's axis is along the ray: it passes nothing.
        Some(e) if e == DVec3::ZERO => Coherence::zero(2),
        Some(e) => {
            let jones = [Complex64::new(e.dot(x), 0.0), Complex64::new(e.dot(y), 0.0)];
            Coherence::from_jones_vector(jones).scaled(0.5 * l)
        }
    }
}

/// Half-angle, in radians, within which a backward ray sees a collimated
/// light at infinity (`angular_diameter = 0`): 1e-6 rad (0.2″). A
/// collimated beam is a delta in direction; a renderer that traces rays
/// sees it only along rays that arrive exactly from it, which it gets to
/// rounding (1e-15 rad) through flat, parallel surfaces, and misses
/// otherwise. Its `radiance` is what such a ray sees.
pub const COLLIMATED_HALF_ANGLE: f64 = 1e-6;

/// A light at infinity: plane waves travelling within a cone around
/// `direction` (a sun-like disc of `angular_diameter`, or a collimated
/// beam when that is 0), less the cone of `inner_diameter` (a ring of
/// directions: the built-in rigs, `render::rig`), of uniform radiance and
/// polarization. Each
/// direction is one plane wave: paths that arrive from the same direction
/// are mutually coherent (docs/physics.md §9).
#[derive(Clone, Debug, PartialEq)]
pub struct DistantLight {
    /// Unit direction the light travels (from the light into the scene).
    pub direction: DVec3,
    /// Full angular diameter of the disc of directions, radians (0:
    /// collimated).
    pub angular_diameter: f64,
    /// Full angular diameter, radians, of the cone around `direction`
    /// that is dark (0: none, a full disc).
    pub inner_diameter: f64,
    /// Radiance scale (× D65).
    pub radiance: f64,
    /// A filter in the plane normal to `direction` (the sheet polarizer's
    /// `N` is `direction`).
    pub polarization: Polarization,
}

impl DistantLight {
    /// Cosine of the half-angle within which a backward ray sees it.
    #[inline]
    pub fn cos_half_angle(&self) -> f64 {
        (0.5 * self.angular_diameter)
            .clamp(COLLIMATED_HALF_ANGLE, std::f64::consts::PI)
            .cos()
    }

    /// True when a backward ray along unit `d` (toward the light) sees it:
    /// within the half-angle of `direction`, and beyond the dark cone's
    /// half-angle when there is one.
    #[inline]
    pub fn seen_along(&self, d: DVec3) -> bool {
        let c = (-d).dot(self.direction);
        c >= self.cos_half_angle()
            && (self.inner_diameter <= 0.0 || c < (0.5 * self.inner_diameter).cos())
    }

    /// The coherence matrix of the light travelling along unit `k` (one of
    /// its directions), in the basis (x, y) transverse to `k`.
    pub fn emitted(&self, lambda_nm: f64, k: DVec3, x: DVec3, y: DVec3) -> Coherence {
        self.state(k, x, y)
            .scaled(self.spectral_radiance(lambda_nm))
    }

    /// Spectral radiance (in units of D65), before any filter.
    #[inline]
    pub fn spectral_radiance(&self, lambda_nm: f64) -> f64 {
        self.radiance * cie::d65(lambda_nm)
    }

    /// The polarization state of unit radiance along `k`, in the basis
    /// (x, y) transverse to `k`.
    pub fn state(&self, k: DVec3, x: DVec3, y: DVec3) -> Coherence {
        let fallback = self.direction.any_orthonormal_vector();
        filtered(self.polarization, self.direction, fallback, 1.0, k, x, y)
    }
}

/// A light at infinity in every direction (`[[light]] environment`): a
/// uniform radiance, or a latitude–longitude map of it, unpolarized. Each
/// direction is a plane wave of its own (docs/physics.md §9.3): paths that
/// leave for it in the same direction are coherent.
///
/// The map's axes, for the direction ω the light comes from (ω = −k for
/// light travelling along k), world +z up: row 0 is the zenith (+z), the
/// last row the nadir, rows uniform in the polar angle θ = acos ω_z;
/// column 0 starts at azimuth φ = atan2(ω_y, ω_x) = −180° (−x) and
/// columns run with increasing φ (through −y, +x, +y).
#[derive(Clone, Debug)]
pub struct Environment {
    /// Radiance scale (× D65 × the map's spectrum).
    pub radiance: f64,
    pub map: Option<EnvironmentMap>,
}

/// The texels of an environment map: each texel's linear RGB divided by
/// its largest component as a smooth spectrum in [0, 1] (Jakob & Hanika
/// 2019), times that component (`scale`), so high-dynamic-range maps keep
/// their brightness.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    pub texture: Texture,
    /// Per texel, row-major.
    pub scale: Vec<f64>,
}

impl EnvironmentMap {
    /// A map from linear RGB texels (row-major, row 0 the zenith); every
    /// value must be finite and ≥ 0.
    pub fn from_linear_rgb(width: usize, height: usize, rgb: &[[f64; 3]]) -> EnvironmentMap {
        assert_eq!(rgb.len(), width * height);
        let scale: Vec<f64> = rgb
            .iter()
            .map(|c| c[0].max(c[1]).max(c[2]).max(0.0))
            .collect();
        let normalized: Vec<[f64; 3]> = rgb
            .iter()
            .zip(&scale)
            .map(|(c, &s)| if s > 0.0 { c.map(|v| v / s) } else { [0.0; 3] })
            .collect();
        EnvironmentMap {
            texture: Texture::from_linear_rgb(width, height, &normalized),
            scale,
        }
    }

    /// The texel that light travelling along unit `k` comes from.
    #[inline]
    pub fn texel(&self, k: DVec3) -> usize {
        let w = -k;
        let theta = w.z.clamp(-1.0, 1.0).acos();
        let phi = w.y.atan2(w.x);
        let (width, height) = (self.texture.width, self.texture.height);
        let x = (((phi + std::f64::consts::PI) / std::f64::consts::TAU * width as f64) as usize)
            .min(width - 1);
        let y = ((theta / std::f64::consts::PI * height as f64) as usize).min(height - 1);
        y * width + x
    }
}

impl Environment {
    /// Spectral radiance (in units of D65) of the light travelling along
    /// unit `k`.
    #[inline]
    pub fn spectral_radiance(&self, k: DVec3, lambda_nm: f64) -> f64 {
        let base = self.radiance * cie::d65(lambda_nm);
        match &self.map {
            None => base,
            Some(m) => {
                let i = m.texel(k);
                base * m.scale[i] * m.texture.texels[i].eval(lambda_nm)
            }
        }
    }
}
