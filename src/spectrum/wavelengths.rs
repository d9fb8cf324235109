//! Sets of wavelengths with quadrature weights: what a render integrates
//! over.
//!
//! A set is a list of wavelengths `λ_i` (nm) and weights `w_i` (nm) such that
//! `Σ w_i f(λ_i) ≈ ∫ f(λ) dλ` over the visible range 380–780 nm. The same type
//! serves a fixed grid (the seed's 21 wavelengths every 20 nm), an explicit
//! list, one wavelength (monochrome) and the few stratified wavelengths per
//! sample of hero-wavelength rendering ([`WavelengthSet::hero`]), whose
//! weights make the sum an unbiased Monte Carlo estimate of the integral.

use super::SpectrumError;

/// Shortest wavelength a set may hold, nm.
pub const LAMBDA_MIN_NM: f64 = 380.0;
/// Longest wavelength a set may hold, nm.
pub const LAMBDA_MAX_NM: f64 = 780.0;
/// Width of the visible range, nm.
pub const LAMBDA_RANGE_NM: f64 = LAMBDA_MAX_NM - LAMBDA_MIN_NM;

/// Wavelengths (nm) with quadrature weights (nm).
#[derive(Clone, Debug, PartialEq)]
pub struct WavelengthSet {
    lambdas: Vec<f64>,
    weights: Vec<f64>,
}

fn check_lambda(lambda_nm: f64) -> Result<(), SpectrumError> {
    if (LAMBDA_MIN_NM..=LAMBDA_MAX_NM).contains(&lambda_nm) {
        Ok(())
    } else {
        Err(SpectrumError::WavelengthOutOfRange(lambda_nm))
    }
}

impl WavelengthSet {
    /// `count` equally spaced wavelengths from 380 to 780 nm inclusive, with
    /// trapezoid weights (half a step at each end). `uniform(21)` is the
    /// seed's sampling, every 20 nm; `uniform(401)` every 1 nm; `uniform(1)`
    /// is 580 nm, the middle of the range.
    pub fn uniform(count: usize) -> Result<Self, SpectrumError> {
        match count {
            0 => Err(SpectrumError::Empty),
            1 => Self::single(0.5 * (LAMBDA_MIN_NM + LAMBDA_MAX_NM)),
            _ => {
                let step = LAMBDA_RANGE_NM / (count - 1) as f64;
                let lambdas: Vec<f64> = (0..count)
                    .map(|i| {
                        if i == count - 1 {
                            LAMBDA_MAX_NM
                        } else {
                            LAMBDA_MIN_NM + i as f64 * step
                        }
                    })
                    .collect();
                Self::from_list(&lambdas)
            }
        }
    }

    /// An explicit list of wavelengths (nm, any order, no duplicates). Each
    /// wavelength weighs the width of the part of 380–780 nm nearer to it
    /// than to any other listed wavelength; on an equally spaced grid with
    /// both ends this is the trapezoid rule.
    pub fn from_list(lambdas: &[f64]) -> Result<Self, SpectrumError> {
        if lambdas.is_empty() {
            return Err(SpectrumError::Empty);
        }
        for &l in lambdas {
            check_lambda(l)?;
        }
        let mut order: Vec<usize> = (0..lambdas.len()).collect();
        order.sort_by(|&a, &b| lambdas[a].total_cmp(&lambdas[b]));
        for pair in order.windows(2) {
            if lambdas[pair[0]] == lambdas[pair[1]] {
                return Err(SpectrumError::Duplicate(lambdas[pair[0]]));
            }
        }
        let mut weights = vec![0.0; lambdas.len()];
        for (rank, &i) in order.iter().enumerate() {
            let lo = if rank == 0 {
                LAMBDA_MIN_NM
            } else {
                0.5 * (lambdas[order[rank - 1]] + lambdas[i])
            };
            let hi = if rank + 1 == order.len() {
                LAMBDA_MAX_NM
            } else {
                0.5 * (lambdas[i] + lambdas[order[rank + 1]])
            };
            weights[i] = hi - lo;
        }
        Ok(WavelengthSet {
            lambdas: lambdas.to_vec(),
            weights,
        })
    }

