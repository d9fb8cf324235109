//! `Material::parse` and model validation: clear errors, never panics.

use spar::material::{self, Dispersion, Material};

#[test]
fn builtin_names_case_insensitive_and_aliases() {
    for name in material::BUILTIN_NAMES {
        let m = Material::parse(name).unwrap();
        assert_eq!(m.name(), *name);
        assert_eq!(Material::parse(&name.to_uppercase()).unwrap(), m);
    }
    assert_eq!(Material::parse("BK7").unwrap().name(), "n-bk7");
    assert_eq!(Material::parse("N_BK7").unwrap().name(), "n-bk7");
    assert_eq!(Material::parse("Crystal Quartz").unwrap().name(), "quartz");
    assert_eq!(Material::parse(" Calcite ").unwrap().name(), "calcite");
}

#[test]
fn unknown_names_list_the_builtins() {
    let err = Material::parse("unobtainium").unwrap_err();
    assert!(err.contains("unobtainium"), "{err}");
    for name in material::BUILTIN_NAMES {
        assert!(err.contains(name), "{err} lacks {name}");
    }
    assert!(
        err.contains("iso:N") && err.contains("uniaxial:NO:NE"),
        "{err}"
    );
}

#[test]
fn constant_indices() {
    let glass = Material::parse("iso:1.5").unwrap();
    assert_eq!(glass.indices(400.0), (1.5, 1.5));
    assert!(!glass.is_dispersive() && !glass.is_uniaxial());
    let crystal = Material::parse("UNIAXIAL:1.6584:1.4864").unwrap();
    assert!(crystal.is_uniaxial() && !crystal.is_dispersive());
    assert_eq!(crystal.indices(700.0), (1.6584, 1.4864));
    // n_o = n_e is a legitimate (degenerate) crystal.
    assert!(Material::parse("uniaxial:1.5:1.5").is_ok());
}

#[test]
fn bad_specs_are_clear_errors() {
    let cases = [
        ("iso:", "not a number"),
        ("iso:abc", "not a number"),
        ("iso:0", "finite positive"),
        ("iso:-1.5", "finite positive"),
        ("iso:nan", "finite positive"),
        ("iso:inf", "finite positive"),
        ("uniaxial:1.6", "uniaxial:NO:NE"),
        ("uniaxial:1.6:1.5:1.4", "uniaxial:NO:NE"),
        ("uniaxial:1.6:x", "not a number"),
        ("uniaxial:1.6:-2", "finite positive"),
        ("", "unknown material"),
    ];
    for (spec, needle) in cases {
        let err = Material::parse(spec).unwrap_err();
        assert!(err.contains(needle), "{spec:?} gave {err:?}");
    }
}

#[test]
fn poles_and_bad_coefficients_are_refused() {
    // A Sellmeier pole at 500 nm (C = 0.25 µm²).
    let err = Material::isotropic("bad", Dispersion::sellmeier(1.0, &[(1.0, 0.25)])).unwrap_err();
    assert!(err.contains("pole at 500.0 nm"), "{err}");
    // The same written as a pole wavelength.
    let err =
        Material::isotropic("bad", Dispersion::sellmeier_poles(1.0, &[(1.0, 0.6)])).unwrap_err();
    assert!(err.contains("pole at 600.0 nm"), "{err}");
    // A gas term with its pole at 450 nm (C = 1/0.45² µm⁻²).
    let err = Material::isotropic(
        "bad",
        Dispersion::Gas {
            a: 0.0,
            terms: vec![(1e-3, 1.0 / 0.45_f64.powi(2))],
        },
    )
    .unwrap_err();
    assert!(err.contains("pole at 450.0 nm"), "{err}");
    // Poles outside the range are fine: 316 nm (C = 0.1 µm²), 790 nm.
    assert!(Material::isotropic("ok", Dispersion::sellmeier(1.0, &[(1.0, 0.1)])).is_ok());
    assert!(Material::isotropic("ok", Dispersion::sellmeier_poles(1.0, &[(0.01, 0.79)])).is_ok());
    // n² < 0 somewhere in range.
    let err = Material::isotropic("bad", Dispersion::sellmeier(-3.0, &[(1.0, 0.01)])).unwrap_err();
    assert!(err.contains("finite and positive"), "{err}");
    // Non-finite coefficients and a negative Cauchy index.
    assert!(Material::isotropic("bad", Dispersion::sellmeier(f64::NAN, &[])).is_err());
    assert!(Material::isotropic(
        "bad",
        Dispersion::Cauchy {
            a: -1.0,
            b: 0.0,
            c: 0.0
        }
    )
    .is_err());
    assert!(Material::isotropic("bad", Dispersion::Constant(0.0)).is_err());
    // Uniaxial errors say which index.
    let err = Material::uniaxial(
        "bad",
        Dispersion::Constant(1.5),
        Dispersion::sellmeier(1.0, &[(1.0, 0.25)]),
    )
    .unwrap_err();
    assert!(err.contains("extraordinary"), "{err}");
}

#[test]
fn constant_biaxial_materials_and_their_axes() {
    use glam::DVec3;
    use spar::optics::Medium;
    let m = Material::parse("biaxial:1.6093:1.6116:1.6194").unwrap();
    assert!(m.is_biaxial() && !m.is_uniaxial() && !m.is_dispersive());
    assert_eq!(m.principal_indices(500.0), [1.6093, 1.6116, 1.6194]);
    assert_eq!(m.indices(500.0), (1.6093, 1.6194));
    assert_eq!(m.axis(), None);
    // x is orthogonalized against z (Gram–Schmidt), as Medium::biaxial does.
    let z = DVec3::new(0.0, 1.0, 1.0);
    let x = DVec3::new(1.0, 0.0, 3.0);
    let m = m.with_crystal_axes(z, x).unwrap();
    assert_eq!(
        m.medium(550.0, DVec3::ZERO),
        Medium::biaxial([1.6093, 1.6116, 1.6194], z, x).unwrap()
    );
    // Parallel or zero axes, a one-axis orientation, bad names.
    assert!(m
        .clone()
        .with_crystal_axes(z, -2.0 * z)
        .unwrap_err()
        .contains("not parallel"));
    assert!(m.clone().with_crystal_axes(DVec3::ZERO, x).is_err());
    assert!(m.clone().with_axis(z).unwrap_err().contains("biaxial"));
    assert!(Material::parse("calcite")
        .unwrap()
        .with_crystal_axes(z, x)
        .is_err());
    for bad in [
        "biaxial:1.6:1.7",
        "biaxial:1.6:x:1.7",
        "biaxial:1.6:1.7:-1",
        "biaxial:1:2:3:4",
    ] {
        assert!(Material::parse(bad).is_err(), "{bad}");
    }
    // Three equal indices: ε = n² I, the isotropic medium.
    let eq = Material::parse("biaxial:1.7:1.7:1.7").unwrap();
    assert_eq!(eq.medium(550.0, DVec3::ZERO), Medium::Isotropic { n: 1.7 });
}
