//! Triangles four at a time: the watertight ray/triangle test of Woop,
//! Benthin & Wald ("Watertight Ray/Triangle Intersection", JCGT 2(1), 2013)
//! on structure-of-arrays packets, plus an f64 recomputation of the winning
//! hit's `t`, barycentrics and normal against the caller's exact ray.
//!
//! Why the test is watertight without any epsilon: each vertex is mapped,
//! by the same rounded operations for every triangle that shares it, to a
//! 2D point in a plane across the ray (the ray itself at 0). The edge
//! functions U, V, W are 2×2 determinants of those points; f32 rounding is
//! monotonic, so each computed determinant has the exact sign of the
//! determinant of the rounded points, or is 0. The rounded points form a
//! consistent planar arrangement, so some triangle of a closed mesh contains
//! the ray exactly in it — and that triangle's computed U, V, W are all ≥ 0
//! or all ≤ 0. Zero counts as inside for both neighbours of an edge (the
//! paper instead recomputes zeros in f64 to drop the duplicate; for a
//! closest-hit query the duplicate is harmless), so no ray leaks through a
//! shared edge or vertex.

use super::lanes::{F4, M4};
use super::ray::PreparedRay;
use crate::accel::Ray;
use glam::DVec3;

/// Triangles per packet: one SSE register of f32 per coordinate.
pub(super) const LANES: usize = 4;

/// Four triangles, structure of arrays. Lanes of a partly filled packet
/// repeat its last triangle, so they can only report a hit that a real lane
/// reports too.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct Tri4 {
    /// `v[vertex][axis][lane]`.
    pub v: [[[f32; LANES]; 3]; 3],
    /// Mesh index per lane.
    pub geom: [u32; LANES],
    /// Triangle index within its mesh per lane, as the caller numbered it.
    pub prim: [u32; LANES],
}

/// The hit of one lane, in the prepared ray's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LaneHit {
    pub t: f32,
    pub lane: usize,
}

impl Tri4 {
    /// Packs up to four triangles (each `(geom, prim, [v0, v1, v2])`).
    pub fn pack(tris: &[(u32, u32, [[f32; 3]; 3])]) -> Tri4 {
        assert!(!tris.is_empty() && tris.len() <= LANES);
        let mut p = Tri4 {
            v: [[[0.0; LANES]; 3]; 3],
            geom: [0; LANES],
            prim: [0; LANES],
        };
        for lane in 0..LANES {
            let (geom, prim, verts) = tris[lane.min(tris.len() - 1)];
            p.geom[lane] = geom;
            p.prim[lane] = prim;
            for (vertex, xyz) in verts.iter().enumerate() {
                for (axis, &c) in xyz.iter().enumerate() {
                    p.v[vertex][axis][lane] = c;
                }
            }
        }
        p
    }

    /// Vertex `vertex` of `lane`'s triangle in f64 (exact: stored in f32).
    pub fn vertex(&self, vertex: usize, lane: usize) -> DVec3 {
        let v = &self.v[vertex];
        DVec3::new(v[0][lane] as f64, v[1][lane] as f64, v[2][lane] as f64)
    }

    /// Vertex `j` of each lane translated to the ray origin, permuted and
    /// sheared: (x, y) in the plane across the ray, z along it (before the
    /// S_z scaling, which the caller applies once).
    #[inline(always)]
    fn project(&self, j: usize, ray: &PreparedRay) -> (F4, F4, F4) {
        let [kx, ky, kz] = ray.k;
        let [sx, sy, _] = ray.shear;
        let [ox, oy, oz] = ray.org_k;
        let v = &self.v[j];
        let z = F4(v[kz]) - oz;
        let x = F4(v[kx]) - ox - z * sx;
        let y = F4(v[ky]) - oy - z * sy;
        (x, y, z)
    }