    /// One wavelength (monochrome rendering), weighing the whole range.
    pub fn single(lambda_nm: f64) -> Result<Self, SpectrumError> {
        check_lambda(lambda_nm)?;
        Ok(WavelengthSet {
            lambdas: vec![lambda_nm],
            weights: vec![LAMBDA_RANGE_NM],
        })
    }

    /// Wavelengths with weights of your choosing (both in nm; weights
    /// finite and non-negative).
    pub fn with_weights(lambdas: &[f64], weights: &[f64]) -> Result<Self, SpectrumError> {
        if lambdas.is_empty() {
            return Err(SpectrumError::Empty);
        }
        if lambdas.len() != weights.len() {
            return Err(SpectrumError::WeightCount {
                lambdas: lambdas.len(),
                weights: weights.len(),
            });
        }
        for (&l, &w) in lambdas.iter().zip(weights) {
            check_lambda(l)?;
            if !(w.is_finite() && w >= 0.0) {
                return Err(SpectrumError::BadWeight(w));
            }
        }
        Ok(WavelengthSet {
            lambdas: lambdas.to_vec(),
            weights: weights.to_vec(),
        })
    }

    /// Hero-wavelength sampling (Wilkie et al. 2014): `count` wavelengths
    /// equally spaced around the range, rotated by `u` ∈ [0, 1) (one random
    /// number per sample). The first is the hero wavelength
    /// `380 + 400 u` nm; the others follow at `400 / count` nm intervals,
    /// wrapping around the range. Each weighs `400 / count` nm (one over the
    /// uniform density), so over random `u` the weighted sum is an unbiased
    /// estimate of the integral over 380–780 nm. `u` outside [0, 1) wraps;
    /// `count = 0` is treated as 1.
    pub fn hero(count: usize, u: f64) -> Self {
        let count = count.max(1);
        let u = if u.is_finite() {
            u.rem_euclid(1.0)
        } else {
            0.0
        };
        let lambdas = (0..count)
            .map(|j| {
                let f = (u + j as f64 / count as f64).fract();
                (LAMBDA_MIN_NM + f * LAMBDA_RANGE_NM).min(LAMBDA_MAX_NM)
            })
            .collect();
        WavelengthSet {
            lambdas,
            weights: vec![LAMBDA_RANGE_NM / count as f64; count],
        }
    }

    /// Parses a set from text: a count (`21`: [`Self::uniform`]), one
    /// wavelength with its unit (`580nm`: [`Self::single`]), or a comma
    /// separated list of wavelengths in nm (`450,550,650` or
    /// `450nm,550nm,650nm`: [`Self::from_list`]).
    pub fn parse(spec: &str) -> Result<Self, String> {
        let spec = spec.trim();
        let number = |s: &str| -> Result<f64, String> {
            let s = s.trim();
            let s = s.strip_suffix("nm").unwrap_or(s).trim();
            s.parse::<f64>()
                .map_err(|_| format!("`{s}` is not a wavelength in nm"))
        };
        let result = if spec.contains(',') {
            let list = spec.split(',').map(number).collect::<Result<Vec<_>, _>>()?;
            Self::from_list(&list)
        } else if spec.ends_with("nm") {
            Self::single(number(spec)?)
        } else {
            let count: usize = spec.parse().map_err(|_| {
                format!(
                    "`{spec}` is not a wavelength set: give a count (21), one wavelength \
                     (580nm) or a list in nm (450,550,650)"
                )
            })?;
            Self::uniform(count)
        };
        result.map_err(|e| e.to_string())
    }

    /// The wavelengths, nm.
    pub fn lambdas(&self) -> &[f64] {
        &self.lambdas
    }

    /// The quadrature weights, nm.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Number of wavelengths.
    pub fn len(&self) -> usize {
        self.lambdas.len()
    }

    /// Always false: a set holds at least one wavelength.
    pub fn is_empty(&self) -> bool {
        self.lambdas.is_empty()
    }

    /// True when the set holds one wavelength.
    pub fn is_monochrome(&self) -> bool {
        self.lambdas.len() == 1
    }

    /// `(λ, w)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.lambdas
            .iter()
            .copied()
            .zip(self.weights.iter().copied())
    }

    /// The quadrature `Σ w_i f(λ_i)`.
    pub fn integrate(&self, f: impl Fn(f64) -> f64) -> f64 {
        self.iter().map(|(l, w)| w * f(l)).sum()
    }
}
