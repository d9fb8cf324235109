//! Measured polarized absorption spectra of coloured stones, as their
//! sources give them, and the conversions to spar's coefficient α per mm
//! (natural log: a path of `d` mm keeps `exp(−α d)`). docs/materials.md
//! ("Coloured stones") lists each source with its figure or file.
//!
//! The rows are the published numbers unchanged (a subset of them: see
//! each table); [`super::gems::spectrum`] converts them with the functions
//! here, at the concentration or scale stated per stone. Each row is
//! `(wavelength nm, value for E ⊥ c, value for E ∥ c)`: E ⊥ c is the
//! ordinary wave's spectrum (σ), E ∥ c the extraordinary's (π).
//!
//! The numbers were taken from the data files of the Rust gem renderer
//! indicatrix (github.com/suitable-name/indicatrix,
//! `crates/indicatrix/data/reference_spectra/`, commit ea4fb71), which
//! transcribed them from the sources named per table. The tests
//! (tests/spectrum_material/material_gems.rs) check a few rows against
//! the sources and the band maxima against the published positions.

use std::f64::consts::LN_10;

/// Cr³⁺ in corundum: absorption cross-section σ per Cr³⁺ ion, cm²
/// (natural log, reflection-corrected), E ⊥ c and E ∥ c. Dubinsky,
/// Stone-Sundberg & Emmett, "A quantitative description of the causes of
/// color in corundum", Gems & Gemology 56(1), 2–28 (2020), its
/// absorption cross-section data sheet (the spreadsheet published with
/// the article, column Cr³⁺): GIA sample 1110, a Czochralski synthetic
/// ruby wafer (c in its plane, Cr measured by SIMS), 1 nm steps,
/// 1.5 nm resolution. Rows here: every 5 nm from 380 to 780 nm, with the
/// 1 nm rows at the maxima (398 nm E ∥ c Y band, 558 nm E ⊥ c U band)
/// and at the R lines (692–694 nm). The flat ~1.5·10⁻²¹ cm² beyond
/// 640 nm is, per the data sheet, instrument baseline; it is left in
/// (0.03 mm⁻¹ at [`RUBY_CR_PER_CM3`]).
pub const RUBY_CR_SIGMA_CM2: &[(f64, f64, f64)] = &[
    (380.0, 7.724e-20, 1.765e-19),
    (385.0, 9.618e-20, 2.256e-19),
    (390.0, 1.162e-19, 2.689e-19),
    (395.0, 1.346e-19, 2.944e-19),
    (398.0, 1.444e-19, 2.985e-19),
    (400.0, 1.501e-19, 2.964e-19),
    (405.0, 1.612e-19, 2.753e-19),
    (410.0, 1.653e-19, 2.431e-19),
    (415.0, 1.618e-19, 2.109e-19),
    (420.0, 1.508e-19, 1.808e-19),
    (425.0, 1.329e-19, 1.530e-19),
    (430.0, 1.113e-19, 1.262e-19),
    (435.0, 8.810e-20, 9.975e-20),
    (440.0, 6.517e-20, 7.465e-20),
    (445.0, 4.525e-20, 5.336e-20),
    (450.0, 3.074e-20, 3.695e-20),
    (455.0, 2.162e-20, 2.567e-20),
    (460.0, 1.627e-20, 1.897e-20),
    (465.0, 1.334e-20, 1.443e-20),
    (470.0, 1.255e-20, 1.203e-20),
    (475.0, 1.472e-20, 1.178e-20),
    (480.0, 1.393e-20, 9.920e-21),
    (485.0, 1.717e-20, 1.074e-20),
    (490.0, 2.228e-20, 1.290e-20),
    (495.0, 2.848e-20, 1.587e-20),
    (500.0, 3.630e-20, 1.964e-20),
    (505.0, 4.574e-20, 2.396e-20),
    (510.0, 5.653e-20, 2.881e-20),
    (515.0, 6.868e-20, 3.394e-20),
    (520.0, 8.166e-20, 3.907e-20),
    (525.0, 9.599e-20, 4.420e-20),
    (530.0, 1.103e-19, 4.852e-20),
    (535.0, 1.241e-19, 5.204e-20),
    (540.0, 1.369e-19, 5.421e-20),
    (545.0, 1.477e-19, 5.503e-20),
    (550.0, 1.561e-19, 5.450e-20),
    (555.0, 1.610e-19, 5.208e-20),
    (558.0, 1.623e-19, 5.020e-20),
    (560.0, 1.621e-19, 4.859e-20),
    (565.0, 1.586e-19, 4.348e-20),
    (570.0, 1.499e-19, 3.784e-20),
    (575.0, 1.378e-19, 3.193e-20),
    (580.0, 1.221e-19, 2.602e-20),
    (585.0, 1.032e-19, 2.038e-20),
    (590.0, 8.290e-20, 1.556e-20),
    (595.0, 6.375e-20, 1.154e-20),
    (600.0, 4.677e-20, 8.599e-21),
    (605.0, 3.385e-20, 6.462e-21),
    (610.0, 2.364e-20, 4.594e-21),
    (615.0, 1.613e-20, 3.531e-21),
    (620.0, 1.131e-20, 2.735e-21),
    (625.0, 8.098e-21, 2.207e-21),
    (630.0, 5.693e-21, 1.947e-21),
    (635.0, 4.361e-21, 1.686e-21),
    (640.0, 3.565e-21, 1.694e-21),
    (645.0, 3.037e-21, 1.701e-21),
    (650.0, 2.508e-21, 1.440e-21),
    (655.0, 2.515e-21, 1.447e-21),
    (660.0, 3.326e-21, 2.258e-21),
    (665.0, 3.065e-21, 1.729e-21),
    (670.0, 3.340e-21, 1.467e-21),
    (675.0, 2.543e-21, 1.742e-21),
    (680.0, 2.014e-21, 1.480e-21),
    (685.0, 1.752e-21, 1.487e-21),
    (690.0, 2.026e-21, 1.225e-21),
    (692.0, 6.316e-21, 2.031e-21),
    (693.0, 8.730e-21, 2.032e-21),
    (694.0, 8.463e-21, 1.765e-21),
    (695.0, 5.516e-21, 1.499e-21),
    (700.0, 1.771e-21, 1.237e-21),
    (705.0, 1.777e-21, 1.243e-21),
    (710.0, 1.783e-21, 1.248e-21),
    (715.0, 1.788e-21, 1.254e-21),
    (720.0, 1.526e-21, 1.260e-21),
    (725.0, 1.800e-21, 1.265e-21),
    (730.0, 1.537e-21, 1.271e-21),
    (735.0, 1.811e-21, 1.276e-21),
    (740.0, 1.548e-21, 1.281e-21),
    (745.0, 1.286e-21, 1.018e-21),
    (750.0, 1.559e-21, 1.024e-21),
    (755.0, 1.564e-21, 1.297e-21),
    (760.0, 1.569e-21, 1.301e-21),
    (765.0, 1.574e-21, 1.306e-21),
    (770.0, 1.579e-21, 1.311e-21),
    (775.0, 1.584e-21, 1.048e-21),
    (780.0, 1.589e-21, 1.321e-21),
];

