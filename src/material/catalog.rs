//! Built-in media with cited dispersion data.
//!
//! Every model is valid over 380–780 nm; the tests in
//! `tests/spectrum_material/material_indices.rs` check each against a published index.

use super::{Dispersion, Material};

/// Names accepted by [`builtin`] (case-insensitive), aliases after the
/// canonical names.
pub const BUILTIN_NAMES: &[&str] = &[
    "vacuum",
    "air",
    "standard-air",
    "n-bk7",
    "fused-silica",
    "diamond",
    "calcite",
    "quartz",
    "sapphire",
];

pub use super::gems::SPECTRUM_NAMES;

/// The built-in absorption spectrum called `name` (case-insensitive; `_`
/// and spaces count as `-`), per mm ([`SPECTRUM_NAMES`]).
pub fn absorption_spectrum(name: &str) -> Option<super::Curve> {
    super::gems::spectrum(&canonical(name))
}

/// Every name [`builtin`] knows, for the message of an unknown one: the
/// media above, then the gems of [`super::gems`].
pub fn known_names() -> Vec<&'static str> {
    BUILTIN_NAMES
        .iter()
        .chain(super::gems::GEM_NAMES)
        .copied()
        .collect()
}

/// A name as the catalogue looks it up: trimmed, lower case, `_` and
/// spaces as `-`.
fn canonical(name: &str) -> String {
    name.trim()
        .to_ascii_lowercase()
        .chars()
        .map(|c| if c == '_' || c == ' ' { '-' } else { c })
        .collect()
}

/// Aliases and the canonical name each stands for.
const ALIASES: &[(&str, &str)] = &[
    ("ciddor-air", "standard-air"),
    ("bk7", "n-bk7"),
    ("silica", "fused-silica"),
    ("crystal-quartz", "quartz"),
];

/// Vacuum: n = 1 exactly.
pub fn vacuum() -> Material {
    Material::isotropic("vacuum", Dispersion::Constant(1.0)).expect("valid")
}

/// Air as renders have it around every object: n = 1 exactly, the
/// ambient medium of every scene (`render::integrator::AMBIENT`), so that
/// `air` names one medium in scene files, renders and `spar interface`.
/// Real air's index, for comparisons that need it, is [`standard_air`].
pub fn air() -> Material {
    Material::isotropic("air", Dispersion::Constant(1.0)).expect("valid")
}

/// Standard dry air (15 °C, 101 325 Pa, 450 ppm CO₂), `standard-air`:
/// n − 1 = 2.77e-4 at 589.3 nm. Renders do not put it around objects
/// ([`air`]); a scene may use it as an object's medium.
pub fn standard_air() -> Material {
    // Ciddor 1996, "Refractive index of air: new equations for the visible
    // and near infrared", Appl. Opt. 35, 1566, eq. (1):
    // (n − 1) = k1/(k0 − σ²) + k3/(k2 − σ²), σ in µm⁻¹.
    Material::isotropic(
        "standard-air",
        Dispersion::Gas {
            a: 0.0,
            terms: vec![(0.057_921_05, 238.0185), (0.001_679_17, 57.362)],
        },
    )
    .expect("valid")
}

/// Schott N-BK7 borosilicate crown glass.
pub fn n_bk7() -> Material {
    // Schott optical glass data sheet N-BK7 (517642.251), Sellmeier
    // B1..B3, C1..C3 (C in µm²).
    Material::isotropic(
        "n-bk7",
        Dispersion::sellmeier(
            1.0,
            &[
                (1.039_612_12, 0.006_000_698_67),
                (0.231_792_344, 0.020_017_914_4),
                (1.010_469_45, 103.560_653),
            ],
        ),
    )
    .expect("valid")
}

