//! Absorption: how much light a medium takes out per length of path, per
//! wavelength and per eigenwave (Beer–Lambert, docs/physics.md §11).
//!
//! A coefficient α is the intensity attenuation per millimetre of path:
//! light that travels `d` mm keeps `exp(−α d)` of its intensity, and a
//! wave's amplitude `exp(−α d / 2)`. Scenes give α per mm whatever their
//! length unit (`[render] units`); the renderer converts.
//!
//! A uniaxial crystal has two principal coefficients: `o` for light whose
//! field is normal to the optic axis (the ordinary wave, E ⊥ c: what
//! gemmological and spectroscopic papers call the σ or "E ⊥ c" spectrum)
//! and `e` for a field along the axis (E ∥ c, the π spectrum). An
//! extraordinary ray at angle θ to the axis absorbs a mixture of the two,
//! [`extraordinary_weights`]. An isotropic medium has `o == e`.
//!
//! The indices stay real: for α ≤ 10 mm⁻¹ (a deep-coloured gem),
//! κ = αλ/4π ≤ 4·10⁻⁴ at 500 nm, which changes a Fresnel coefficient's
//! modulus by parts in 10⁶ and its phase by under 10⁻³ rad; the renderer
//! leaves both out and attenuates along paths only.

use crate::spectrum::{LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// One absorption coefficient as a function of wavelength, per mm.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// The same coefficient at every wavelength, mm⁻¹.
    Constant(f64),
    /// Linear interpolation between `(nm, per_mm)` points, wavelengths
    /// strictly increasing and covering 380–780 nm.
    Table { nm: Vec<f64>, per_mm: Vec<f64> },
    /// A sum of Gaussian bands in photon energy on a constant floor:
    /// `floor + Σ peak · exp(−½ ((E − E₀)/σ)²)`, E = 1239.84198/λ eV, each
    /// band `(centre nm, FWHM in eV, peak mm⁻¹)` (σ = FWHM / 2.35482). The
    /// form spectroscopists fit crystal-field bands with.
    Bands {
        floor: f64,
        bands: Vec<(f64, f64, f64)>,
    },
}

/// h c in eV·nm (CODATA 2018: h c = 1.239 841 98 µm·eV).
const HC_EV_NM: f64 = 1_239.841_98;

/// FWHM / σ of a Gaussian: 2 √(2 ln 2).
const FWHM_PER_SIGMA: f64 = 2.354_820_045;

impl Curve {
    /// The coefficient at `lambda_nm`, mm⁻¹.
    pub fn per_mm(&self, lambda_nm: f64) -> f64 {
        match self {
            Curve::Constant(a) => *a,
            Curve::Table { nm, per_mm } => interpolate(nm, per_mm, lambda_nm),
            Curve::Bands { floor, bands } => {
                let e = HC_EV_NM / lambda_nm;
                floor
                    + bands
                        .iter()
                        .map(|&(centre, fwhm, peak)| {
                            let x = (e - HC_EV_NM / centre) / (fwhm / FWHM_PER_SIGMA);
                            peak * (-0.5 * x * x).exp()
                        })
                        .sum::<f64>()
            }
        }
    }

    /// True when the coefficient is zero at every wavelength.
    pub fn is_zero(&self) -> bool {
        match self {
            Curve::Constant(a) => *a == 0.0,
            Curve::Table { per_mm, .. } => per_mm.iter().all(|&a| a == 0.0),
            Curve::Bands { floor, bands } => *floor == 0.0 && bands.iter().all(|b| b.2 == 0.0),
        }
    }

