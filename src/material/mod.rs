//! Materials: dispersion models and the catalogue of built-in media.
//!
//! A [`Material`] is isotropic (one index), uniaxial (ordinary and
//! extraordinary indices and an optic axis, +z unless set) or biaxial
//! (principal indices along the crystal axes x, y, z; crystal z and x along
//! +z and +x unless set), each index a [`Dispersion`] of wavelength. At one wavelength it becomes an
//! [`optics::Medium`](crate::optics::Medium), what the interface solver sees.

pub mod absorption;
pub mod catalog;
pub mod dispersion;
pub mod gems;
pub mod measured;

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
    /// A biaxial crystal: principal indices `n = [n_x, n_y, n_z]` along the
    /// crystal axes x, y = z × x and z, with the crystal's `z` and `x` unit
    /// and orthogonal (in the object's frame).
    Biaxial {
        n: [Dispersion; 3],
        z: DVec3,
        x: DVec3,
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

    /// A biaxial material with principal indices `n_x`, `n_y`, `n_z` along
    /// the crystal axes, crystal z along +z and x along +x; fails when a
    /// model is not usable over 380–780 nm.
    pub fn biaxial(
        name: impl Into<String>,
        n_x: Dispersion,
        n_y: Dispersion,
        n_z: Dispersion,
    ) -> Result<Self, String> {
        let name = name.into();
        for (d, axis) in [(&n_x, "x"), (&n_y, "y"), (&n_z, "z")] {
            d.validate()
                .map_err(|e| format!("{name}: index along crystal {axis}: {e}"))?;
        }
        Ok(Material {
            name,
            optics: Optics::Biaxial {
                n: [n_x, n_y, n_z],
                z: DVec3::Z,
                x: DVec3::X,
            },
            absorption: None,
        })
    }

    /// The same biaxial material with its crystal z along `z` and its crystal
    /// x along the part of `x` orthogonal to `z` (both normalised). Fails
    /// for a zero or non-finite vector, for `x` parallel to `z`, and for a
    /// material that is not biaxial.
    pub fn with_crystal_axes(mut self, z: DVec3, x: DVec3) -> Result<Self, String> {
        let Optics::Biaxial {
            z: own_z, x: own_x, ..
        } = &mut self.optics
        else {
            return Err(format!(
                "{} is not a biaxial crystal: it has no crystal axes to set",
                self.name
            ));
        };
        let (z, x) = crate::optics::medium::orthonormal_axes(z, x).ok_or_else(|| {
            format!(
                "{}: crystal axes z = {z} and x = {x} must be finite, non-zero and not parallel",
                self.name
            )
        })?;
        *own_z = z;
        *own_x = x;
        Ok(self)
    }

    /// The crystal axes `(z, x)` of a biaxial material, `None` otherwise.
    pub fn crystal_axes(&self) -> Option<(DVec3, DVec3)> {
        match self.optics {
            Optics::Biaxial { z, x, .. } => Some((z, x)),
            _ => None,
        }
    }

    /// The same material with its optic axis along `axis` (normalised).
    /// Fails for a zero or non-finite axis, and for an isotropic or biaxial
    /// material (a biaxial crystal's axes are set by
    /// [`Material::with_crystal_axes`]).
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
            Optics::Biaxial { .. } => {
                return Err(format!(
                    "{} is biaxial: set its crystal axes (z and x), not one optic axis",
                    self.name
                ))
            }
        }
        Ok(self)
    }

    /// Parses a material: a built-in name (case-insensitive: see
    /// [`BUILTIN_NAMES`]), `iso:N` (constant index N), `uniaxial:NO:NE`
    /// (constant ordinary and extraordinary indices, axis +z) or
    /// `biaxial:NX:NY:NZ` (constant principal indices, crystal axes +x, +z).
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
        if let Some(rest) = lower.strip_prefix("biaxial:") {
            let parts: Vec<&str> = rest.split(':').collect();
            if parts.len() != 3 {
                return Err(format!(
                    "`{spec}`: a constant biaxial material is `biaxial:NX:NY:NZ` (principal \
                     indices along crystal x, y, z), e.g. `biaxial:1.609:1.612:1.619`"
                ));
            }
            let n_x = index(parts[0], "the index along crystal x")?;
            let n_y = index(parts[1], "the index along crystal y")?;
            let n_z = index(parts[2], "the index along crystal z")?;
            return Material::biaxial(
                spec,
                Dispersion::Constant(n_x),
                Dispersion::Constant(n_y),
                Dispersion::Constant(n_z),
            );
        }
        builtin(spec).ok_or_else(|| {
            format!(
                "unknown material `{spec}`: use one of {}, or `iso:N`, `uniaxial:NO:NE` or \
                 `biaxial:NX:NY:NZ`",
                catalog::known_names().join(", ")
            )
        })
    }

    /// The same material absorbing as `absorption` says (`None`, or
    /// curves that are zero everywhere: colourless). Fails for an invalid
    /// curve, for an isotropic material whose `o` and `e` curves differ,
    /// and for any absorption on a biaxial material (not modelled: biaxial
    /// media are lossless, docs/materials.md).
    pub fn with_absorption(mut self, absorption: Option<Absorption>) -> Result<Self, String> {
        if let Some(a) = &absorption {
            if self.is_biaxial() && !a.is_zero() {
                return Err(format!(
                    "{} is biaxial: absorption in biaxial crystals is not modelled (they are \
                     treated as lossless)",
                    self.name
                ));
            }
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

    /// True for a biaxial crystal.
    pub fn is_biaxial(&self) -> bool {
        matches!(self.optics, Optics::Biaxial { .. })
    }

    /// True when an index depends on wavelength (constant indices do not).
    pub fn is_dispersive(&self) -> bool {
        match &self.optics {
            Optics::Isotropic { n } => !n.is_constant(),
            Optics::Uniaxial { n_o, n_e, .. } => !(n_o.is_constant() && n_e.is_constant()),
            Optics::Biaxial { n, .. } => !n.iter().all(Dispersion::is_constant),
        }
    }

    /// The optic axis of a uniaxial material (in the object's frame), `None`
    /// for an isotropic or biaxial one (a biaxial crystal has two optic axes
    /// that move with wavelength: see [`Material::crystal_axes`]).
    pub fn axis(&self) -> Option<DVec3> {
        match self.optics {
            Optics::Uniaxial { axis, .. } => Some(axis),
            Optics::Isotropic { .. } | Optics::Biaxial { .. } => None,
        }
    }

    /// The indices at `lambda_nm`: `(n, n)` for an isotropic material,
    /// `(n_o, n_e)` for a uniaxial one, the smallest and largest principal
    /// index for a biaxial one (see [`Material::principal_indices`]).
    pub fn indices(&self, lambda_nm: f64) -> (f64, f64) {
        match &self.optics {
            Optics::Isotropic { n } => {
                let n = n.n(lambda_nm);
                (n, n)
            }
            Optics::Uniaxial { n_o, n_e, .. } => (n_o.n(lambda_nm), n_e.n(lambda_nm)),
            Optics::Biaxial { .. } => {
                let n = self.principal_indices(lambda_nm);
                (n[0].min(n[1]).min(n[2]), n[0].max(n[1]).max(n[2]))
            }
        }
    }

    /// The principal indices at `lambda_nm` along crystal x, y, z: `[n; 3]`
    /// for an isotropic material, `[n_o, n_o, n_e]` (axis as z) for a
    /// uniaxial one.
    pub fn principal_indices(&self, lambda_nm: f64) -> [f64; 3] {
        match &self.optics {
            Optics::Isotropic { n } => [n.n(lambda_nm); 3],
            Optics::Uniaxial { n_o, n_e, .. } => {
                let o = n_o.n(lambda_nm);
                [o, o, n_e.n(lambda_nm)]
            }
            Optics::Biaxial { n, .. } => [n[0].n(lambda_nm), n[1].n(lambda_nm), n[2].n(lambda_nm)],
        }
    }

    /// The medium at `lambda_nm`, with the optic axis `axis` (the object's
    /// axis in the frame of the interface, normalised here; a zero or
    /// non-finite `axis` falls back to the material's own axis). Isotropic
    /// and biaxial materials ignore `axis`: a biaxial one is
    /// [`Medium::Biaxial`] on its own crystal axes, or
    /// [`Medium::Isotropic`] at a wavelength where its three indices are
    /// equal.
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
            // ε = Σ n_i² a_i a_iᵀ (docs/physics.md §4.8); axes are orthonormal by
            // construction (`with_crystal_axes`). Three equal indices make
            // ε = n² I exactly: the isotropic medium. The interface solver
            // handles equal and nearly equal indices (optics::near_isotropic),
            // but the renderer chains a biaxial ray's wave by its name, and
            // where fast and slow are degenerate their fields are a choice
            // of basis that differs from node to node (docs/physics.md §4.8).
            Optics::Biaxial { n, z, x } => {
                let n = [n[0].n(lambda_nm), n[1].n(lambda_nm), n[2].n(lambda_nm)];
                if n[0] == n[1] && n[1] == n[2] {
                    Medium::Isotropic { n: n[0] }
                } else {
                    Medium::Biaxial { n, x: *x, z: *z }
                }
            }
        }
    }
}

fn unit_axis(axis: DVec3) -> Option<DVec3> {
    let len = axis.length();
    (len.is_finite() && len > 0.0).then(|| axis / len)
}
