//! Built-in gemological light rigs (`[[light]] rig = NAME`, `spar render
//! --light-rig NAME`): the lighting gem software and gem photography use,
//! defined relative to the camera so that it follows any camera. Each rig
//! is a set of lights at infinity ([`DistantLight`]: a disc, or a ring of
//! directions with a hole), unpolarized, so rigs add no machinery to the
//! integrators. Angles are measured from the camera's axis; docs/scenes.md
//! lists the numbers.

use super::camera::Camera;
use super::light::{DistantLight, Polarization};
use glam::{DMat3, DVec3};
use std::fmt;
use std::str::FromStr;

/// Ring light: light travels at 10° to 15° from the camera's axis (a ring
/// around the lens, 15 cm across at 28 cm from the stone), radiance 1.
pub const RING_INNER_DEG: f64 = 10.0;
/// Outer half-angle of the ring light, degrees.
pub const RING_OUTER_DEG: f64 = 15.0;
/// The dome's head shadow, full angular diameter in degrees unless given:
/// a 16 cm head at 30 cm from the stone (2 atan(8/30) = 29.9°).
pub const DEFAULT_HEAD_SHADOW_DEG: f64 = 30.0;
/// Spot: a disc 2° across (a 5 cm lamp at 1.4 m) ...
pub const SPOT_DIAMETER_DEG: f64 = 2.0;
/// ... whose centre is 20° above the camera's axis (toward image up, so
/// outside the head shadow) ...
pub const SPOT_ELEVATION_DEG: f64 = 20.0;
/// ... of radiance 2, over the dome at this radiance (a dim room, so that
/// the stone's outline shows between the flashes).
pub const SPOT_RADIANCE: f64 = 2.0;
/// The spot rig's dim dome (with the default head shadow).
pub const SPOT_FILL_RADIANCE: f64 = 0.05;

/// The names of the built-in rigs, in the order errors list them.
pub const RIG_NAMES: [&str; 3] = ["ring", "dome", "spot"];

/// A built-in light rig.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightRig {
    /// A ring light around the lens: light from every direction between
    /// [`RING_INNER_DEG`] and [`RING_OUTER_DEG`] off the camera's axis.
    Ring,
    /// A diffuse dome over the stone's camera side (every direction up to
    /// 90° off the camera's axis, radiance 1) with the observer's head
    /// shadow: no light within `head_shadow / 2` of the axis.
    Dome {
        /// Full angular diameter of the head's shadow, degrees (0 to 180).
        head_shadow: f64,
    },
    /// A small bright source for fire over a dim dome.
    Spot,
}

impl fmt::Display for LightRig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LightRig::Ring => f.write_str("ring"),
            LightRig::Dome { head_shadow } if *head_shadow == DEFAULT_HEAD_SHADOW_DEG => {
                f.write_str("dome")
            }
            LightRig::Dome { head_shadow } => write!(f, "dome:{head_shadow}"),
            LightRig::Spot => f.write_str("spot"),
        }
    }
}

impl FromStr for LightRig {
    type Err = String;

    /// `ring`, `dome`, `dome:DEG` (a head shadow DEG degrees across) or
    /// `spot`.
    fn from_str(s: &str) -> Result<LightRig, String> {
        let t = s.trim();
        let (name, arg) = t.split_once(':').map_or((t, None), |(n, a)| (n, Some(a)));
        let known = || {
            format!(
                "the light rigs are {} (dome:DEG: a head shadow DEG degrees across, default {})",
                RIG_NAMES.join(", "),
                DEFAULT_HEAD_SHADOW_DEG
            )
        };
        match (name, arg) {
            ("ring", None) => Ok(LightRig::Ring),
            ("spot", None) => Ok(LightRig::Spot),
            ("dome", None) => Ok(LightRig::Dome {
                head_shadow: DEFAULT_HEAD_SHADOW_DEG,
            }),
            ("dome", Some(a)) => match a.trim().parse::<f64>() {
                Ok(d) if d.is_finite() && (0.0..=180.0).contains(&d) => {
                    Ok(LightRig::Dome { head_shadow: d })
                }
                _ => Err(format!(
                    "`{t}`: the head shadow is a number of degrees from 0 to 180 (dome:30)"
                )),
            },
            ("ring" | "spot", Some(_)) => Err(format!("`{t}`: {name} takes no parameter")),
            _ => Err(format!("unknown light rig `{t}`: {}", known())),
        }
    }
}

/// A light at infinity travelling within `outer_deg` of `direction` and
/// not within `inner_deg` of it (half-angles, degrees), radiance `radiance`.
fn cone(direction: DVec3, inner_deg: f64, outer_deg: f64, radiance: f64) -> DistantLight {
    DistantLight {
        direction,
        angular_diameter: (2.0 * outer_deg).to_radians(),
        inner_diameter: (2.0 * inner_deg).to_radians(),
        radiance,
        polarization: Polarization::Unpolarized,
    }
}

impl LightRig {
    /// The rig's lights for `camera`, every radiance times `scale`. The
    /// camera's axis is its viewing direction `f` (a rig's light travels
    /// along it, from behind the camera into the scene); "above" is toward
    /// the camera's image up.
    pub fn lights(&self, camera: &Camera, scale: f64) -> Vec<DistantLight> {
        let f = camera.forward();
        match *self {
            LightRig::Ring => vec![cone(f, RING_INNER_DEG, RING_OUTER_DEG, scale)],
            LightRig::Dome { head_shadow } => vec![cone(f, 0.5 * head_shadow, 90.0, scale)],
            LightRig::Spot => {
                // Light from above the camera travels down: f turned
                // toward −up by the elevation (a right-handed turn about
                // right = f × up turns f toward +up).
                let right = camera.right();
                let d = DMat3::from_axis_angle(right, -SPOT_ELEVATION_DEG.to_radians()) * f;
                vec![
                    cone(d, 0.0, 0.5 * SPOT_DIAMETER_DEG, SPOT_RADIANCE * scale),
                    cone(
                        f,
                        0.5 * DEFAULT_HEAD_SHADOW_DEG,
                        90.0,
                        SPOT_FILL_RADIANCE * scale,
                    ),
                ]
            }
        }
    }
}
