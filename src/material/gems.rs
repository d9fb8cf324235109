//! Gem materials: dispersion from published fits, and for coloured
//! varieties absorption per eigenwave (docs/materials.md has the table with
//! every source). Biaxial gems (topaz, peridot, tanzanite, chrysoberyl, iolite)
//! have their principal indices n_α ≤ n_β ≤ n_γ along crystal x, y, z and
//! absorb nothing (biaxial absorption is not modelled).
//!
//! Dispersion: each index is the published fit as its paper (or the
//! refractiveindex.info database entry that reproduces it, named below)
//! gives it, transformed here only in form (`A + B/(λ² − C)` becomes the
//! Sellmeier form `(A − B/C) + (B/C) λ²/(λ² − C)`, exactly). Where no
//! Sellmeier fit of a gem mineral is published (beryl, tourmaline,
//! zircon, topaz, peridot, tanzanite, iolite), the index is the Cauchy law
//! `n = a + b/λ²` through two published gemmological constants: the index
//! at the sodium D line (589.3 nm) and the dispersion
//! `n(430.8 nm) − n(686.7 nm)` (the B–G interval of the Fraunhofer lines),
//! the same `b` for every wave (so the indices never cross).
//!
//! Absorption: ruby, blue sapphire and emerald are measured spectra
//! (tables, [`Curve::Table`], from [`super::measured`], which names each
//! source and its conversion to α per mm); aquamarine is still a sum of
//! Gaussian bands ([`Curve::Bands`]) at its cited band positions for the
//! field normal to the optic axis (`o`, the σ or E ⊥ c spectrum) and
//! along it (`e`, π, E ∥ c), the heights and widths set by hand so that
//! its colours follow the cited spectra (no measured coefficients of an
//! aquamarine were at hand). A scene can give any measured table instead
//! (`absorption_o = { nm = […], per_mm = […] }`).

use super::absorption::{Absorption, Curve};
use super::measured;
use super::{Dispersion, Material};

/// Gem names [`gem`] knows (case-insensitive; `_` and spaces count as
/// `-`), after the catalogue's own [`super::BUILTIN_NAMES`].
pub const GEM_NAMES: &[&str] = &[
    "corundum",
    "ruby",
    "blue-sapphire",
    "beryl",
    "emerald",
    "aquamarine",
    "tourmaline",
    "zircon",
    "spinel",
    "moissanite",
    "rutile",
    "cubic-zirconia",
    "yag",
    "mgf2",
    "fluorite",
    "zincite",
    "scheelite",
    "bromellite",
    "topaz",
    "peridot",
    "tanzanite",
    "chrysoberyl",
    "iolite",
];

/// Names of the built-in absorption spectra, per mm: a stone's `-o`
/// (field normal to the optic axis) and `-e` (field along it) curves.
pub const SPECTRUM_NAMES: &[&str] = &[
    "ruby-o",
    "ruby-e",
    "blue-sapphire-o",
    "blue-sapphire-e",
    "emerald-o",
    "emerald-e",
    "aquamarine-o",
    "aquamarine-e",
];

