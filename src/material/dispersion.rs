//! Dispersion models: refractive index as a function of wavelength.
//!
//! Wavelengths are in nanometres at the API and in micrometres inside every
//! formula (the unit the published coefficients use).

use crate::spectrum::{LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// A refractive index as a function of wavelength.
#[derive(Clone, Debug, PartialEq)]
pub enum Dispersion {
    /// The same index at every wavelength.
    Constant(f64),
    /// Sellmeier, poles as squared wavelengths (Schott's form, and Ghosh
    /// 1999's with `a ≠ 1`): `n² = a + Σ B_i λ² / (λ² − C_i)`, λ in µm,
    /// terms `(B_i, C_i)` with `C_i` in µm².
    Sellmeier { a: f64, terms: Vec<(f64, f64)> },
    /// Sellmeier, poles as wavelengths (Malitson's form):
    /// `n² = a + Σ B_i λ² / (λ² − λ_i²)`, λ in µm, terms `(B_i, λ_i)` with
    /// `λ_i` in µm.
    SellmeierPoles { a: f64, terms: Vec<(f64, f64)> },
    /// Sellmeier with an infrared term (Bond 1965's and the Handbook of
    /// Optics' form): `n² = a + Σ B_i λ² / (λ² − C_i) − ir λ²`, λ in µm,
    /// `C_i` in µm², `ir` in µm⁻².
    SellmeierIr {
        a: f64,
        terms: Vec<(f64, f64)>,
        ir: f64,
    },
    /// Cauchy: `n = a + b / λ² + c / λ⁴`, λ in µm (b in µm², c in µm⁴).
    Cauchy { a: f64, b: f64, c: f64 },
    /// The form of Edlén, Peck & Reeder and Ciddor for gases:
    /// `n − 1 = a + Σ B_i / (C_i − σ²)`, σ = 1/λ in µm⁻¹, terms `(B_i, C_i)`
    /// with `C_i` in µm⁻².
    Gas { a: f64, terms: Vec<(f64, f64)> },
}

impl Dispersion {
    /// Sellmeier with poles as squared wavelengths (see
    /// [`Dispersion::Sellmeier`]).
    pub fn sellmeier(a: f64, terms: &[(f64, f64)]) -> Self {
        Dispersion::Sellmeier {
            a,
            terms: terms.to_vec(),
        }
    }

    /// Sellmeier with poles as wavelengths (see
    /// [`Dispersion::SellmeierPoles`]).
    pub fn sellmeier_poles(a: f64, terms: &[(f64, f64)]) -> Self {
        Dispersion::SellmeierPoles {
            a,
            terms: terms.to_vec(),
        }
    }

    /// The refractive index at `lambda_nm`.
    pub fn n(&self, lambda_nm: f64) -> f64 {
        let l = lambda_nm * 1e-3; // µm
        let l2 = l * l;
        match self {
            Dispersion::Constant(n) => *n,
            Dispersion::Sellmeier { a, terms } => {
                let n2 = a + terms.iter().map(|&(b, c)| b * l2 / (l2 - c)).sum::<f64>();
                n2.sqrt()
            }
            Dispersion::SellmeierIr { a, terms, ir } => {
                let n2 = a + terms.iter().map(|&(b, c)| b * l2 / (l2 - c)).sum::<f64>() - ir * l2;
                n2.sqrt()
            }
            Dispersion::SellmeierPoles { a, terms } => {
                let n2 = a + terms
                    .iter()
                    .map(|&(b, p)| b * l2 / (l2 - p * p))
                    .sum::<f64>();
                n2.sqrt()
            }
            Dispersion::Cauchy { a, b, c } => a + b / l2 + c / (l2 * l2),
            Dispersion::Gas { a, terms } => {
                let s2 = 1.0 / l2;
                1.0 + a + terms.iter().map(|&(b, c)| b / (c - s2)).sum::<f64>()
            }
        }
    }

    /// True when the index does not depend on wavelength.
    pub fn is_constant(&self) -> bool {
        match self {
            Dispersion::Constant(_) => true,
            Dispersion::Sellmeier { terms, .. }
            | Dispersion::SellmeierPoles { terms, .. }
            | Dispersion::Gas { terms, .. } => terms.iter().all(|&(b, _)| b == 0.0),
            Dispersion::SellmeierIr { terms, ir, .. } => {
                *ir == 0.0 && terms.iter().all(|&(b, _)| b == 0.0)
            }
            Dispersion::Cauchy { b, c, .. } => *b == 0.0 && *c == 0.0,
        }
    }

    /// Every coefficient of the model.
    fn coefficients(&self) -> Vec<f64> {
        match self {
            Dispersion::Constant(n) => vec![*n],
            Dispersion::Sellmeier { a, terms }
            | Dispersion::SellmeierPoles { a, terms }
            | Dispersion::Gas { a, terms } => std::iter::once(*a)
                .chain(terms.iter().flat_map(|&(b, c)| [b, c]))
                .collect(),
            Dispersion::SellmeierIr { a, terms, ir } => [*a, *ir]
                .into_iter()
                .chain(terms.iter().flat_map(|&(b, c)| [b, c]))
                .collect(),
            Dispersion::Cauchy { a, b, c } => vec![*a, *b, *c],
        }
    }

    /// The wavelength (µm) of a pole of this term, if it has one.
    fn pole_um(&self, (b, c): (f64, f64)) -> Option<f64> {
        if b == 0.0 {
            return None;
        }
        match self {
            Dispersion::Sellmeier { .. } | Dispersion::SellmeierIr { .. } => {
                (c > 0.0).then(|| c.sqrt())
            }
            Dispersion::SellmeierPoles { .. } => (c != 0.0).then(|| c.abs()),
            Dispersion::Gas { .. } => (c > 0.0).then(|| 1.0 / c.sqrt()),
            Dispersion::Constant(_) | Dispersion::Cauchy { .. } => None,
        }
    }

    /// Checks that the model is usable over the visible range 380–780 nm:
    /// finite coefficients, no pole inside the range, and a finite positive
    /// index at every nanometre of it.
    pub fn validate(&self) -> Result<(), String> {
        if !self.coefficients().iter().all(|c| c.is_finite()) {
            return Err(format!("dispersion coefficients must be finite: {self:?}"));
        }
        let terms: &[(f64, f64)] = match self {
            Dispersion::Sellmeier { terms, .. }
            | Dispersion::SellmeierPoles { terms, .. }
            | Dispersion::SellmeierIr { terms, .. }
            | Dispersion::Gas { terms, .. } => terms,
            Dispersion::Constant(_) | Dispersion::Cauchy { .. } => &[],
        };
        let (lo, hi) = (LAMBDA_MIN_NM * 1e-3, LAMBDA_MAX_NM * 1e-3);
        for &term in terms {
            if let Some(pole) = self.pole_um(term) {
                if (lo..=hi).contains(&pole) {
                    return Err(format!(
                        "the dispersion model has a pole at {:.1} nm, inside 380-780 nm",
                        pole * 1e3
                    ));
                }
            }
        }
        let first = LAMBDA_MIN_NM as usize;
        let last = LAMBDA_MAX_NM as usize;
        for lambda in first..=last {
            let n = self.n(lambda as f64);
            if !(n.is_finite() && n > 0.0) {
                return Err(format!(
                    "the refractive index is {n} at {lambda} nm: it must be finite and positive \
                     over 380-780 nm"
                ));
            }
        }
        Ok(())
    }
}
