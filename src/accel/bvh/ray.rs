//! A ray prepared once for traversal: the f64 ray of the [`Intersector`]
//! trait turned into the f32 quantities the box and triangle tests read, with
//! the direction rescaled by a power of two so that no magnitude of the
//! caller's direction can underflow or overflow f32.
//!
//! Everything here is relative: rounding is bounded by multiples of the f32
//! unit roundoff `u = 2⁻²⁴`, never by an absolute epsilon, so a scene and its
//! rays scaled or translated together give the same answers (within f32
//! rounding of the coordinates themselves).
//!
//! [`Intersector`]: crate::accel::Intersector

use super::lanes::F4;
use crate::accel::Ray;

/// Unit roundoff of f32 (half an ulp of 1).
const UNIT_ROUNDOFF: f32 = f32::EPSILON * 0.5;

/// γ(n) = n·u / (1 − n·u): the bound on the relative error of n chained f32
/// roundings (Higham, "Accuracy and Stability of Numerical Algorithms",
/// §3.1; pbrt-v3 §3.9.1 uses the same notation).
const fn gamma(n: f32) -> f32 {
    n * UNIT_ROUNDOFF / (1.0 - n * UNIT_ROUNDOFF)
}

/// Factor on a box's far distance that makes the slab test conservative
/// (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013). Both tests use the
/// same f32 origin and direction `d`. A slab distance
/// `fl(fl(plane − o) · fl(1/d_a))` is three roundings from the exact
/// `(plane − o)/d_a`; the triangle test's sheared ray crosses that plane at
/// a parameter one rounding (of `S_x = d_x · S_z`) from it (along the
/// dominant axis the two tests share `1/d_z` exactly). So near and far are
/// each within γ(4) of the exact distances along the ray the triangle test
/// uses, and one more rounding for the product by this factor gives
/// `near ≤ far · (1 + 2γ(5))` whenever that ray meets the box.
pub(super) const FAR_FACTOR: f32 = 1.0 + 2.0 * gamma(5.0);

/// The ray as the traversal sees it. Parameters `t` here are in units of
/// the rescaled direction; multiply by [`PreparedRay::t_to_caller`] for the
/// caller's units.
#[derive(Clone, Copy, Debug)]
pub(super) struct PreparedRay {
    /// Origin rounded to nearest f32. Box and triangle tests both use this
    /// origin, so they test the same ray.
    pub org: [f32; 3],
    /// 1 / direction per axis (±∞ for a zero component).
    pub inv_dir: [f32; 3],
    /// Per axis, whether the ray enters a slab through its max plane (the
    /// direction component is negative), i.e. which of a box's bounds is
    /// the near one.
    pub enters_at_max: [bool; 3],
    /// Woop–Benthin–Wald axis permutation: `k[2]` is the dominant axis of
    /// the direction; `k[0]`, `k[1]` follow it cyclically, swapped when the
    /// dominant component is negative so that the winding is preserved.
    pub k: [usize; 3],
    /// The origin's coordinates in the order `k`.
    pub org_k: [f32; 3],
    /// Shear constants (S_x, S_y, S_z) of the same paper: after
    /// translating by the origin, `x − S_x·z` and `y − S_y·z` are the
    /// coordinates in a plane across the ray, and `S_z·z` the distance.
    pub shear: [f32; 3],
    /// The interval of the ray in these units, rounded outward.
    pub tmin: f32,
    pub tmax: f32,
    /// Power of two that converts `t` back to the caller's units (exact).
    pub t_to_caller: f64,
}

/// `2^e` for |e| ≤ 1022, built from its bits.
fn pow2(e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// The largest f32 not above `x` (f32 rounding is to nearest).
pub(super) fn f32_down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x {
        next_toward_neg_inf(y)
    } else {
        y
    }
}

/// The smallest f32 not below `x`.
pub(super) fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        -next_toward_neg_inf(-y)
    } else {
        y
    }
}

/// The f32 just above `y`.
pub(super) fn next_f32_up(y: f32) -> f32 {
    -next_toward_neg_inf(-y)
}

/// The f32 just below `y` (`f32::next_down`, which is newer than spar's
/// minimum Rust version).
fn next_toward_neg_inf(y: f32) -> f32 {
    if y.is_nan() || y == f32::NEG_INFINITY {
        y
    } else if y == 0.0 {
        -f32::from_bits(1)
    } else if y > 0.0 {
        f32::from_bits(y.to_bits() - 1)
    } else {
        f32::from_bits(y.to_bits() + 1)
    }
}

