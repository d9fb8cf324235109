//! The gem catalogue (`spar::material::gems`) against published
//! gemmological constants, and the absorption model
//! (`spar::material::absorption`) against independent computations.

use spar::material::absorption::{extraordinary_weights, Absorption, Curve};
use spar::material::{self, Material};

fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: {actual} vs {expected} (tolerance {tol})"
    );
}

/// Indices at the sodium D line against the GIA Gem Reference Guide
/// (1995) and handbook values (ω, ε; equal for a cubic stone). The
/// tolerance is the spread of the published values or half their last
/// digit.
#[test]
fn gem_indices_match_published_constants() {
    let cases: &[(&str, f64, f64, f64)] = &[
        ("spinel", 1.718, 1.718, 3e-3),
        ("moissanite", 2.648, 2.691, 3e-3),
        ("rutile", 2.616, 2.903, 7e-3),
        ("cubic-zirconia", 2.16, 2.16, 0.02),
        ("yag", 1.833, 1.833, 1e-3),
        ("mgf2", 1.378, 1.390, 1e-3),
        ("fluorite", 1.434, 1.434, 5e-4),
        ("zincite", 2.013, 2.029, 0.012),
        ("scheelite", 1.9195, 1.9365, 2e-3),
        ("bromellite", 1.719, 1.733, 2e-3),
        ("zircon", 1.925, 1.984, 5e-4),
        ("tourmaline", 1.644, 1.624, 5e-4),
        ("emerald", 1.580, 1.574, 5e-4),
        ("aquamarine", 1.580, 1.574, 5e-4),
        ("ruby", 1.768, 1.760, 5e-4),
        ("blue-sapphire", 1.768, 1.760, 5e-4),
    ];
    for &(name, w, e, tol) in cases {
        let m = Material::parse(name).unwrap_or_else(|e| panic!("{e}"));
        let (n_o, n_e) = m.indices(589.3);
        eprintln!("{name}: n_o {n_o:.4}, n_e {n_e:.4}");
        assert_close(n_o, w, tol, &format!("{name} ω"));
        assert_close(n_e, e, tol, &format!("{name} ε"));
    }
}

/// Dispersion, n(430.8 nm) − n(686.7 nm) (the B–G interval), against the
/// GIA Gem Reference Guide's values: it is what makes fire.
#[test]
fn gem_dispersion_matches_published_constants() {
    let cases: &[(&str, f64, f64)] = &[
        ("moissanite", 0.104, 0.01),
        ("cubic-zirconia", 0.060, 0.006),
        ("yag", 0.028, 0.003),
        ("spinel", 0.020, 0.002),
        ("fluorite", 0.007, 0.001),
        ("zircon", 0.039, 1e-9),
        ("tourmaline", 0.017, 1e-9),
        ("emerald", 0.014, 1e-9),
    ];
    for &(name, bg, tol) in cases {
        let m = Material::parse(name).unwrap();
        let d = m.indices(430.8).0 - m.indices(686.7).0;
        eprintln!("{name}: B–G dispersion {d:.4}");
        assert_close(d, bg, tol, &format!("{name} dispersion"));
    }
}