    /// The closest lane hit with `t` in `[ray.tmin, t_best]`, both faces
    /// counted (Woop, Benthin & Wald 2013, Fig. 5, on four lanes).
    #[inline(always)]
    pub fn intersect(&self, ray: &PreparedRay, t_best: f32) -> Option<LaneHit> {
        let sz = ray.shear[2];
        let (x0, y0, z0) = self.project(0, ray);
        let (x1, y1, z1) = self.project(1, ray);
        let (x2, y2, z2) = self.project(2, ray);
        // Scaled barycentrics: 2D edge functions (weights of v0, v1, v2).
        let u = x2 * y1 - y2 * x1;
        let v = x0 * y2 - y0 * x2;
        let w = x1 * y0 - y1 * x0;
        let zero = F4::splat(0.0);
        // Inside (or on an edge) when U, V, W do not have opposite signs:
        // all ≥ 0 or all ≤ 0. A NaN lane fails the det test below.
        let lowest = u.min_or(v.min_or(w));
        let highest = u.max_or(v.max_or(w));
        let det = u + v + w;
        // T = t·det; compare T·sign(det) with the interval times |det| so
        // that no lane pays for a division (the paper's deferred division).
        let t_det = (u * z0 + v * z1 + w * z2) * sz;
        let t_signed = t_det.xor_sign_of(det);
        let abs_det = det.abs();
        let valid: M4 = (lowest.ge(zero) | highest.le(zero))
            & det.ne(zero)
            & t_signed.ge(abs_det * ray.tmin)
            & t_signed.le(abs_det * t_best);
        let mut mask = valid.bits();
        if mask == 0 {
            return None;
        }
        // Usually one lane; several only where triangles of one packet
        // overlap along the ray.
        let mut best: Option<LaneHit> = None;
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let t = t_det.0[lane] / det.0[lane];
            if best.is_none_or(|b| t < b.t) {
                best = Some(LaneHit { t, lane });
            }
        }
        best
    }

    /// `t`, barycentrics (weights of v1 and v2) and the unnormalized normal
    /// (v1 − v0) × (v2 − v0) of `lane`'s triangle for the caller's f64 ray,
    /// by Möller & Trumbore ("Fast, Minimum Storage Ray/Triangle
    /// Intersection", JGT 2(1), 1997) in f64. The f32 test decided that
    /// this triangle is hit; this only makes the numbers exact to f64
    /// rounding for the stored (f32) vertices. Falls back to the f32 values
    /// when the f64 ones are not finite (a ray in the triangle's plane).
    pub fn refine(&self, lane: usize, ray: &Ray, t32: f64) -> (f64, f64, f64, DVec3) {
        let v0 = self.vertex(0, lane);
        let e1 = self.vertex(1, lane) - v0;
        let e2 = self.vertex(2, lane) - v0;
        let ng = e1.cross(e2);
        let p = ray.dir.cross(e2);
        let det = e1.dot(p);
        let s = ray.origin - v0;
        let q = s.cross(e1);
        let inv = 1.0 / det;
        let (u, v, t) = (s.dot(p) * inv, ray.dir.dot(q) * inv, e2.dot(q) * inv);
        if u.is_finite() && v.is_finite() && t.is_finite() {
            (t, u, v, ng)
        } else {
            (t32, 0.0, 0.0, ng)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f64; 3], d: [f64; 3]) -> PreparedRay {
        PreparedRay::new(&Ray::new(DVec3::from(o), DVec3::from(d))).unwrap()
    }

    /// The triangle (0,0,0), (1,0,0), (0,1,0) in the z = 0 plane.
    fn unit() -> Tri4 {
        Tri4::pack(&[(0, 7, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])])
    }

    #[test]
    fn both_faces_hit_at_the_plane() {
        let tri = unit();
        let down = ray([0.25, 0.25, 2.0], [0.0, 0.0, -1.0]);
        let up = ray([0.25, 0.25, -2.0], [0.0, 0.0, 0.5]);
        assert_eq!(tri.intersect(&down, f32::INFINITY).unwrap().t, 2.0);
        // t in units of the scaled direction: (0,0,0.5) was rescaled to
        // (0,0,1), so 2 here is 4 in the caller's units.
        let hit = tri.intersect(&up, f32::INFINITY).unwrap();
        assert_eq!(hit.t as f64 * up.t_to_caller, 4.0);
        assert_eq!(hit.lane, 0);
    }

    #[test]
    fn edges_and_vertices_count_and_outside_does_not() {
        let tri = unit();
        // On the hypotenuse, on a leg, at each vertex: hits.
        for o in [[0.5, 0.5], [0.5, 0.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] {
            let r = ray([o[0], o[1], 1.0], [0.0, 0.0, -1.0]);
            assert!(tri.intersect(&r, f32::INFINITY).is_some(), "{o:?}");
        }
        // Just outside each edge, by one f32 ulp.
        let e = f32::EPSILON as f64;
        for o in [[0.5 + e, 0.5], [0.5, -e], [-e, 0.5]] {
            let r = ray([o[0], o[1], 1.0], [0.0, 0.0, -1.0]);
            assert!(tri.intersect(&r, f32::INFINITY).is_none(), "{o:?}");
        }
    }

    #[test]
    fn interval_is_closed_and_respected() {
        let tri = unit();
        let mut r = ray([0.25, 0.25, 2.0], [0.0, 0.0, -1.0]);
        assert!(tri.intersect(&r, 2.0).is_some());
        assert!(tri.intersect(&r, 1.9).is_none());
        r.tmin = 2.0;
        assert!(tri.intersect(&r, f32::INFINITY).is_some());
        r.tmin = 2.1;
        assert!(tri.intersect(&r, f32::INFINITY).is_none());
    }

    #[test]
    fn parallel_and_degenerate_triangles_miss() {
        let tri = unit();
        let along = ray([-1.0, 0.25, 0.0], [1.0, 0.0, 0.0]);
        assert!(tri.intersect(&along, f32::INFINITY).is_none());
        let flat = Tri4::pack(&[(0, 0, [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]])]);
        let r = ray([0.5, 0.5, 1.0], [0.0, 0.0, -1.0]);
        assert!(flat.intersect(&r, f32::INFINITY).is_none());
    }

    #[test]
    fn closest_lane_wins_and_padding_repeats_the_last_triangle() {
        let at = |z: f32, prim| (0, prim, [[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]]);
        let p = Tri4::pack(&[at(0.0, 0), at(0.5, 1), at(-0.5, 2)]);
        assert_eq!(p.prim, [0, 1, 2, 2]);
        let r = ray([0.25, 0.25, 2.0], [0.0, 0.0, -1.0]);
        assert_eq!(p.intersect(&r, f32::INFINITY).unwrap().lane, 1);
        let r = ray([0.25, 0.25, -2.0], [0.0, 0.0, 1.0]);
        let hit = p.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!((hit.lane, hit.t), (2, 1.5));
    }

    #[test]
    fn refine_matches_the_definitions() {
        let tri = Tri4::pack(&[(0, 0, [[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [1.0, 4.0, 0.0]])]);
        let r = Ray::new(DVec3::new(1.5, 1.0, 3.0), DVec3::new(0.0, 0.0, -2.0));
        let (t, u, v, ng) = tri.refine(0, &r, 0.0);
        assert_eq!(t, 1.5);
        // Point (1.5, 1, 0) = v0 + u (v1 − v0) + v (v2 − v0): u = 0.25, v = 0.25.
        assert!(
            (u - 0.25).abs() < 1e-15 && (v - 0.25).abs() < 1e-15,
            "{u} {v}"
        );
        assert_eq!(ng, DVec3::new(0.0, 0.0, 8.0));
    }
}
