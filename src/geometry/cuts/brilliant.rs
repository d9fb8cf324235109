//! The round brilliant (and the oval, its stretch).
//!
//! Facets, counted as a cutter counts them: table 1, stars 8, bezels
//! (crown mains) 8, upper girdles 16, pavilion mains 8, lower girdles 16 —
//! 57; a culet makes 58. A girdle of non-zero thickness adds its band:
//! `girdle_facets` vertical facets (16 by default, one under each pair of
//! upper girdles), so the default stone has 57 + 16 = 73 facets. With
//! `girdle = 0` the upper and lower girdles meet in a knife edge and the
//! count is 57 (58 with a culet).
//!
//! Construction (R = diameter/2, girdle thickness g, mains at azimuths
//! 0°, 45°, …, star and lower-girdle tips halfway between):
//! - girdle corners at radius R on every multiple of 22.5°, at z = ±g/2;
//! - bezel k: crown angle, through the girdle corner at its azimuth;
//! - table: z = g/2 + R (1 − table) tan(crown angle), so the table octagon's
//!   corners lie at radius table·R on the mains' azimuths (Tolkowsky's
//!   crown height (D − T)/2 · tan θc);
//! - star tip: on the two bezels, at the fraction `star` of the way from the
//!   table edge to the girdle along its azimuth; star k through two table
//!   corners and that tip; upper girdles through a bezel's girdle corner,
//!   the girdle corner halfway to the next bezel, and the star tip;
//! - pavilion main k: pavilion angle, through the girdle corner below the
//!   bezel (pavilion depth R tan θp to the point);
//! - lower-girdle tip: on the ridge of two mains, the fraction
//!   `lower_girdle` of the way from the girdle to the axis; lower girdles
//!   through two girdle corners and that tip;
//! - culet: horizontal, its octagon `culet`·diameter across flats.
//!
//! The oval stretches every plane by `ratio` along +Y (length = ratio ×
//! diameter): heights stay, so its crown and pavilion angles are the given
//! ones across the width and shallower toward the ends
//! (tan θ' = tan θ / ratio), as in a cut oval.

use super::super::convex::HalfSpace;
use super::{check, horizontal, named, through, tilted, NamedPlane};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Length-to-width ratio of an oval unless given.
pub const OVAL_RATIO: f64 = 1.4;

/// Proportions of a round or oval brilliant (fractions of the diameter,
/// angles in degrees from the girdle plane).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct Brilliant {
    /// Girdle diameter (the width of an oval), in scene units. Default 1.
    pub diameter: f64,
    /// Table width corner to corner over the diameter. Default 0.53.
    pub table: f64,
    /// Bezel angle. Default 34.5°.
    pub crown_angle: f64,
    /// Pavilion main angle. Default 40.75°.
    pub pavilion_angle: f64,
    /// Girdle thickness at the mains over the diameter. Default 0.02.
    pub girdle: f64,
    /// Star length: how far the star tips reach from the table edge toward
    /// the girdle. Default 0.5.
    pub star: f64,
    /// Lower-girdle length: how far their tips reach from the girdle toward
    /// the axis. Default 0.77.
    pub lower_girdle: f64,
    /// Culet width across flats over the diameter; 0 for a point. Default 0.
    pub culet: f64,
    /// Vertical facets of the girdle band (a multiple of 16). Default 16.
    pub girdle_facets: u32,
    /// Length over width (ovals only; default 1.4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
}

impl Default for Brilliant {
    /// Tolkowsky's round brilliant (1919): table 53 %, crown 34.5°,
    /// pavilion 40.75°; star 50 %, lower girdle 77 %, girdle 2 %, no culet.
    fn default() -> Brilliant {
        Brilliant {
            diameter: 1.0,
            table: 0.53,
            crown_angle: 34.5,
            pavilion_angle: 40.75,
            girdle: 0.02,
            star: 0.5,
            lower_girdle: 0.77,
            culet: 0.0,
            girdle_facets: 16,
            ratio: None,
        }
    }
}

impl Brilliant {
    /// Crown height over the diameter: (1 − table)/2 · tan(crown angle).
    pub fn crown_height(&self) -> f64 {
        (1.0 - self.table) / 2.0 * self.crown_angle.to_radians().tan()
    }

    /// Pavilion depth (girdle to point) over the diameter:
    /// tan(pavilion angle)/2.
    pub fn pavilion_depth(&self) -> f64 {
        self.pavilion_angle.to_radians().tan() / 2.0
    }

