//! What the camera "photographs" (docs/physics.md §2): intensity, degree of
//! polarization, ellipse azimuth and ellipticity of the light reaching a
//! pixel, from the coherence matrix summed over every ray of that pixel (in
//! one pixel basis, before deriving anything).
//!
//! Two ellipticity maps are offered, named plainly:
//! - [`Polarimetry::ellipticity`]: `b/a = |tan χ|` of the polarized part,
//!   `sin 2χ = S3 / Ip` (0 linear, 1 circular; 0 where nothing is polarized).
//! - [`Polarimetry::ellipticity_paper`]: the seed paper's map,
//!   `E_paper = tan(½ asin(|S3| / S0))`, which is what its eqs. (4)–(5)
//!   reduce to once the square roots cancel (docs/physics.md §2.2). This one
//!   reproduces the seed's figures. For fully polarized light it equals
//!   b/a; for partially polarized light it is b/a weighted by P (half
//!   unpolarized light plus an ellipse of b/a = 0.5 gives 0.2087, not 0.5).
//!
//! Every value is finite and clamped to its range for any input (see
//! [`super::coherence`] on robustness). Formulas avoid `asin`/`tan` and
//! divisions by quantities that can vanish: with `L = √(S1² + S2²)` and
//! `Ip = √(L² + S3²)`, `tan χ = S3 / (Ip + L)` and
//! `tan(½ asin(|S3|/S0)) = |S3| / (S0 + √((S0 − Ip)(S0 + Ip) + L²))`.

use super::coherence::{Coherence, Handedness, Stokes};
use std::f64::consts::{FRAC_PI_2, PI};

/// The polarization state of the light reaching a pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polarimetry {
    /// `I = S0 = tr J`, ≥ 0.
    pub intensity: f64,
    /// `Ip = √(S1² + S2² + S3²)`, in [0, I].
    pub polarized_intensity: f64,
    /// Degree of polarization `P = Ip / I` in [0, 1]; 0 where `I = 0`.
    pub degree_of_polarization: f64,
    /// Azimuth of the ellipse's major axis from basis x toward y,
    /// `ψ = ½ atan2(S2, S1)` in (−π/2, π/2]; 0 where undefined (no linear
    /// part).
    pub azimuth: f64,
    /// Ellipticity angle `χ = ½ asin(S3 / Ip)` in [−π/4, π/4] (its sign is
    /// the handedness); 0 where nothing is polarized.
    pub ellipticity_angle: f64,
    /// Degree of ellipticity `b/a = |tan χ|` of the polarized part, in
    /// [0, 1]; 0 where nothing is polarized.
    pub ellipticity: f64,
    /// The seed paper's map `tan(½ asin(|S3| / S0))`, in [0, 1].
    pub ellipticity_paper: f64,
    /// Sense of rotation of the polarized part; `None` when `S3 = 0`.
    pub handedness: Option<Handedness>,
}

impl Polarimetry {
    /// The polarization state of `j`.
    pub fn of(j: &Coherence) -> Polarimetry {
        let (scale, s) = j.normalized_stokes();
        let mut p = Self::from_normalized(s);
        // Back to absolute units; both are ≥ 0, so saturating at the largest
        // finite number is all the overflow guard needed.
        p.intensity = (p.intensity * scale).min(f64::MAX);
        p.polarized_intensity = (p.polarized_intensity * scale).min(p.intensity);
        p
    }

    /// The polarization state of Stokes parameters (they need not be
    /// physical: S0 is clipped as for a coherence matrix).
    pub fn from_stokes(s: Stokes) -> Polarimetry {
        Polarimetry::of(&Coherence::from_stokes(s))
    }

