//! The biaxial gems of the catalogue (`spar::material::gems`: topaz,
//! peridot, tanzanite, chrysoberyl, iolite) against the published constants typed
//! here from their sources (docs/materials.md, "Biaxial gems"), and the
//! optic angle 2V computed here from the indices, independently of
//! `spar::optics::anisotropic::half_optic_angle`.

use spar::material::{Material, Optics};

/// One gem's published constants at 589.3 nm.
struct Published {
    name: &'static str,
    /// n_α, n_β, n_γ as the source gives them.
    n: [f64; 3],
    /// Tolerance on each index, and why.
    tol: f64,
    /// 2V (degrees, the acute angle) and whether the optic sign is
    /// positive (Z the acute bisectrix), where the source gives them; the
    /// tolerance in degrees.
    two_v: Option<(f64, bool, f64)>,
}

const PUBLISHED: &[Published] = &[
    // Handbook of Mineralogy II (1995), topaz: the low (F-rich) end of
    // α 1.606–1.629, β 1.609–1.631, γ 1.616–1.638; biaxial (+), 2V(meas.)
    // 48°–68°, the largest for F-rich topaz. The catalogue takes the
    // indices exactly (half the last digit), 2V within 3° of 68°.
    Published {
        name: "topaz",
        n: [1.606, 1.609, 1.616],
        tol: 5e-4,
        two_v: Some((68.0, true, 3.0)),
    },
    // GIA Gem Reference Guide (1995), peridot: RI 1.654–1.690, β "near
    // halfway", biaxial "positive or negative": 2V near 90°, the sign not
    // fixed (checked as 2V_z within 2° of 90°, below).
    Published {
        name: "peridot",
        n: [1.654, 1.672, 1.690],
        tol: 5e-4,
        two_v: None,
    },
    // O'Donoghue (ed.), Gems (6th ed., 2006), tanzanite: 1.692, 1.693,
    // 1.700, biaxial (+); no 2V given (the Handbook of Mineralogy's zoisite
    // range, 0°–69°, is checked below).
    Published {
        name: "tanzanite",
        n: [1.692, 1.693, 1.700],
        tol: 5e-4,
        two_v: None,
    },
    // Arem, Color Encyclopedia of Gemstones (2nd ed., 1987), cordierite
    // from Sri Lanka: α 1.530, β 1.534, γ 1.539, biaxial (+), 2V 65°–104°
    // for the species (checked below: positive, 2V inside the range).
    Published {
        name: "iolite",
        n: [1.530, 1.534, 1.539],
        tol: 5e-4,
        two_v: None,
    },
    // Handbook of Mineralogy III (1997), chrysoberyl: α 1.745, β 1.748,
    // γ 1.754, biaxial (+), 2V(meas.) 70°. The catalogue's Walling (1980)
    // / Loiko & Major (2016) fit, measured on alexandrite laser crystals,
    // is 0.004–0.006 lower (tolerance 0.0065) and its 2V is 61°: the
    // disagreement docs/materials.md states (tolerance 10°).
    Published {
        name: "chrysoberyl",
        n: [1.745, 1.748, 1.754],
        tol: 6.5e-3,
        two_v: Some((70.0, true, 10.0)),
    },
];

/// The acute optic angle 2V (degrees) and whether the crystal is optically
/// positive, from n_α ≤ n_β ≤ n_γ: the optic axes lie in the X–Z plane at
/// ±V_z from Z with cos²V_z = n_α²(n_γ² − n_β²) / (n_β²(n_γ² − n_α²))
/// (the wave normals along which both waves have index n_β). Positive when
/// V_z < 45° (Z is the acute bisectrix).
fn optic_angle(n: [f64; 3]) -> (f64, bool) {
    let [a, b, g] = n.map(|x| x * x);
    let cos2 = a * (g - b) / (b * (g - a));
    let v_z = cos2.sqrt().acos().to_degrees();
    if v_z <= 45.0 {
        (2.0 * v_z, true)
    } else {
        (180.0 - 2.0 * v_z, false)
    }
}

fn principal(name: &str, nm: f64) -> [f64; 3] {
    let m = Material::parse(name).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        matches!(m.optics(), Optics::Biaxial { .. }),
        "{name} is biaxial"
    );
    assert!(m.absorption().is_none(), "{name} absorbs nothing");
    m.principal_indices(nm)
}

#[test]
fn biaxial_gem_indices_match_published_constants() {
    for p in PUBLISHED {
        let n = principal(p.name, 589.3);
        eprintln!(
            "{}: n_x {:.5}, n_y {:.5}, n_z {:.5}",
            p.name, n[0], n[1], n[2]
        );
        for (i, axis) in ["α (x)", "β (y)", "γ (z)"].iter().enumerate() {
            assert!(
                (n[i] - p.n[i]).abs() <= p.tol,
                "{} n_{axis}: {} vs published {} (tolerance {})",
                p.name,
                n[i],
                p.n[i],
                p.tol
            );
        }
    }
}