/// The Cr³⁺ concentration of the built-in ruby, per cm³: 2.0·10²⁰
/// (1700 ppma of all atoms, 0.63 wt% Cr₂O₃), so that α per mm is
/// σ / (5·10⁻²⁰ cm²): the E ⊥ c U band 3.25 mm⁻¹. Light crosses a
/// 6 mm stone along about 1 cm: 1700 ppma·cm, where the colours the
/// article computes from these spectra (its Appendix 2, D65) have E ⊥ c
/// red (L* 25, a* 65, b* 3 at 1500 ppma·cm; purplish, b* −18, at half
/// that). At half this concentration the gallery ruby rendered pink.
pub const RUBY_CR_PER_CM3: f64 = 2.0e20;

/// Fe²⁺–Ti⁴⁺ pairs in corundum: absorption cross-section σ per pair, cm²
/// (natural log, reflection-corrected), E ⊥ c and E ∥ c. Dubinsky et al.
/// 2020 (as [`RUBY_CR_SIGMA_CM2`]), the same data sheet, column Fe²⁺–Ti⁴⁺
/// (the mean of 14 Yogo Gulch sapphire wafers, the band shape from
/// Fe–Ti-doped synthetics; the article's text gives the E ⊥ c maximum as
/// 1.94·10⁻¹⁸ cm² ± 25 % at 580 nm). Rows: every 5 nm from 380 to 780 nm,
/// the data sheet's values rounded to four significant figures (the 5 nm
/// digest in indicatrix's `gia_v3plus_fe2plus_ti4plus_sigma_5nm.csv`).
pub const SAPPHIRE_FETI_SIGMA_CM2: &[(f64, f64, f64)] = &[
    (380.0, 2.585e-19, 2.605e-19),
    (385.0, 2.712e-19, 2.833e-19),
    (390.0, 2.832e-19, 3.049e-19),
    (395.0, 2.932e-19, 3.267e-19),
    (400.0, 3.039e-19, 3.469e-19),
    (405.0, 3.137e-19, 3.648e-19),
    (410.0, 3.240e-19, 3.819e-19),
    (415.0, 3.339e-19, 3.969e-19),
    (420.0, 3.454e-19, 4.108e-19),
    (425.0, 3.577e-19, 4.235e-19),
    (430.0, 3.717e-19, 4.367e-19),
    (435.0, 3.884e-19, 4.496e-19),
    (440.0, 4.067e-19, 4.621e-19),
    (445.0, 4.289e-19, 4.762e-19),
    (450.0, 4.538e-19, 4.904e-19),
    (455.0, 4.828e-19, 5.057e-19),
    (460.0, 5.159e-19, 5.214e-19),
    (465.0, 5.541e-19, 5.363e-19),
    (470.0, 5.987e-19, 5.510e-19),
    (475.0, 6.474e-19, 5.634e-19),
    (480.0, 7.000e-19, 5.735e-19),
    (485.0, 7.599e-19, 5.819e-19),
    (490.0, 8.263e-19, 5.876e-19),
    (495.0, 8.960e-19, 5.919e-19),
    (500.0, 9.715e-19, 5.951e-19),
    (505.0, 1.053e-18, 5.985e-19),
    (510.0, 1.138e-18, 6.031e-19),
    (515.0, 1.225e-18, 6.096e-19),
    (520.0, 1.314e-18, 6.186e-19),
    (525.0, 1.405e-18, 6.302e-19),
    (530.0, 1.496e-18, 6.445e-19),
    (535.0, 1.582e-18, 6.607e-19),
    (540.0, 1.662e-18, 6.787e-19),
    (545.0, 1.737e-18, 6.975e-19),
    (550.0, 1.803e-18, 7.170e-19),
    (555.0, 1.858e-18, 7.362e-19),
    (560.0, 1.903e-18, 7.556e-19),
    (565.0, 1.938e-18, 7.753e-19),
    (570.0, 1.963e-18, 7.945e-19),
    (575.0, 1.976e-18, 8.135e-19),
    (580.0, 1.980e-18, 8.323e-19),
    (585.0, 1.975e-18, 8.515e-19),
    (590.0, 1.963e-18, 8.711e-19),
    (595.0, 1.945e-18, 8.910e-19),
    (600.0, 1.921e-18, 9.120e-19),
    (605.0, 1.895e-18, 9.339e-19),
    (610.0, 1.867e-18, 9.561e-19),
    (615.0, 1.838e-18, 9.787e-19),
    (620.0, 1.807e-18, 1.001e-18),
    (625.0, 1.776e-18, 1.024e-18),
    (630.0, 1.743e-18, 1.047e-18),
    (635.0, 1.713e-18, 1.069e-18),
    (640.0, 1.685e-18, 1.090e-18),
    (645.0, 1.657e-18, 1.111e-18),
    (650.0, 1.630e-18, 1.132e-18),
    (655.0, 1.605e-18, 1.151e-18),
    (660.0, 1.583e-18, 1.169e-18),
    (665.0, 1.561e-18, 1.186e-18),
    (670.0, 1.541e-18, 1.202e-18),
    (675.0, 1.522e-18, 1.215e-18),
    (680.0, 1.503e-18, 1.228e-18),
    (685.0, 1.483e-18, 1.238e-18),
    (690.0, 1.463e-18, 1.245e-18),
    (695.0, 1.443e-18, 1.251e-18),
    (700.0, 1.422e-18, 1.254e-18),
    (705.0, 1.401e-18, 1.255e-18),
    (710.0, 1.378e-18, 1.255e-18),
    (715.0, 1.354e-18, 1.251e-18),
    (720.0, 1.330e-18, 1.246e-18),
    (725.0, 1.303e-18, 1.238e-18),
    (730.0, 1.275e-18, 1.228e-18),
    (735.0, 1.247e-18, 1.217e-18),
    (740.0, 1.218e-18, 1.203e-18),
    (745.0, 1.188e-18, 1.188e-18),
    (750.0, 1.157e-18, 1.170e-18),
    (755.0, 1.127e-18, 1.153e-18),
    (760.0, 1.095e-18, 1.132e-18),
    (765.0, 1.064e-18, 1.111e-18),
    (770.0, 1.030e-18, 1.088e-18),
    (775.0, 9.980e-19, 1.065e-18),
    (780.0, 9.664e-19, 1.041e-18),
];

