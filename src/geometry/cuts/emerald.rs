//! The emerald cut: a rectangular step cut with cut corners.
//!
//! The outline is a rectangle, `ratio` × `width` with its length along +Y,
//! whose corners are cut at 45° with legs `corner` × width (`corner = 0`:
//! a plain rectangle). Crown and pavilion are rings of steps that follow
//! the outline: every facet of a ring has the same angle and starts from the
//! outline inset by the same distance, so each horizontal section of a ring
//! is the outline offset inward. Crown rings share the inset from the
//! girdle to the table equally; pavilion rings share the inset from the
//! girdle to the keel (half the width) equally; each ring is `angle_step`
//! shallower than the one outside it.
//!
//! Facets: table 1; per crown or pavilion ring 4 sides + 4 corners (a
//! corner facet is left out of rings that start where the inset outline has
//! already lost its cut corner); girdle band 8 (4 without corners). With the
//! defaults (3 + 3 rings, corners kept in all but the innermost pavilion
//! ring): 1 + 24 + 8 + 20 = 53 facets.

use super::super::convex::HalfSpace;
use super::{check, horizontal, named, tilted, NamedPlane};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Proportions of an emerald cut (fractions of the width, degrees).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct Emerald {
    /// Width of the girdle outline, in scene units. Default 1.
    pub width: f64,
    /// Length over width. Default 1.4.
    pub ratio: f64,
    /// Leg of each 45° corner cut over the width; 0 for square corners.
    /// Default 0.15.
    pub corner: f64,
    /// Table width over the width. Default 0.6.
    pub table: f64,
    /// Angle of the outer crown ring. Default 40°.
    pub crown_angle: f64,
    /// Angle of the outer pavilion ring. Default 50°.
    pub pavilion_angle: f64,
    /// Girdle thickness over the width. Default 0.02.
    pub girdle: f64,
    /// Crown rings. Default 3.
    pub crown_steps: u32,
    /// Pavilion rings. Default 3.
    pub pavilion_steps: u32,
    /// How much shallower each inner ring is. Default 6°.
    pub angle_step: f64,
}

impl Default for Emerald {
    fn default() -> Emerald {
        Emerald {
            width: 1.0,
            ratio: 1.4,
            corner: 0.15,
            table: 0.6,
            crown_angle: 40.0,
            pavilion_angle: 50.0,
            girdle: 0.02,
            crown_steps: 3,
            pavilion_steps: 3,
            angle_step: 6.0,
        }
    }
}

/// Azimuths of the outline's sides and corners, clockwise from +Y, and
/// whether each is a corner.
const DIRECTIONS: [(f64, bool); 8] = [
    (0.0, false),
    (45.0, true),
    (90.0, false),
    (135.0, true),
    (180.0, false),
    (225.0, true),
    (270.0, false),
    (315.0, true),
];

impl Emerald {
    fn validate(&self) -> Result<(), String> {
        check("width", self.width, 0.0, f64::INFINITY, false)?;
        check("ratio", self.ratio, 1.0, 100.0, true)?;
        check("corner", self.corner, 0.0, 0.25, true)?;
        check("table", self.table, 0.0, 1.0, false)?;
        check("crown_angle", self.crown_angle, 0.0, 90.0, false)?;
        check("pavilion_angle", self.pavilion_angle, 0.0, 90.0, false)?;
        check("girdle", self.girdle, 0.0, 0.5, true)?;
        check("angle_step", self.angle_step, 0.0, 90.0, true)?;
        for (name, n) in [
            ("crown_steps", self.crown_steps),
            ("pavilion_steps", self.pavilion_steps),
        ] {
            if !(1..=20).contains(&n) {
                return Err(format!("{name} = {n} must be between 1 and 20"));
            }
        }
        let innermost = |outer: f64, n: u32| outer - (n - 1) as f64 * self.angle_step;
        if innermost(self.crown_angle, self.crown_steps) <= 0.0
            || innermost(self.pavilion_angle, self.pavilion_steps) <= 0.0
        {
            return Err(format!(
                "angle_step = {} leaves the innermost crown or pavilion ring at or below 0°",
                self.angle_step
            ));
        }
        Ok(())
    }

    /// Distance of the outline's side or corner at `azimuth` from the axis.
    fn apothem(&self, azimuth: f64) -> f64 {
        let (w, l) = (self.width, self.width * self.ratio);
        match azimuth as i32 {
            0 | 180 => l / 2.0,
            90 | 270 => w / 2.0,
            // The corner cut through (w/2, l/2 − c) and (w/2 − c, l/2).
            _ => (w / 2.0 + l / 2.0 - self.corner * w) / std::f64::consts::SQRT_2,
        }
    }

    /// True if the outline inset by `inset` still has its cut corners: each
    /// corner edge (length √2·corner·width) shortens by 2 tan 22.5° per unit
    /// of inset.
    fn has_corners(&self, inset: f64) -> bool {
        let edge = std::f64::consts::SQRT_2 * self.corner * self.width;
        edge - 2.0 * inset * 22.5f64.to_radians().tan() > 1e-6 * self.width
    }

    /// One ring of steps: `sign` +1 for the crown, −1 for the pavilion.
    fn ring(&self, out: &mut Vec<NamedPlane>, tier: &str, angle: f64, inset: f64, z: f64) {
        for (d, &(az, corner)) in DIRECTIONS.iter().enumerate() {
            if corner && !self.has_corners(inset) {
                continue;
            }
            let foot = horizontal(az) * (self.apothem(az) - inset) + DVec3::Z * z;
            out.push(named(tilted(az, angle, foot), format!("{tier}-{}", d + 1)));
        }
    }

    /// The facet planes.
    pub fn planes(&self) -> Result<Vec<NamedPlane>, String> {
        self.validate()?;
        let half_g = self.girdle * self.width / 2.0;
        let mut crown = Vec::new();
        let kc = self.crown_steps as usize;
        let step_c = self.width / 2.0 * (1.0 - self.table) / kc as f64;
        let mut z = half_g;
        for i in 0..kc {
            let angle = self.crown_angle - i as f64 * self.angle_step;
            self.ring(
                &mut crown,
                &format!("crown{}", i + 1),
                angle,
                i as f64 * step_c,
                z,
            );
            z += step_c * angle.to_radians().tan();
        }
        let mut planes = vec![named(HalfSpace::new(DVec3::Z, z), "table")];
        planes.extend(crown);
        if self.girdle > 0.0 {
            for (d, &(az, corner)) in DIRECTIONS.iter().enumerate() {
                if corner && self.corner == 0.0 {
                    continue;
                }
                planes.push(named(
                    HalfSpace::new(horizontal(az), self.apothem(az)),
                    format!("girdle-{}", d + 1),
                ));
            }
        }
        let kp = self.pavilion_steps as usize;
        let step_p = self.width / 2.0 / kp as f64;
        let mut z = -half_g;
        for j in 0..kp {
            let angle = self.pavilion_angle - j as f64 * self.angle_step;
            self.ring(
                &mut planes,
                &format!("pavilion{}", j + 1),
                -angle,
                j as f64 * step_p,
                z,
            );
            z -= step_p * angle.to_radians().tan();
        }
        Ok(planes)
    }
}