/// The gem material called `key` (already lower case, `-` for `_` and
/// spaces), or `None`. `sapphire` is the catalogue's corundum (Malitson &
/// Dodge 1972, [`super::catalog::sapphire`]), which ruby and blue
/// sapphire share.
pub fn gem(key: &str, sapphire: fn() -> Material) -> Option<Material> {
    let absorbing = |m: Material, name: &str| {
        let o = spectrum(&format!("{name}-o")).expect("listed");
        let e = spectrum(&format!("{name}-e")).expect("listed");
        m.renamed(name)
            .with_absorption(Some(Absorption { o, e }))
            .expect("valid")
    };
    Some(match key {
        "corundum" => sapphire().renamed("corundum"),
        // Ruby and blue sapphire: corundum's dispersion (Malitson & Dodge
        // 1972; the colouring ions at 0.01–1 wt% move the index by about
        // 0.001) with their ions' absorption.
        "ruby" => absorbing(sapphire(), "ruby"),
        "blue-sapphire" => absorbing(sapphire(), "blue-sapphire"),
        "beryl" => beryl("beryl"),
        "emerald" => absorbing(beryl("emerald"), "emerald"),
        "aquamarine" => absorbing(beryl("aquamarine"), "aquamarine"),
        // GIA Gem Reference Guide (1995), tourmaline: RI 1.624–1.644
        // (ε–ω, negative), dispersion 0.017.
        "tourmaline" => uniaxial(
            "tourmaline",
            gemmological(1.644, 0.017),
            gemmological(1.624, 0.017),
        ),
        // GIA Gem Reference Guide (1995), zircon (high): RI 1.925–1.984
        // (ω–ε, positive), dispersion 0.039.
        "zircon" => uniaxial(
            "zircon",
            gemmological(1.925, 0.039),
            gemmological(1.984, 0.039),
        ),
        // Tropf & Thomas, "Magnesium aluminum spinel", in Palik (ed.),
        // Handbook of Optical Constants of Solids II (1991), 881; the
        // Handbook of Optics (3rd ed., vol. 4, 2009) fit, as
        // refractiveindex.info MgAl2O4/Tropf: poles in µm.
        "spinel" => isotropic(
            "spinel",
            Dispersion::sellmeier_poles(1.0, &[(1.8938, 0.09942), (3.0755, 15.826)]),
        ),
        // Wang et al., "4H-SiC: a new nonlinear material for midinfrared
        // lasers", Laser Photonics Rev. 7, 831 (2013), 6H-SiC (the
        // moissanite polytype), as refractiveindex.info SiC/Wang-6H-o, -e:
        // n² = A + B/(λ² − C) − D λ².
        "moissanite" => uniaxial(
            "moissanite",
            a_b_c_d(6.57232, 0.1401, 0.03178, 0.02153),
            a_b_c_d(6.7452, 0.15352, 0.03597, 0.02249),
        ),
        // Devore, "Refractive indices of rutile and sphalerite", J. Opt.
        // Soc. Am. 41, 416 (1951): n² = A + B/(λ² − C).
        "rutile" => uniaxial(
            "rutile",
            a_b_c_d(5.913, 0.2441, 0.0803, 0.0),
            a_b_c_d(7.197, 0.3322, 0.0843, 0.0),
        ),
        // Wood & Nassau, "Refractive index of cubic zirconia stabilized
        // with yttria", Appl. Opt. 21, 2978 (1982): poles in µm.
        "cubic-zirconia" => isotropic(
            "cubic-zirconia",
            Dispersion::sellmeier_poles(
                1.0,
                &[
                    (1.347_091, 0.062_543),
                    (2.117_788, 0.166_739),
                    (9.452_943, 24.320_570),
                ],
            ),
        ),
        // Zelmon, Small & Page, "Refractive-index measurements of undoped
        // yttrium aluminum garnet from 0.4 to 5.0 µm", Appl. Opt. 37, 4933
        // (1998): C in µm².
        "yag" => isotropic(
            "yag",
            Dispersion::sellmeier(1.0, &[(2.282, 0.01185), (3.27644, 282.734)]),
        ),
        // Dodge, "Refractive properties of magnesium fluoride", Appl. Opt.
        // 23, 1980 (1984): poles in µm.
        "mgf2" => uniaxial(
            "mgf2",
            Dispersion::sellmeier_poles(
                1.0,
                &[
                    (0.487_551_08, 0.043_384_08),
                    (0.398_750_31, 0.094_614_42),
                    (2.312_035_3, 23.793_604),
                ],
            ),
            Dispersion::sellmeier_poles(
                1.0,
                &[
                    (0.413_440_23, 0.036_842_62),
                    (0.504_974_99, 0.090_761_62),
                    (2.490_486_2, 23.771_995),
                ],
            ),
        ),
        // Malitson, "A redetermination of some optical properties of
        // calcium fluoride", Appl. Opt. 2, 1103 (1963): poles in µm.
        "fluorite" => isotropic(
            "fluorite",
            Dispersion::sellmeier_poles(
                1.0,
                &[
                    (0.567_588_8, 0.050_263_605),
                    (0.471_091_4, 0.100_390_9),
                    (3.848_472_3, 34.649_040),
                ],
            ),
        ),
        // Bond, "Measurement of the refractive indices of several
        // crystals", J. Appl. Phys. 36, 1674 (1965), ZnO, in the Handbook
        // of Optics' form (refractiveindex.info ZnO/Bond-o, -e):
        // n² = A + B λ²/(λ² − C²) − D λ².
        "zincite" => uniaxial(
            "zincite",
            Dispersion::SellmeierIr {
                a: 2.81418,
                terms: vec![(0.87968, 0.3042 * 0.3042)],
                ir: 0.00711,
            },
            Dispersion::SellmeierIr {
                a: 2.80333,
                terms: vec![(0.94470, 0.3004 * 0.3004)],
                ir: 0.00714,
            },
        ),
        // Bond 1965 (as for zincite), CaWO4 (refractiveindex.info
        // CaWO4/Bond-o, -e): poles in µm.
        "scheelite" => uniaxial(
            "scheelite",
            Dispersion::sellmeier_poles(1.0, &[(2.5493, 0.1347), (0.9200, 10.815)]),
            Dispersion::sellmeier_poles(1.0, &[(2.6041, 0.1379), (4.1237, 21.371)]),
        ),
        // Edwards & White, "Beryllium oxide", in Palik (ed.), Handbook of
        // Optical Constants of Solids II (1991), 805 (refractiveindex.info
        // BeO/Edwards-o, -e): poles in µm.
        "bromellite" => uniaxial(
            "bromellite",
            Dispersion::sellmeier_poles(1.0, &[(1.92274, 0.07908), (1.24209, 9.7131)]),
            Dispersion::sellmeier_poles(1.0, &[(1.96939, 0.08590), (1.67389, 10.4797)]),
        ),
        // Biaxial gems: principal indices n_α ≤ n_β ≤ n_γ along crystal x,
        // y, z (the indicatrix axes X, Y, Z; docs/materials.md, "Biaxial
        // gems"). Colourless here: biaxial media do not absorb in spar.
        //
        // Topaz (colourless and blue, the fluorine-rich topaz these colours
        // come in): Anthony, Bideaux, Bladh & Nichols, Handbook of
        // Mineralogy, vol. II (Mineralogical Society of America, 1995),
        // topaz: α 1.606–1.629, β 1.609–1.631, γ 1.616–1.638, biaxial (+),
        // 2V(meas.) 48°–68°. The three indices rise together with OH for F,
        // so the low end of each range is one composition, F-rich topaz,
        // with the largest 2V. Dispersion 0.014 (GIA Gem Reference Guide,
        // 1995).
        "topaz" => biaxial(
            "topaz",
            gemmological(1.606, 0.014),
            gemmological(1.609, 0.014),
            gemmological(1.616, 0.014),
        ),
        // Peridot (forsterite-rich olivine): GIA Gem Reference Guide (1995),
        // RI 1.654–1.690 (n_α–n_γ), birefringence 0.036, dispersion 0.020,
        // biaxial "positive or negative", β "usually near halfway between
        // α and γ": β is taken at the midpoint, 1.672 (2V ≈ 90°).
        "peridot" => biaxial(
            "peridot",
            gemmological(1.654, 0.020),
            gemmological(1.672, 0.020),
            gemmological(1.690, 0.020),
        ),
        // Iolite (gem cordierite): Arem, Color Encyclopedia of Gemstones
        // (2nd ed., Van Nostrand Reinhold, 1987), cordierite, the Sri
        // Lanka specimen: α 1.530, β 1.534, γ 1.539 (as the International
        // Gem Society's cordierite page reproduces it); dispersion 0.017
        // (The Gemology Project, iolite). 2V_z = 83.9°, positive: inside
        // Arem's 65°–104° for cordierite.
        "iolite" => biaxial(
            "iolite",
            gemmological(1.530, 0.017),
            gemmological(1.534, 0.017),
            gemmological(1.539, 0.017),
        ),
        // Tanzanite (blue zoisite): O'Donoghue (ed.), Gems, 6th ed.
        // (Butterworth-Heinemann, 2006), tanzanite: α 1.692, β 1.693,
        // γ 1.700, biaxial (+); dispersion 0.012 (The Gemology Project,
        // zoisite).
        "tanzanite" => biaxial(
            "tanzanite",
            gemmological(1.692, 0.012),
            gemmological(1.693, 0.012),
            gemmological(1.700, 0.012),
        ),
        // Chrysoberyl (BeAl₂O₄): Walling, Peterson, Jenssen, Morris &
        // O'Dell, "Tunable alexandrite lasers", IEEE J. Quantum Electron.
        // 16, 1302 (1980), measured indices; fitted by Loiko & Major,
        // "Dispersive properties of alexandrite and beryllium
        // hexaaluminate crystals", Opt. Mater. Express 6, 2177 (2016), as
        // refractiveindex.info BeAl2O4/Walling-c, -a, -b (light polarized
        // along the Pnma axes c, a, b: n_α, n_β, n_γ):
        // n² = A + B λ²/(λ² − C) − D λ².
        "chrysoberyl" => biaxial(
            "chrysoberyl",
            Dispersion::SellmeierIr {
                a: 1.70690,
                terms: vec![(1.28477, 0.01169)],
                ir: 0.01760,
            },
            Dispersion::SellmeierIr {
                a: 1.78522,
                terms: vec![(1.21202, 0.01262)],
                ir: 0.01681,
            },
            Dispersion::SellmeierIr {
                a: 1.58829,
                terms: vec![(1.42711, 0.01113)],
                ir: 0.01696,
            },
        ),
        _ => return None,
    })
}