    /// Everything but the absolute intensities, from Stokes parameters of
    /// moderate magnitude with `S0 ≥ Ip`.
    fn from_normalized(s: Stokes) -> Polarimetry {
        let l = s.s1.hypot(s.s2);
        let ip = l.hypot(s.s3);
        let p = if s.s0 > 0.0 {
            (ip / s.s0).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let mut azimuth = if l > 0.0 { 0.5 * s.s2.atan2(s.s1) } else { 0.0 };
        if azimuth <= -FRAC_PI_2 {
            azimuth += PI;
        }
        let (ellipticity_angle, ellipticity) = if ip > 0.0 {
            let tan_chi = s.s3 / (ip + l); // |·| ≤ 1
            (
                (0.5 * s.s3.atan2(l)).clamp(-0.25 * PI, 0.25 * PI),
                tan_chi.abs().min(1.0),
            )
        } else {
            (0.0, 0.0)
        };
        // tan(½ asin(|S3|/S0)) = |S3| / (S0 + √(S0² − S3²)), with
        // S0² − S3² = (S0 − Ip)(S0 + Ip) + L² written without cancellation:
        // for a pure state it is exactly L², and the map exactly b/a.
        let s0 = s.s0.max(ip);
        let ellipticity_paper = if s0 > 0.0 {
            let root = ((s0 - ip) * (s0 + ip) + l * l).sqrt();
            (s.s3.abs() / (s0 + root)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let handedness = if s.s3 > 0.0 {
            Some(Handedness::Right)
        } else if s.s3 < 0.0 {
            Some(Handedness::Left)
        } else {
            None
        };
        Polarimetry {
            intensity: s.s0,
            polarized_intensity: ip,
            degree_of_polarization: p,
            azimuth,
            ellipticity_angle,
            ellipticity,
            ellipticity_paper,
            handedness,
        }
    }
}

/// A quantity the camera can write as an image channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolarizationMap {
    /// `I = S0`.
    Intensity,
    /// `P` in [0, 1].
    DegreeOfPolarization,
    /// `b/a` of the polarized part, in [0, 1].
    Ellipticity,
    /// The seed paper's `tan(½ asin(|S3| / S0))`, in [0, 1]; reproduces its
    /// figures.
    EllipticityPaper,
    /// Azimuth ψ mapped to [0, 1] as `(ψ + π/2) / π`.
    Azimuth,
}

impl PolarizationMap {
    /// Every map, in a fixed order.
    pub const ALL: [PolarizationMap; 5] = [
        PolarizationMap::Intensity,
        PolarizationMap::DegreeOfPolarization,
        PolarizationMap::Ellipticity,
        PolarizationMap::EllipticityPaper,
        PolarizationMap::Azimuth,
    ];

    /// The map's name on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            PolarizationMap::Intensity => "intensity",
            PolarizationMap::DegreeOfPolarization => "dop",
            PolarizationMap::Ellipticity => "ellipticity",
            PolarizationMap::EllipticityPaper => "ellipticity-paper",
            PolarizationMap::Azimuth => "azimuth",
        }
    }

    /// The map called `name` (case-insensitive).
    pub fn parse(name: &str) -> Result<PolarizationMap, String> {
        let key = name.trim().to_ascii_lowercase();
        PolarizationMap::ALL
            .into_iter()
            .find(|m| m.name() == key)
            .ok_or_else(|| {
                let names: Vec<&str> = PolarizationMap::ALL.iter().map(|m| m.name()).collect();
                format!("unknown map `{name}`: use one of {}", names.join(", "))
            })
    }

    /// The map's value for one pixel.
    pub fn value(self, p: &Polarimetry) -> f64 {
        match self {
            PolarizationMap::Intensity => p.intensity,
            PolarizationMap::DegreeOfPolarization => p.degree_of_polarization,
            PolarizationMap::Ellipticity => p.ellipticity,
            PolarizationMap::EllipticityPaper => p.ellipticity_paper,
            PolarizationMap::Azimuth => ((p.azimuth + FRAC_PI_2) / PI).clamp(0.0, 1.0),
        }
    }
}
