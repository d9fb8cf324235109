//! The princess: a square modified brilliant with a chevron pavilion.
//!
//! Facets: table 1; crown `crown_steps` rings of 4 (a step crown, each
//! ring `angle_step` shallower than the one outside it); girdle band 4
//! (when `girdle > 0`); pavilion 4 mains plus `chevrons − 1` tiers of 8
//! chevron facets. Defaults: 1 + 8 + 4 + 4 + 16 = 33 facets.
//!
//! Pavilion construction (W = width, girdle thickness g): on each side's
//! centre line the pavilion profile runs from the girdle (radius W/2) to the
//! point on the axis in `chevrons` equal radial steps, the outer one at
//! `pavilion_angle`, each further one `angle_step` shallower, through
//! profile points P₀ (on the girdle), P₁, …, P_m (the point). The side's
//! main facet is the plane of its girdle edge and P₁; chevron tier j is the
//! pair of planes through P_{j−1}, P_j and one of the side's two girdle
//! corners. Seen from below, the chevrons are the nested V's between a
//! side's main facet and the point.

use super::super::convex::HalfSpace;
use super::{check, horizontal, named, through, tilted, NamedPlane};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Proportions of a princess (fractions of the width, degrees).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct Princess {
    /// Side of the square girdle, in scene units. Default 1.
    pub width: f64,
    /// Side of the square table over the width. Default 0.70.
    pub table: f64,
    /// Angle of the outer crown ring. Default 35°.
    pub crown_angle: f64,
    /// Angle of the pavilion mains (across the sides). Default 50°.
    pub pavilion_angle: f64,
    /// Girdle thickness over the width. Default 0.02.
    pub girdle: f64,
    /// Rings of the step crown. Default 2.
    pub crown_steps: u32,
    /// Pavilion tiers: the mains, then chevron pairs. Default 3.
    pub chevrons: u32,
    /// How much shallower each inner crown ring or chevron tier is.
    /// Default 5°.
    pub angle_step: f64,
}

impl Default for Princess {
    fn default() -> Princess {
        Princess {
            width: 1.0,
            table: 0.70,
            crown_angle: 35.0,
            pavilion_angle: 50.0,
            girdle: 0.02,
            crown_steps: 2,
            chevrons: 3,
            angle_step: 5.0,
        }
    }
}

impl Princess {
    fn validate(&self) -> Result<(), String> {
        check("width", self.width, 0.0, f64::INFINITY, false)?;
        check("table", self.table, 0.0, 1.0, false)?;
        check("crown_angle", self.crown_angle, 0.0, 90.0, false)?;
        check("pavilion_angle", self.pavilion_angle, 0.0, 90.0, false)?;
        check("girdle", self.girdle, 0.0, 0.5, true)?;
        check("angle_step", self.angle_step, 0.0, 90.0, true)?;
        for (name, n) in [
            ("crown_steps", self.crown_steps),
            ("chevrons", self.chevrons),
        ] {
            if !(1..=20).contains(&n) {
                return Err(format!("{name} = {n} must be between 1 and 20"));
            }
        }
        let innermost = |outer: f64, n: u32| outer - (n - 1) as f64 * self.angle_step;
        if innermost(self.crown_angle, self.crown_steps) <= 0.0
            || innermost(self.pavilion_angle, self.chevrons) <= 0.0
        {
            return Err(format!(
                "angle_step = {} leaves the innermost crown ring or chevron tier at or below 0°",
                self.angle_step
            ));
        }
        Ok(())
    }

    /// Heights of the pavilion profile points P₀…P_m below the girdle's
    /// bottom (non-negative depths) and the radial step.
    fn profile(&self) -> (Vec<f64>, f64) {
        let m = self.chevrons as usize;
        let step = self.width / 2.0 / m as f64;
        let mut depth = vec![0.0];
        for j in 0..m {
            let angle = self.pavilion_angle - j as f64 * self.angle_step;
            depth.push(depth[j] + step * angle.to_radians().tan());
        }
        (depth, step)
    }

    /// The facet planes.
    pub fn planes(&self) -> Result<Vec<NamedPlane>, String> {
        self.validate()?;
        let w = self.width;
        let half_g = self.girdle * w / 2.0;
        let sides = [0.0, 90.0, 180.0, 270.0];
        let mut planes = Vec::new();

        // Crown: rings of equal radial width from the girdle to the table.
        let k = self.crown_steps as usize;
        let ring = w / 2.0 * (1.0 - self.table) / k as f64;
        let mut z = half_g;
        let mut crown = Vec::new();
        for i in 0..k {
            let angle = self.crown_angle - i as f64 * self.angle_step;
            for (s, &az) in sides.iter().enumerate() {
                let foot = horizontal(az) * (w / 2.0 - i as f64 * ring) + DVec3::Z * z;
                crown.push(named(
                    tilted(az, angle, foot),
                    format!("crown{}-{}", i + 1, s + 1),
                ));
            }
            z += ring * angle.to_radians().tan();
        }
        planes.push(named(HalfSpace::new(DVec3::Z, z), "table"));
        planes.extend(crown);
        if self.girdle > 0.0 {
            for (s, &az) in sides.iter().enumerate() {
                planes.push(named(
                    HalfSpace::new(horizontal(az), w / 2.0),
                    format!("girdle-{}", s + 1),
                ));
            }
        }

        // Pavilion: mains and chevrons from the centre-line profile.
        let (depth, step) = self.profile();
        let m = self.chevrons as usize;
        let total = depth[m];
        // A chevron fan is convex only if the last tier rises faster toward
        // the centre line than the corner ridge does: W tan θ_m > depth.
        let last = (self.pavilion_angle - (m - 1) as f64 * self.angle_step).to_radians();
        if m > 1 && w * last.tan() <= total {
            return Err(format!(
                "the chevron tiers are too shallow for a convex pavilion (tan of the last tier, {:.3}, must exceed pavilion depth/width, {:.3}): lower angle_step or chevrons",
                last.tan(),
                total / w
            ));
        }
        let inside = DVec3::ZERO;
        for (s, &az) in sides.iter().enumerate() {
            let profile = |j: usize| {
                horizontal(az) * (w / 2.0 - j as f64 * step) - DVec3::Z * (half_g + depth[j])
            };
            planes.push(named(
                tilted(az, -self.pavilion_angle, profile(0)),
                format!("pavilion-main-{}", s + 1),
            ));
            let corner =
                |da: f64| horizontal(az + da) * (w / std::f64::consts::SQRT_2) - DVec3::Z * half_g;
            for j in 2..=m {
                for (c, da) in [-45.0, 45.0].iter().enumerate() {
                    planes.push(named(
                        through(corner(*da), profile(j - 1), profile(j), inside),
                        format!("chevron{}-{}", j - 1, 2 * s + c + 1),
                    ));
                }
            }
        }
        Ok(planes)
    }

    /// Total depth over the width (table to point).
    pub fn depth(&self) -> f64 {
        let k = self.crown_steps as usize;
        let ring = (1.0 - self.table) / 2.0 / k as f64;
        let crown: f64 = (0..k)
            .map(|i| {
                ring * (self.crown_angle - i as f64 * self.angle_step)
                    .to_radians()
                    .tan()
            })
            .sum();
        crown + self.girdle + self.profile().0[self.chevrons as usize] / self.width
    }
}