/// Fused silica (amorphous SiO₂).
pub fn fused_silica() -> Material {
    // Malitson 1965, "Interspecimen comparison of the refractive index of
    // fused silica", J. Opt. Soc. Am. 55, 1205: poles as wavelengths in µm.
    Material::isotropic(
        "fused-silica",
        Dispersion::sellmeier_poles(
            1.0,
            &[
                (0.696_166_3, 0.068_404_3),
                (0.407_942_6, 0.116_241_4),
                (0.897_479_4, 9.896_161),
            ],
        ),
    )
    .expect("valid")
}

/// Diamond.
pub fn diamond() -> Material {
    // Peter 1923, "Über Brechungsindizes und Absorptionskonstanten des
    // Diamanten zwischen 644 und 226 mµ", Z. Phys. 15, 358 (the two-term
    // Sellmeier fit as tabulated by refractiveindex.info; docs/physics.md §8.1):
    // poles at 0.1750 µm and 0.1060 µm.
    Material::isotropic(
        "diamond",
        Dispersion::sellmeier_poles(1.0, &[(0.3306, 0.1750), (4.3356, 0.1060)]),
    )
    .expect("valid")
}

/// Calcite (CaCO₃), negative uniaxial.
pub fn calcite() -> Material {
    // Ghosh 1999, "Dispersion-equation coefficients for the refractive index
    // and birefringence of calcite and quartz crystals", Opt. Commun. 163, 95:
    // n² = A + B1 λ²/(λ² − C1) + B2 λ²/(λ² − C2), C in µm².
    Material::uniaxial(
        "calcite",
        Dispersion::sellmeier(
            1.733_587_49,
            &[(0.964_643_45, 1.943_252_03e-2), (1.828_314_54, 120.0)],
        ),
        Dispersion::sellmeier(
            1.358_596_95,
            &[(0.824_278_30, 1.066_895_43e-2), (0.144_291_28, 120.0)],
        ),
    )
    .expect("valid")
}

/// Crystal quartz (α-SiO₂), positive uniaxial (its optical activity is not
/// modelled).
pub fn quartz() -> Material {
    // Ghosh 1999 (as for calcite), Opt. Commun. 163, 95.
    Material::uniaxial(
        "quartz",
        Dispersion::sellmeier(
            1.286_041_41,
            &[(1.070_440_83, 1.005_859_97e-2), (1.102_022_42, 100.0)],
        ),
        Dispersion::sellmeier(
            1.288_518_04,
            &[(1.095_099_24, 1.021_018_64e-2), (1.156_624_75, 100.0)],
        ),
    )
    .expect("valid")
}

/// Sapphire (α-Al₂O₃), negative uniaxial.
pub fn sapphire() -> Material {
    // Malitson & Dodge 1972, "Refractive index and birefringence of synthetic
    // sapphire", J. Opt. Soc. Am. 62, 1405: poles as wavelengths in µm.
    Material::uniaxial(
        "sapphire",
        Dispersion::sellmeier_poles(
            1.0,
            &[
                (1.431_349_3, 0.072_663_1),
                (0.650_547_13, 0.119_324_2),
                (5.341_402_1, 18.028_251),
            ],
        ),
        Dispersion::sellmeier_poles(
            1.0,
            &[
                (1.503_975_9, 0.074_028_8),
                (0.550_691_41, 0.121_652_9),
                (6.592_737_9, 20.072_248),
            ],
        ),
    )
    .expect("valid")
}

/// The built-in material called `name` (case-insensitive; `_` and spaces
/// count as `-`), or `None`.
pub fn builtin(name: &str) -> Option<Material> {
    let key = canonical(name);
    let key = ALIASES
        .iter()
        .find(|(alias, _)| *alias == key)
        .map_or(key.as_str(), |(_, canonical)| canonical);
    Some(match key {
        "vacuum" => vacuum(),
        "air" => air(),
        "standard-air" => standard_air(),
        "n-bk7" => n_bk7(),
        "fused-silica" => fused_silica(),
        "diamond" => diamond(),
        "calcite" => calcite(),
        "quartz" => quartz(),
        "sapphire" => sapphire(),
        gem => return super::gems::gem(gem, sapphire),
    })
}