impl PreparedRay {
    /// Prepares a ray, or `None` when no hit is possible: a zero,
    /// subnormal (below 2⁻¹⁰²² in every component) or non-finite direction,
    /// a NaN bound, an origin that is not a finite f32, or an
    /// empty interval. A negative `tmin` counts as 0, as Embree requires.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Option<PreparedRay> {
        let d = ray.dir.to_array();
        let largest = d[0].abs().max(d[1].abs()).max(d[2].abs());
        if !(largest >= f64::MIN_POSITIVE && d.iter().all(|c| c.is_finite())) {
            return None;
        }
        // Rescale the direction by 2^-exp so its largest component lies in
        // [1, 2): exact (a power of two), and it keeps 1/dir and the shear
        // constants inside f32's range for any caller's direction. Then
        // o + t·d = o + t'·d' with t = t'·2^-exp. The exponent is split in
        // two factors so each stays a normal f64.
        let exp = ((largest.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        let (e1, e2) = (exp / 2, exp - exp / 2);
        let d = d.map(|c| c * pow2(-e1) * pow2(-e2));
        let t_to_caller = pow2(-e1) * pow2(-e2);
        let t_from_caller = pow2(e1) * pow2(e2);

        let org = ray.origin.to_array().map(|c| c as f32);
        if !org.iter().all(|c| c.is_finite()) {
            return None;
        }
        if ray.tmin.is_nan() || !(ray.tmin.max(0.0) <= ray.tmax) {
            return None;
        }
        let tmin = f32_down(ray.tmin.max(0.0) * t_from_caller);
        let tmax = f32_up(ray.tmax * t_from_caller);

        // Both tests use this direction, rounded once; a component far below
        // the largest may round to ±0, whose reciprocal ±∞ is what the slab
        // test wants.
        let d = d.map(|c| c as f32);
        let inv = F4::splat(1.0) / F4([d[0], d[1], d[2], 1.0]);
        let inv_dir = [inv.0[0], inv.0[1], inv.0[2]];
        let enters_at_max = inv_dir.map(|i| i < 0.0);

        // Woop, Benthin & Wald 2013, §3: permute so that z is the dominant
        // axis, keep the winding by swapping x and y when dir.z < 0.
        let a = d.map(f32::abs);
        let kz = if a[0] > a[1] {
            if a[0] > a[2] {
                0
            } else {
                2
            }
        } else if a[1] > a[2] {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = inv_dir[kz];
        let shear = [d[kx] * sz, d[ky] * sz, sz];
        Some(PreparedRay {
            org,
            inv_dir,
            enters_at_max,
            k: [kx, ky, kz],
            org_k: [org[kx], org[ky], org[kz]],
            shear,
            tmin,
            tmax,
            t_to_caller,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn outward_rounding_brackets_the_value() {
        for x in [0.1, -0.1, 1e-40, -1e-40, 3.0, 1e38, 1e39, -1e39, 0.0] {
            let (lo, hi) = (f32_down(x), f32_up(x));
            assert!((lo as f64) <= x && x <= hi as f64, "{x}: {lo} {hi}");
            assert!(hi == lo || next_toward_neg_inf(hi) == lo, "{x}: {lo} {hi}");
        }
        assert_eq!(f32_up(f64::INFINITY), f32::INFINITY);
        assert_eq!(f32_down(1.0), 1.0);
    }

    #[test]
    fn direction_rescaling_is_a_power_of_two_and_any_magnitude_works() {
        for m in [1e-300, 1e-30, 0.75, 1.0, 2.0 - 1e-16, 3.0, 1e30, 1e300] {
            let ray = Ray::new(DVec3::ZERO, DVec3::new(0.5, -1.0, 0.25) * m);
            let p = PreparedRay::new(&ray).unwrap();
            // The dominant component is y; scaled into [1, 2).
            assert_eq!(p.k[2], 1);
            let scaled = 1.0 / (p.shear[2] as f64);
            assert!((1.0..2.0).contains(&scaled.abs()), "{m}: {scaled}");
            // t_to_caller is exactly the power of two that undoes it.
            // (1/S_z is rounded to f32: 2⁻²⁴ relative.)
            let back = -scaled / p.t_to_caller / m;
            assert!((back - 1.0).abs() < 1e-7, "{m}: {back}");
            assert_eq!(p.t_to_caller.to_bits() & ((1 << 52) - 1), 0);
        }
    }

    #[test]
    fn rays_that_cannot_hit_are_refused() {
        let o = DVec3::ZERO;
        assert!(PreparedRay::new(&Ray::new(o, DVec3::ZERO)).is_none());
        assert!(PreparedRay::new(&Ray::new(o, DVec3::new(f64::NAN, 1.0, 0.0))).is_none());
        assert!(PreparedRay::new(&Ray::new(DVec3::splat(1e39), DVec3::X)).is_none());
        let mut r = Ray::new(o, DVec3::X);
        r.tmin = 2.0;
        r.tmax = 1.0;
        assert!(PreparedRay::new(&r).is_none());
        r.tmax = f64::NAN;
        assert!(PreparedRay::new(&r).is_none());
    }

    #[test]
    fn winding_is_kept_by_the_permutation() {
        // k must be an even permutation of (0, 1, 2) when dir[kz] > 0 and an
        // odd one when it is negative.
        for d in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ] {
            let p = PreparedRay::new(&Ray::new(DVec3::ZERO, d)).unwrap();
            let even = (p.k[1] == (p.k[0] + 1) % 3) && (p.k[2] == (p.k[1] + 1) % 3);
            assert_eq!(even, d.to_array()[p.k[2]] > 0.0, "{d}");
        }
    }
}