    /// Checks that the curve is a finite coefficient ≥ 0 over 380–780 nm:
    /// a table's wavelengths strictly increasing and covering the range,
    /// as many values as wavelengths.
    pub fn validate(&self) -> Result<(), String> {
        let coefficient = |a: f64, what: String| {
            if a.is_finite() && a >= 0.0 {
                Ok(())
            } else {
                Err(format!(
                    "{what} is {a}: an absorption coefficient is a finite number ≥ 0 (per mm)"
                ))
            }
        };
        match self {
            Curve::Constant(a) => coefficient(*a, "the coefficient".into()),
            Curve::Table { nm, per_mm } => {
                if nm.len() != per_mm.len() {
                    return Err(format!(
                        "`nm` has {} wavelengths but `per_mm` has {} values",
                        nm.len(),
                        per_mm.len()
                    ));
                }
                if nm.len() < 2 {
                    return Err("a table needs at least two wavelengths".into());
                }
                for (i, &l) in nm.iter().enumerate() {
                    if !l.is_finite() {
                        return Err(format!("wavelength {l} is not a finite number of nm"));
                    }
                    if i > 0 && !(l > nm[i - 1]) {
                        return Err(format!(
                            "wavelengths must increase: {l} nm follows {} nm",
                            nm[i - 1]
                        ));
                    }
                }
                if nm[0] > LAMBDA_MIN_NM || nm[nm.len() - 1] < LAMBDA_MAX_NM {
                    return Err(format!(
                        "the table covers {}–{} nm: it must cover {LAMBDA_MIN_NM}–{LAMBDA_MAX_NM} nm",
                        nm[0],
                        nm[nm.len() - 1]
                    ));
                }
                for (&l, &a) in nm.iter().zip(per_mm) {
                    coefficient(a, format!("the value at {l} nm"))?;
                }
                Ok(())
            }
            Curve::Bands { floor, bands } => {
                coefficient(*floor, "the floor".into())?;
                for &(centre, fwhm, peak) in bands {
                    if !(centre.is_finite() && centre > 0.0 && fwhm.is_finite() && fwhm > 0.0) {
                        return Err(format!(
                            "band at {centre} nm, FWHM {fwhm} eV: both must be finite and > 0"
                        ));
                    }
                    coefficient(peak, format!("the peak of the band at {centre} nm"))?;
                }
                Ok(())
            }
        }
    }
}

/// Linear interpolation of `(xs, ys)` at `x`, the end values beyond them.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let i = xs.partition_point(|&v| v <= x);
    if i == 0 {
        return ys[0];
    }
    if i >= xs.len() {
        return ys[ys.len() - 1];
    }
    let t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    ys[i - 1] + t * (ys[i] - ys[i - 1])
}

/// A medium's absorption: the principal coefficients for a field normal
/// to the optic axis (`o`) and along it (`e`); equal in an isotropic
/// medium.
#[derive(Clone, Debug, PartialEq)]
pub struct Absorption {
    pub o: Curve,
    pub e: Curve,
}

impl Absorption {
    /// The same coefficient for every field direction.
    pub fn isotropic(curve: Curve) -> Absorption {
        Absorption {
            o: curve.clone(),
            e: curve,
        }
    }

    /// `(α_o, α_e)` at `lambda_nm`, mm⁻¹.
    pub fn per_mm(&self, lambda_nm: f64) -> (f64, f64) {
        (self.o.per_mm(lambda_nm), self.e.per_mm(lambda_nm))
    }

    /// True when nothing is absorbed at any wavelength.
    pub fn is_zero(&self) -> bool {
        self.o.is_zero() && self.e.is_zero()
    }

    /// Both curves valid (see [`Curve::validate`]).
    pub fn validate(&self) -> Result<(), String> {
        self.o.validate().map_err(|e| format!("ordinary: {e}"))?;
        self.e.validate().map_err(|e| format!("extraordinary: {e}"))
    }
}

/// The weights `(w_o, w_e)` that make an extraordinary ray's absorption
/// per unit length of ray `α = w_o α_o + w_e α_e`, for a ray at `cos θ`
/// to the optic axis in a crystal of indices `n_o`, `n_e` (first order in
/// κ: power lost per unit time over power carried along the ray,
/// `ω E·ε″E / |S|`). The e-wave's field E is normal to its ray, in the
/// plane of the ray and the axis, so `E ⊥ c` carries `cos²θ` of it and
/// `E ∥ c` `sin²θ`; `ε″ = 2 n κ` on each principal axis, and
/// `|S| ∝ n_ray |E|²` with `n_ray² = n_o² cos²θ + n_e² sin²θ` (the ray
/// index, `n cos ρ`): `α = (n_o α_o cos²θ + n_e α_e sin²θ) / n_ray`. Along
/// the axis it is `α_o`, across it `α_e`.
pub fn extraordinary_weights(n_o: f64, n_e: f64, cos_theta: f64) -> (f64, f64) {
    let c2 = (cos_theta * cos_theta).min(1.0);
    let s2 = 1.0 - c2;
    let n_ray = (n_o * n_o * c2 + n_e * n_e * s2).sqrt();
    (n_o * c2 / n_ray, n_e * s2 / n_ray)
}