/// The cosine form above against the tangent form of the same angle,
/// tan²V_z = (1/n_α² − 1/n_β²) / (1/n_β² − 1/n_γ²), and a case worked by
/// hand: n 1.5, 1.6, 1.7 has cos²V_z = 2.25·0.33/(2.56·0.64) = 0.45319,
/// V_z = 47.69° (β nearer γ in 1/n²: negative, 2V = 2V_x = 84.6°).
#[test]
fn optic_angle_formula_checks() {
    let (two_v, positive) = optic_angle([1.5, 1.6, 1.7]);
    assert!(!positive);
    assert!((two_v - 84.62).abs() < 0.01, "{two_v}");
    for n in [
        [1.5, 1.6, 1.7],
        [1.606, 1.609, 1.616],
        [1.654, 1.669, 1.690],
        [1.74, 1.748, 1.75],
    ] {
        let [a, b, g] = n.map(|x: f64| 1.0 / (x * x));
        let v_z = ((a - b) / (b - g)).sqrt().atan().to_degrees();
        let want = if v_z <= 45.0 {
            2.0 * v_z
        } else {
            180.0 - 2.0 * v_z
        };
        let (two_v, positive) = optic_angle(n);
        assert!((two_v - want).abs() < 1e-9, "{n:?}: {two_v} vs {want}");
        assert_eq!(positive, v_z <= 45.0, "{n:?}");
    }
}

#[test]
fn biaxial_gem_optic_angles_match_published_values() {
    for p in PUBLISHED {
        let (two_v, positive) = optic_angle(principal(p.name, 589.3));
        eprintln!(
            "{}: 2V = {two_v:.1}°, {}",
            p.name,
            if positive { "+" } else { "−" }
        );
        if let Some((want, want_positive, tol)) = p.two_v {
            assert_eq!(positive, want_positive, "{} optic sign", p.name);
            assert!(
                (two_v - want).abs() <= tol,
                "{}: 2V {two_v:.2}° vs published {want}° (tolerance {tol}°)",
                p.name
            );
        }
    }
    // Peridot: β halfway, 2V_z within 2° of 90° (GIA: either sign).
    let n = principal("peridot", 589.3);
    let [a, b, g] = n.map(|x| x * x);
    let v_z = (a * (g - b) / (b * (g - a))).sqrt().acos().to_degrees();
    assert!(
        (2.0 * v_z - 90.0).abs() <= 2.0,
        "peridot 2V_z {}",
        2.0 * v_z
    );
    // Tanzanite: positive, 2V inside the Handbook of Mineralogy's zoisite
    // range 0°–69°.
    let (two_v, positive) = optic_angle(principal("tanzanite", 589.3));
    assert!(positive && two_v <= 69.0, "tanzanite 2V {two_v}");
    // Iolite: Arem's sign (+) and 2V range 65°–104° (2V_z; computed from
    // his specimen's indices by hand: 83.9°).
    let (two_v, positive) = optic_angle(principal("iolite", 589.3));
    assert!(
        positive && (65.0..=104.0).contains(&two_v) && (two_v - 83.9).abs() < 0.2,
        "iolite 2V {two_v}"
    );
}

/// n_α ≤ n_β ≤ n_γ at every nanometre of 380–780 nm: no crossing that
/// would swap the indicatrix axes (and with them the optic plane).
#[test]
fn biaxial_gem_indices_stay_ordered_across_the_visible() {
    for p in PUBLISHED {
        for nm in 380..=780 {
            let n = principal(p.name, nm as f64);
            assert!(
                n[0] < n[1] && n[1] < n[2],
                "{} at {nm} nm: {n:?} not increasing",
                p.name
            );
        }
    }
}

/// The dispersion n(430.8 nm) − n(686.7 nm) of each principal index: the
/// published B–G value for the gemmological Cauchy laws (topaz 0.014,
/// peridot 0.020, tanzanite 0.012, iolite 0.017: exact by construction), and for the
/// chrysoberyl fit against GIA's 0.015: the fit gives 0.0168, 0.0171 and
/// 0.0175 (tolerance 0.003, docs/materials.md).
#[test]
fn biaxial_gem_dispersion_matches_published_values() {
    for (name, bg, tol) in [
        ("topaz", 0.014, 1e-9),
        ("peridot", 0.020, 1e-9),
        ("tanzanite", 0.012, 1e-9),
        ("iolite", 0.017, 1e-9),
        ("chrysoberyl", 0.015, 3e-3),
    ] {
        let (blue, red) = (principal(name, 430.8), principal(name, 686.7));
        for i in 0..3 {
            let d = blue[i] - red[i];
            assert!(
                (d - bg).abs() <= tol,
                "{name} index {i}: B–G {d:.5} vs {bg}"
            );
        }
    }
}