/// The built-in absorption spectrum called `key` (lower case), per mm.
pub fn spectrum(key: &str) -> Option<Curve> {
    let bands = |bands: &[(f64, f64, f64)]| Curve::Bands {
        floor: 0.0,
        bands: bands.to_vec(),
    };
    // A measured table: column `o` (E ⊥ c) or `e` (E ∥ c) of `rows`, each
    // value turned into α per mm by `per_mm`.
    let table = |rows: &[(f64, f64, f64)], e: bool, per_mm: &dyn Fn(f64) -> f64| Curve::Table {
        nm: rows.iter().map(|r| r.0).collect(),
        per_mm: rows
            .iter()
            .map(|r| per_mm(if e { r.2 } else { r.1 }))
            .collect(),
    };
    let ruby = |s: f64| measured::cross_section_per_mm(s, measured::RUBY_CR_PER_CM3);
    let sapphire = |s: f64| measured::cross_section_per_mm(s, measured::SAPPHIRE_FETI_PER_CM3);
    // Beryl's ω and ε at 589 nm ([`beryl`]) for each wave's reflection.
    let emerald = |n: f64| {
        move |a: f64| {
            measured::absorbance_per_mm(a, n, measured::EMERALD_GRR3570_MM, measured::EMERALD_SCALE)
        }
    };
    Some(match key {
        // Cr³⁺ in corundum, measured (Dubinsky et al. 2020,
        // [`measured::RUBY_CR_SIGMA_CM2`]): the U and Y bands at 558 and
        // 410 nm for E ⊥ c, 545 and 398 nm for E ∥ c, the U band a third
        // as strong in E ∥ c, as McClure ("Optical spectra of
        // transition-metal ions in corundum", J. Chem. Phys. 36, 2757
        // (1962)) places them (555.6, 409.8; 542.0, 396.8 nm): the o
        // colour purplish red, the e colour orangy red.
        "ruby-o" => table(measured::RUBY_CR_SIGMA_CM2, false, &ruby),
        "ruby-e" => table(measured::RUBY_CR_SIGMA_CM2, true, &ruby),
        // Fe²⁺–Ti⁴⁺ charge transfer in corundum, measured (Dubinsky et al.
        // 2020, [`measured::SAPPHIRE_FETI_SIGMA_CM2`]): the band at 580 nm
        // for E ⊥ c, near 705 nm and weaker for E ∥ c (Townsend, "Visible
        // charge transfer band in blue sapphire", Solid State Commun. 6,
        // 81 (1968): 700 nm): the o colour violetish blue, the e colour
        // greenish blue. Fe³⁺ (the 450 nm line) is not in it.
        "blue-sapphire-o" => table(measured::SAPPHIRE_FETI_SIGMA_CM2, false, &sapphire),
        "blue-sapphire-e" => table(measured::SAPPHIRE_FETI_SIGMA_CM2, true, &sapphire),
        // Cr³⁺ in beryl, measured (Caltech GRR 3570,
        // [`measured::EMERALD_GRR3570_ABSORBANCE`]): the ⁴T₂ (U) band at
        // 605 nm and the ⁴T₁ (Y) band at 435 nm for E ⊥ c; for E ∥ c the U
        // band moved toward the red (645 nm) and the Y band toward the
        // violet (420 nm), as Wood, Ferguson, Knox & Dillon ("Crystal-field
        // spectra of d³,⁷ ions. III", J. Chem. Phys. 39, 890 (1963))
        // describe: the o colour yellowish green, the e colour bluish green.
        "emerald-o" => table(measured::EMERALD_GRR3570_ABSORBANCE, false, &emerald(1.580)),
        "emerald-e" => table(measured::EMERALD_GRR3570_ABSORBANCE, true, &emerald(1.574)),
        // Fe in beryl, modelled: Fe²⁺ near 820 nm in both, the Fe²⁺–Fe³⁺
        // charge transfer near 620 nm for E ∥ c (Goldman, Rossman &
        // Parkin, "Channel constituents in beryl", Phys. Chem. Minerals 3,
        // 225 (1978)), Fe³⁺ at 427 nm in both and 370 nm for E ⊥ c
        // (Choudhary, "Aquamarine with unusually strong dichroism", Gems &
        // Gemology 50(3), 2014): the e colour blue, the o colour pale
        // bluish green.
        "aquamarine-o" => bands(&[(820.0, 0.45, 0.15), (427.0, 0.15, 0.05), (370.0, 0.2, 0.08)]),
        "aquamarine-e" => bands(&[
            (620.0, 0.45, 0.12),
            (820.0, 0.45, 0.10),
            (427.0, 0.15, 0.05),
        ]),
        _ => return None,
    })
}