    fn validate(&self, ratio: f64) -> Result<(), String> {
        check("diameter", self.diameter, 0.0, f64::INFINITY, false)?;
        check("table", self.table, 0.0, 1.0, false)?;
        check("crown_angle", self.crown_angle, 0.0, 90.0, false)?;
        check("pavilion_angle", self.pavilion_angle, 0.0, 90.0, false)?;
        check("girdle", self.girdle, 0.0, 0.5, true)?;
        check("star", self.star, 0.0, 1.0, false)?;
        check("lower_girdle", self.lower_girdle, 0.0, 1.0, false)?;
        check("culet", self.culet, 0.0, 1.0 - self.lower_girdle, true)
            .map_err(|e| format!("{e} (the culet must stay inside the lower-girdle tips)"))?;
        check("ratio", ratio, 1.0, 100.0, true)?;
        let n = self.girdle_facets;
        if n < 16 || n % 16 != 0 || n > 4096 {
            return Err(format!(
                "girdle_facets = {n} must be a multiple of 16 between 16 and 4096"
            ));
        }
        Ok(())
    }

    /// The facet planes of the brilliant, stretched by `ratio` along +Y.
    pub fn planes(&self, ratio: f64) -> Result<Vec<NamedPlane>, String> {
        self.validate(ratio)?;
        let r = self.diameter / 2.0;
        let half_g = self.girdle * self.diameter / 2.0;
        let (tc, tp) = (
            self.crown_angle.to_radians().tan(),
            self.pavilion_angle.to_radians().tan(),
        );
        let z_table = half_g + r * (1.0 - self.table) * tc;
        let z_point = -half_g - r * tp;
        let main = |k: usize| 45.0 * k as f64;
        let mid = |k: usize| 45.0 * k as f64 + 22.5;
        let at = |radius: f64, azimuth: f64, z: f64| horizontal(azimuth) * radius + DVec3::Z * z;
        let cos_half = 22.5f64.to_radians().cos();
        let inside = DVec3::ZERO;
        // The star tip: radius along its azimuth, height on the bezel.
        let table_edge = self.table * r * cos_half;
        let r_star = table_edge + self.star * (r - table_edge);
        let z_star = half_g + tc * (r - r_star * cos_half);
        // The lower-girdle tip: on the ridge of two pavilion mains.
        let r_lower = r * (1.0 - self.lower_girdle);
        let z_lower = -half_g - tp * (r - r_lower * cos_half);

        let mut planes = vec![named(HalfSpace::new(DVec3::Z, z_table), "table")];
        for k in 0..8 {
            let (t0, t1) = (
                at(self.table * r, main(k), z_table),
                at(self.table * r, main(k + 1), z_table),
            );
            let tip = at(r_star, mid(k), z_star);
            planes.push(named(
                through(t0, t1, tip, inside),
                format!("star-{}", k + 1),
            ));
        }
        for k in 0..8 {
            planes.push(named(
                tilted(main(k), self.crown_angle, at(r, main(k), half_g)),
                format!("bezel-{}", k + 1),
            ));
        }
        for k in 0..8 {
            let tip = at(r_star, mid(k), z_star);
            let (b0, g, b1) = (
                at(r, main(k), half_g),
                at(r, mid(k), half_g),
                at(r, main(k + 1), half_g),
            );
            planes.push(named(
                through(b0, g, tip, inside),
                format!("upper-girdle-{}", 2 * k + 1),
            ));
            planes.push(named(
                through(g, b1, tip, inside),
                format!("upper-girdle-{}", 2 * k + 2),
            ));
        }
        if self.girdle > 0.0 {
            let n = self.girdle_facets as usize;
            let step = 360.0 / n as f64;
            let apothem = r * (step / 2.0).to_radians().cos();
            for j in 0..n {
                let azimuth = step * (j as f64 + 0.5);
                planes.push(named(
                    HalfSpace::new(horizontal(azimuth), apothem),
                    format!("girdle-{}", j + 1),
                ));
            }
        }
        for k in 0..8 {
            planes.push(named(
                tilted(main(k), -self.pavilion_angle, at(r, main(k), -half_g)),
                format!("pavilion-main-{}", k + 1),
            ));
        }
        for k in 0..8 {
            let tip = at(r_lower, mid(k), z_lower);
            let (p0, g, p1) = (
                at(r, main(k), -half_g),
                at(r, mid(k), -half_g),
                at(r, main(k + 1), -half_g),
            );
            planes.push(named(
                through(p0, g, tip, inside),
                format!("lower-girdle-{}", 2 * k + 1),
            ));
            planes.push(named(
                through(g, p1, tip, inside),
                format!("lower-girdle-{}", 2 * k + 2),
            ));
        }
        if self.culet > 0.0 {
            let z_culet = z_point + self.culet * r * tp;
            planes.push(named(HalfSpace::new(-DVec3::Z, -z_culet), "culet"));
        }
        if ratio != 1.0 {
            for p in &mut planes {
                p.plane = stretch_y(p.plane, ratio);
            }
        }
        Ok(planes)
    }
}

/// The half-space after the map (x, y, z) → (x, s·y, z): n·x ≤ d becomes
/// (n_x, n_y/s, n_z)·x' ≤ d.
fn stretch_y(h: HalfSpace, s: f64) -> HalfSpace {
    HalfSpace::new(DVec3::new(h.normal.x, h.normal.y / s, h.normal.z), h.offset)
}
