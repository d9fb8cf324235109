//! Materials: dispersion models and the catalogue of built-in media.
//!
//! A [`Material`] is isotropic (one index) or uniaxial (ordinary and
//! extraordinary indices and an optic axis, +z unless set), each index a
//! [`Dispersion`] of wavelength. At one wavelength it becomes an
//! [`optics::Medium`](crate::optics::Medium), what the interface solver sees.

pub mod absorption;
pub mod catalog;
pub mod dispersion;
pub mod gems;

pub use absorption::{Absorption, Curve};
pub use catalog::{builtin, BUILTIN_NAMES};
pub use dispersion::Dispersion;

use crate::optics::Medium;
use glam::DVec3;

/// The optical description of a material, apart from its name.
#[derive(Clone, Debug, PartialEq)]
pub enum Optics {
    /// One refractive index.
    Isotropic { n: Dispersion },
    /// A uniaxial crystal: ordinary and extraordinary indices and the optic
    /// axis (a unit vector in the object's frame).
    Uniaxial {
        n_o: Dispersion,
        n_e: Dispersion,
        axis: DVec3,
    },
}

/// A named medium whose indices depend on wavelength.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    name: String,
    optics: Optics,
    /// What the medium absorbs (`None`: nothing, the colourless case).
    absorption: Option<Absorption>,
}

impl Material {
    /// An isotropic material; fails when the model is not usable over
    /// 380–780 nm (see [`Dispersion::validate`]).
    pub fn isotropic(name: impl Into<String>, n: Dispersion) -> Result<Self, String> {
        let name = name.into();
        n.validate().map_err(|e| format!("{name}: {e}"))?;
        Ok(Material {
            name,
            optics: Optics::Isotropic { n },
            absorption: None,
        })
    }

    /// A uniaxial material with its optic axis along +z; fails when either
    /// model is not usable over 380–780 nm.
    pub fn uniaxial(
        name: impl Into<String>,
        n_o: Dispersion,
        n_e: Dispersion,
    ) -> Result<Self, String> {
        let name = name.into();
        n_o.validate()
            .map_err(|e| format!("{name}: ordinary index: {e}"))?;
        n_e.validate()
            .map_err(|e| format!("{name}: extraordinary index: {e}"))?;
        Ok(Material {
            name,
            optics: Optics::Uniaxial {
                n_o,
                n_e,
                axis: DVec3::Z,
            },
            absorption: None,
        })
    }

    /// The same material with its optic axis along `axis` (normalised).
    /// Fails for a zero or non-finite axis, and for an isotropic material.
    pub fn with_axis(mut self, axis: DVec3) -> Result<Self, String> {
        let unit = unit_axis(axis).ok_or_else(|| {
            format!(
                "{}: optic axis {axis} is not a finite non-zero vector",
                self.name
            )
        })?;
        match &mut self.optics {
            Optics::Uniaxial { axis, .. } => *axis = unit,
            Optics::Isotropic { .. } => {
                return Err(format!(
                    "{} is isotropic: it has no optic axis to set",
                    self.name
                ))
            }
        }
        Ok(self)
    }

    /// Parses a material: a built-in name (case-insensitive: see
    /// [`BUILTIN_NAMES`]), `iso:N` (constant index N) or `uniaxial:NO:NE`
    /// (constant ordinary and extraordinary indices, axis +z).
    pub fn parse(spec: &str) -> Result<Material, String> {
        let spec = spec.trim();
        let index = |s: &str, what: &str| -> Result<f64, String> {
            let n: f64 = s
                .trim()
                .parse()
                .map_err(|_| format!("`{s}` is not a number ({what} in `{spec}`)"))?;
            if n.is_finite() && n > 0.0 {
                Ok(n)
            } else {
                Err(format!(
                    "{what} {n} in `{spec}` must be a finite positive number"
                ))
            }
        };
        let lower = spec.to_ascii_lowercase();
        if let Some(rest) = lower.strip_prefix("iso:") {
            let n = index(rest, "the refractive index")?;
            return Material::isotropic(spec, Dispersion::Constant(n));
        }
        if let Some(rest) = lower.strip_prefix("uniaxial:") {
            let parts: Vec<&str> = rest.split(':').collect();
            if parts.len() != 2 {
                return Err(format!(
                    "`{spec}`: a constant uniaxial material is `uniaxial:NO:NE`, \
                     e.g. `uniaxial:1.6584:1.4864`"
                ));
            }
            let n_o = index(parts[0], "the ordinary index")?;
            let n_e = index(parts[1], "the extraordinary index")?;
            return Material::uniaxial(spec, Dispersion::Constant(n_o), Dispersion::Constant(n_e));
        }
        builtin(spec).ok_or_else(|| {
            format!(
                "unknown material `{spec}`: use one of {}, or `iso:N`, or `uniaxial:NO:NE`",
                catalog::known_names().join(", ")
            )
        })
    }