#[test]
fn at_least_twenty_gem_materials_and_unknown_names_list_them() {
    let gems: Vec<&str> = material::catalog::known_names()
        .into_iter()
        .filter(|n| !["vacuum", "air", "standard-air", "n-bk7", "fused-silica"].contains(n))
        .collect();
    assert!(gems.len() >= 20, "{} gem materials: {gems:?}", gems.len());
    for name in &gems {
        Material::parse(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    let err = Material::parse("kryptonite").unwrap_err();
    for name in material::catalog::known_names() {
        assert!(err.contains(name), "{err} lacks {name}");
    }
}

#[test]
fn coloured_gems_absorb_and_colourless_ones_do_not() {
    for name in ["ruby", "blue-sapphire", "emerald", "aquamarine"] {
        let m = Material::parse(name).unwrap();
        let a = m.absorption().unwrap_or_else(|| panic!("{name} absorbs"));
        assert!(a.validate().is_ok());
        assert_ne!(a.o, a.e, "{name} is dichroic");
    }
    for name in ["corundum", "sapphire", "diamond", "spinel", "zircon"] {
        assert!(
            Material::parse(name).unwrap().absorption().is_none(),
            "{name}"
        );
    }
}

/// Ruby's cited pleochroism (McClure 1962): the U band is stronger and
/// further to the red for E ⊥ c, so the o wave loses more yellow-green
/// (its colour purplish red) and the e wave more green-blue (orangy red).
#[test]
fn ruby_o_absorbs_more_yellow_than_e() {
    let ruby = Material::parse("ruby").unwrap();
    let a = ruby.absorption().unwrap();
    assert!(a.o.per_mm(580.0) > 1.5 * a.e.per_mm(580.0));
    assert!(
        a.o.per_mm(690.0) < 0.2 && a.e.per_mm(690.0) < 0.2,
        "red passes"
    );
}

/// The extraordinary ray's absorption per unit length against the complex
/// index of its wave normal, computed here with complex arithmetic:
/// 1/ñ² = cos²θ/ñ_o² + sin²θ/ñ_e² with ñ = n + iκ, α_normal = 2 k₀ Im ñ,
/// along the ray α_normal cos ρ (ρ the walk-off, tan θ_ray =
/// (n_o²/n_e²) tan θ). Calcite's strong birefringence tests the index
/// weights hardest.
#[test]
fn extraordinary_weights_match_the_complex_index() {
    use num_complex::Complex64 as C;
    for (n_o, n_e) in [(1.6584, 1.4864), (1.768, 1.760), (1.925, 1.984)] {
        let (k_o, k_e) = (3e-7, 1e-7);
        for theta in [0.0, 0.3, 0.8, 1.2, std::f64::consts::FRAC_PI_2] {
            let (c2, s2) = (f64::cos(theta).powi(2), f64::sin(theta).powi(2));
            let inv = C::new(c2, 0.0) / (C::new(n_o, k_o) * C::new(n_o, k_o))
                + C::new(s2, 0.0) / (C::new(n_e, k_e) * C::new(n_e, k_e));
            let n = (C::new(1.0, 0.0) / inv).sqrt();
            let theta_ray = (n_o * n_o / (n_e * n_e) * theta.tan()).atan();
            let theta_ray = if theta == std::f64::consts::FRAC_PI_2 {
                theta
            } else {
                theta_ray
            };
            let rho = theta_ray - theta;
            let k0 = 1.0; // α in units of k₀: α_x = 2 κ_x
            let want = 2.0 * k0 * n.im * rho.cos();
            let (w_o, w_e) = extraordinary_weights(n_o, n_e, theta_ray.cos());
            let got = w_o * 2.0 * k_o + w_e * 2.0 * k_e;
            assert!(
                (got / want - 1.0).abs() < 1e-6,
                "n_o {n_o}, n_e {n_e}, θ {theta}: {got} against {want}"
            );
        }
    }
}

#[test]
fn curves_interpolate_and_bands_have_their_stated_width() {
    let table = Curve::Table {
        nm: vec![380.0, 500.0, 780.0],
        per_mm: vec![1.0, 0.4, 0.0],
    };
    assert_close(table.per_mm(440.0), 0.7, 1e-12, "midway");
    assert_close(table.per_mm(640.0), 0.2, 1e-12, "midway");
    // A band is its peak at its centre and half of it FWHM/2 away in
    // photon energy (E = hc/λ, hc = 1239.84198 eV nm).
    let band = Curve::Bands {
        floor: 0.05,
        bands: vec![(550.0, 0.4, 2.0)],
    };
    let e0 = 1239.84198 / 550.0;
    assert_close(band.per_mm(550.0), 2.05, 1e-12, "peak");
    for e in [e0 - 0.2, e0 + 0.2] {
        assert_close(band.per_mm(1239.84198 / e), 1.05, 1e-9, "half maximum");
    }
}

#[test]
fn bad_curves_are_refused_with_the_reason() {
    let cases = [
        (Curve::Constant(-0.1), "≥ 0"),
        (Curve::Constant(f64::NAN), "finite"),
        (
            Curve::Table {
                nm: vec![400.0, 780.0],
                per_mm: vec![1.0, 1.0],
            },
            "cover",
        ),
        (
            Curve::Table {
                nm: vec![380.0, 380.0, 780.0],
                per_mm: vec![1.0, 1.0, 1.0],
            },
            "increase",
        ),
        (
            Curve::Table {
                nm: vec![380.0, 780.0],
                per_mm: vec![1.0],
            },
            "values",
        ),
    ];
    for (curve, why) in cases {
        let err = curve.validate().unwrap_err();
        assert!(err.contains(why), "{curve:?}: {err}");
    }
    // An isotropic medium has one coefficient.
    let glass = Material::parse("n-bk7").unwrap();
    let two = Absorption {
        o: Curve::Constant(0.1),
        e: Curve::Constant(0.2),
    };
    assert!(glass.with_absorption(Some(two)).is_err());
}