fn isotropic(name: &str, n: Dispersion) -> Material {
    Material::isotropic(name, n).expect("valid")
}

fn uniaxial(name: &str, n_o: Dispersion, n_e: Dispersion) -> Material {
    Material::uniaxial(name, n_o, n_e).expect("valid")
}

/// A biaxial gem with `n_α`, `n_β`, `n_γ` along crystal x, y, z.
fn biaxial(name: &str, alpha: Dispersion, beta: Dispersion, gamma: Dispersion) -> Material {
    Material::biaxial(name, alpha, beta, gamma).expect("valid")
}

/// Beryl (emerald, aquamarine): GIA Gem Reference Guide (1995), RI
/// 1.577–1.583 (ε–ω, negative: ω 1.580 and ε 1.574 taken at mid-range,
/// birefringence 0.006), dispersion 0.014.
fn beryl(name: &str) -> Material {
    uniaxial(name, gemmological(1.580, 0.014), gemmological(1.574, 0.014))
}

/// The Cauchy law `n = a + b/λ²` (λ in µm) with index `n_d` at 589.3 nm
/// and `n(430.8 nm) − n(686.7 nm) = bg`.
fn gemmological(n_d: f64, bg: f64) -> Dispersion {
    let inv2 = |nm: f64| 1.0 / (nm * 1e-3 * nm * 1e-3);
    let b = bg / (inv2(430.8) - inv2(686.7));
    Dispersion::Cauchy {
        a: n_d - b * inv2(589.3),
        b,
        c: 0.0,
    }
}

/// `n² = A + B/(λ² − C) − D λ²` (λ in µm, C in µm²) in the Sellmeier
/// form: `B/(λ² − C) = (B/C) λ²/(λ² − C) − B/C`.
fn a_b_c_d(a: f64, b: f64, c: f64, d: f64) -> Dispersion {
    Dispersion::SellmeierIr {
        a: a - b / c,
        terms: vec![(b / c, c)],
        ir: d,
    }
}