/// The Fe²⁺–Ti⁴⁺ pair concentration of the built-in blue sapphire, per
/// cm³: 4.0·10¹⁸ (34 ppma of all atoms), so that α per mm is
/// σ · 4·10¹⁷ cm⁻² (the E ⊥ c band 0.79 mm⁻¹ at 580 nm): a medium blue
/// in a 6 mm stone (at half this the gallery stone rendered pale blue).
pub const SAPPHIRE_FETI_PER_CM3: f64 = 4.0e18;

/// Emerald, Caltech GRR 3570 (Afghanistan), decadic absorbance of a
/// 0.859 mm plate, E ⊥ c and E ∥ c: G. R. Rossman, Mineral Spectroscopy
/// Server, California Institute of Technology
/// (minerals.gps.caltech.edu, files `Visible/Beryl/Emerald_3570_a.asc`,
/// E ⊥ c, and `Emerald_3570_c.asc`, E ∥ c), resampled to 5 nm (the
/// digest in indicatrix's `caltech_emerald_grr3570_5nm.csv`). Reflection
/// at the plate's two faces and any baseline offset are in the numbers
/// (no composition was published for the stone).
pub const EMERALD_GRR3570_ABSORBANCE: &[(f64, f64, f64)] = &[
    (380.0, 0.30147, 0.30086),
    (385.0, 0.32029, 0.32697),
    (390.0, 0.34543, 0.36542),
    (395.0, 0.38266, 0.41252),
    (400.0, 0.42765, 0.46157),
    (405.0, 0.47461, 0.51114),
    (410.0, 0.52195, 0.55598),
    (415.0, 0.57021, 0.58868),
    (420.0, 0.6167, 0.60437),
    (425.0, 0.65731, 0.60247),
    (430.0, 0.68125, 0.58279),
    (435.0, 0.68453, 0.54475),
    (440.0, 0.67573, 0.50929),
    (445.0, 0.65452, 0.47217),
    (450.0, 0.61882, 0.42901),
    (455.0, 0.57324, 0.38829),
    (460.0, 0.52133, 0.34722),
    (465.0, 0.46133, 0.30975),
    (470.0, 0.4091, 0.28003),
    (475.0, 0.35688, 0.25126),
    (480.0, 0.3174, 0.22606),
    (485.0, 0.26924, 0.20636),
    (490.0, 0.23394, 0.19207),
    (495.0, 0.20873, 0.18263),
    (500.0, 0.19259, 0.17772),
    (505.0, 0.18427, 0.17672),
    (510.0, 0.18165, 0.17955),
    (515.0, 0.18361, 0.18583),
    (520.0, 0.18902, 0.19525),
    (525.0, 0.19748, 0.20745),
    (530.0, 0.209, 0.22208),
    (535.0, 0.22387, 0.2395),
    (540.0, 0.24252, 0.25918),
    (545.0, 0.26563, 0.28164),
    (550.0, 0.2919, 0.30646),
    (555.0, 0.32233, 0.33397),
    (560.0, 0.35552, 0.36315),
    (565.0, 0.3917, 0.39271),
    (570.0, 0.42919, 0.42286),
    (575.0, 0.46655, 0.45188),
    (580.0, 0.50485, 0.48087),
    (585.0, 0.53954, 0.50911),
    (590.0, 0.57225, 0.53905),
    (595.0, 0.5979, 0.57233),
    (600.0, 0.61454, 0.61292),
    (605.0, 0.62194, 0.6465),
    (610.0, 0.61628, 0.68317),
    (615.0, 0.598, 0.72607),
    (620.0, 0.57207, 0.76288),
    (625.0, 0.53951, 0.7958),
    (630.0, 0.50737, 0.82026),
    (635.0, 0.49502, 0.80857),
    (640.0, 0.48176, 0.82957),
    (645.0, 0.4398, 0.87089),
    (650.0, 0.3995, 0.86236),
    (655.0, 0.36433, 0.77697),
    (660.0, 0.34142, 0.74626),
    (665.0, 0.31677, 0.72578),
    (670.0, 0.29337, 0.63856),
    (675.0, 0.27317, 0.55658),
    (680.0, 0.27956, 0.52269),
    (685.0, 0.25719, 0.67553),
    (690.0, 0.2211, 0.48259),
    (695.0, 0.20207, 0.40694),
    (700.0, 0.18674, 0.35488),
    (705.0, 0.17456, 0.31632),
    (710.0, 0.16551, 0.28676),
    (715.0, 0.15814, 0.26463),
    (720.0, 0.15329, 0.24755),
    (725.0, 0.14926, 0.23509),
    (730.0, 0.14659, 0.2264),
    (735.0, 0.1453, 0.22103),
    (740.0, 0.14414, 0.21646),
    (745.0, 0.14327, 0.2139),
    (750.0, 0.14262, 0.2129),
    (755.0, 0.14224, 0.2122),
    (760.0, 0.1423, 0.2122),
    (765.0, 0.14236, 0.2121),
    (770.0, 0.14227, 0.21257),
    (775.0, 0.1426, 0.2128),
    (780.0, 0.14301, 0.2127),
];