    /// The same material absorbing as `absorption` says (`None`, or
    /// curves that are zero everywhere: colourless). Fails for an invalid
    /// curve, and for an isotropic material whose `o` and `e` curves
    /// differ.
    pub fn with_absorption(mut self, absorption: Option<Absorption>) -> Result<Self, String> {
        if let Some(a) = &absorption {
            a.validate()
                .map_err(|e| format!("{}: absorption: {e}", self.name))?;
            if !self.is_uniaxial() && a.o != a.e {
                return Err(format!(
                    "{} is isotropic: it has one absorption coefficient, not an ordinary and an \
                     extraordinary one",
                    self.name
                ));
            }
        }
        self.absorption = absorption.filter(|a| !a.is_zero());
        Ok(self)
    }

    /// The same material under another name.
    pub fn renamed(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// What the medium absorbs, `None` when it absorbs nothing.
    pub fn absorption(&self) -> Option<&Absorption> {
        self.absorption.as_ref()
    }

    /// The material's name (the built-in name, or the text it was parsed
    /// from).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its optical description.
    pub fn optics(&self) -> &Optics {
        &self.optics
    }

    /// True for a uniaxial crystal.
    pub fn is_uniaxial(&self) -> bool {
        matches!(self.optics, Optics::Uniaxial { .. })
    }

    /// True when an index depends on wavelength (constant indices do not).
    pub fn is_dispersive(&self) -> bool {
        match &self.optics {
            Optics::Isotropic { n } => !n.is_constant(),
            Optics::Uniaxial { n_o, n_e, .. } => !(n_o.is_constant() && n_e.is_constant()),
        }
    }

    /// The optic axis of a uniaxial material (in the object's frame), `None`
    /// for an isotropic one.
    pub fn axis(&self) -> Option<DVec3> {
        match self.optics {
            Optics::Uniaxial { axis, .. } => Some(axis),
            Optics::Isotropic { .. } => None,
        }
    }

    /// The indices at `lambda_nm`: `(n, n)` for an isotropic material,
    /// `(n_o, n_e)` for a uniaxial one.
    pub fn indices(&self, lambda_nm: f64) -> (f64, f64) {
        match &self.optics {
            Optics::Isotropic { n } => {
                let n = n.n(lambda_nm);
                (n, n)
            }
            Optics::Uniaxial { n_o, n_e, .. } => (n_o.n(lambda_nm), n_e.n(lambda_nm)),
        }
    }

    /// The medium at `lambda_nm`, with the optic axis `axis` (the object's
    /// axis in the frame of the interface, normalised here; a zero or
    /// non-finite `axis` falls back to the material's own axis). Isotropic
    /// materials ignore `axis`.
    pub fn medium(&self, lambda_nm: f64, axis: DVec3) -> Medium {
        match &self.optics {
            Optics::Isotropic { n } => Medium::Isotropic { n: n.n(lambda_nm) },
            Optics::Uniaxial {
                n_o,
                n_e,
                axis: own,
            } => Medium::Uniaxial {
                n_o: n_o.n(lambda_nm),
                n_e: n_e.n(lambda_nm),
                axis: unit_axis(axis).unwrap_or(*own),
            },
        }
    }
}

fn unit_axis(axis: DVec3) -> Option<DVec3> {
    let len = axis.length();
    (len.is_finite() && len > 0.0).then(|| axis / len)
}