/// The thickness of the GRR 3570 plate, mm.
pub const EMERALD_GRR3570_MM: f64 = 0.859;

/// The built-in emerald's coefficients as a fraction of GRR 3570's: a
/// third (the plate is a deep emerald; a third gives a medium-toned
/// stone a few mm across, the E ⊥ c U band 0.52 mm⁻¹).
pub const EMERALD_SCALE: f64 = 1.0 / 3.0;

/// α per mm from a cross-section `sigma_cm2` (cm², natural log) at
/// `per_cm3` absorbers per cm³: α = σ N per cm, a tenth of that per mm.
pub fn cross_section_per_mm(sigma_cm2: f64, per_cm3: f64) -> f64 {
    sigma_cm2 * per_cm3 / 10.0
}

/// The decadic absorbance of a plate's two faces at normal incidence, for
/// index `n`: each face transmits `1 − R`, `R = ((n − 1)/(n + 1))²`.
pub fn faces_absorbance(n: f64) -> f64 {
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    -2.0 * (1.0 - r).log10()
}

/// α per mm from the decadic absorbance `a` of a plate `d_mm` thick with
/// index `n`, times `scale`: the faces' reflection taken out (what is left
/// is absorbed inside), `α = scale · ln 10 · (a − a_faces) / d`, never
/// below 0.
pub fn absorbance_per_mm(a: f64, n: f64, d_mm: f64, scale: f64) -> f64 {
    (scale * LN_10 * (a - faces_absorbance(n)) / d_mm).max(0.0)
}
