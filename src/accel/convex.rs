//! Leaving a convex object from inside, by its facet planes alone.
//!
//! Most rays of a gem's tree travel inside the stone, from one facet to
//! the next. A cut stone is convex: its inside is the intersection of its
//! facets' half-spaces `n · x ≤ c`. A ray `o + t d` from a point inside
//! leaves through the facet whose plane it crosses first (ray–convex
//! polyhedron clipping, Haines, "Fast ray–convex polyhedron intersection",
//! Graphics Gems II, 1991): for every facet it moves towards (`n · d > 0`),
//! `t = (c − n · o) / (n · d)`, and the exit is the smallest. No
//! acceleration structure, no triangles, and the hit lies exactly on the
//! facet's own f64 plane, the plane whose normal the interface solver uses.
//!
//! [`ConvexInterior::new`] accepts a mesh only when every vertex lies
//! within a tolerance of the inner side of every facet plane (then the
//! closed mesh bounds exactly that intersection of half-spaces, up to the
//! tolerance). [`ConvexInterior::exit`] answers [`Exit::Unsure`] when the
//! origin is not strictly inside every plane (a ray started within its
//! offset of an edge, or not finite): the caller then asks the general
//! backend, as it would without this shortcut.

use crate::geometry::mesh::Mesh;
use glam::DVec3;

/// How far (relative to the mesh's bounding-box diagonal) a vertex may lie
/// outside a facet plane for the mesh to count as convex: far below the
/// 1e-5 offset secondary rays start at, far above f64 rounding of facet
/// planes fitted to their vertices.
pub const CONVEX_TOLERANCE: f64 = 1e-9;

/// Planes are processed this many at a time, in independent lanes (the
/// loop has no branches, so the compiler turns it into SIMD).
const LANES: usize = 4;

/// The facet planes of a convex mesh, one entry per facet, as columns
/// padded to a multiple of [`LANES`] with planes no ray approaches.
#[derive(Clone, Debug)]
pub struct ConvexInterior {
    blocks: Vec<Block>,
    /// One triangle of each facet (what a backend would report as `prim`).
    prims: Vec<u32>,
}

/// [`LANES`] planes `n · x <= offset`, as rows `[nx, ny, nz, offset]`
/// (the layout the AVX loop in `native::simd` loads).
type Block = [[f64; LANES]; 4];

/// How far inside plane `l` of block `b` the point `o` is, and the speed
/// of direction `d` towards it.
#[inline(always)]
fn approach(b: &Block, l: usize, o: DVec3, d: DVec3) -> (f64, f64) {
    let (nx, ny, nz) = (b[0][l], b[1][l], b[2][l]);
    let inside = b[3][l] - (nx * o.x + ny * o.y + nz * o.z);
    (inside, nx * d.x + ny * d.y + nz * d.z)
}

/// Where a ray from inside leaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exit {
    /// Through facet `facet` (triangle `prim` of it) at `origin + t dir`.
    Facet { t: f64, facet: u32, prim: u32 },
    /// The origin is not strictly inside every facet plane, or the ray is
    /// not finite: ask the general backend.
    Unsure,
}

impl ConvexInterior {
    /// The planes of `mesh` when it is closed and consistently oriented,
    /// convex within [`CONVEX_TOLERANCE`], and every facet has a triangle;
    /// `None` otherwise (an open box's planes would bound more than the
    /// box: a ray could leave through the missing face).
    pub fn new(mesh: &Mesh) -> Option<ConvexInterior> {
        mesh.check_closed_and_oriented().ok()?;
        let (lo, hi) = mesh.bounds();
        let tolerance = CONVEX_TOLERANCE * (hi - lo).length();
        if !(tolerance > 0.0) || !tolerance.is_finite() {
            return None;
        }
        let mut prims = vec![u32::MAX; mesh.facets.len()];
        for (t, &f) in mesh.triangle_facet.iter().enumerate().rev() {
            prims[f as usize] = t as u32;
        }
        if prims.contains(&u32::MAX) {
            return None;
        }
        for facet in &mesh.facets {
            let ok = mesh
                .positions
                .iter()
                .all(|&p| facet.normal.dot(p) - facet.offset <= tolerance);
            if !ok || !facet.normal.is_finite() || !facet.offset.is_finite() {
                return None;
            }
        }
        // Padding planes 0 · x <= 1: every point is inside them and no ray
        // approaches them.
        let padding: Block = [[0.0; LANES], [0.0; LANES], [0.0; LANES], [1.0; LANES]];
        let mut blocks = vec![padding; mesh.facets.len().div_ceil(LANES)];
        for (i, facet) in mesh.facets.iter().enumerate() {
            let (b, l) = (&mut blocks[i / LANES], i % LANES);
            b[0][l] = facet.normal.x;
            b[1][l] = facet.normal.y;
            b[2][l] = facet.normal.z;
            b[3][l] = facet.offset;
        }
        Some(ConvexInterior { blocks, prims })
    }

    /// The plane loop, portable: per lane, the nearest crossing as a
    /// fraction inside / speed (plane i is nearer than the best so far
    /// when inside_i · speed < inside · speed_i; the start 1 / 0 loses to
    /// every approaching plane and to no receding one, since every inside
    /// is positive when the answer counts) and the smallest distance
    /// inside. Branch-free, so the compiler vectorizes it;
    /// `native::simd` runs the same operations in AVX registers.
    #[inline(always)]
    fn lanes(&self, o: DVec3, d: DVec3) -> ([f64; LANES], [f64; LANES], [f64; LANES]) {
        let mut num = [1.0f64; LANES];
        let mut den = [0.0f64; LANES];
        let mut least_inside = [f64::INFINITY; LANES];
        for b in &self.blocks {
            for l in 0..LANES {
                let (inside, speed) = approach(b, l, o, d);
                let nearer = inside * den[l] < num[l] * speed;
                num[l] = if nearer { inside } else { num[l] };
                den[l] = if nearer { speed } else { den[l] };
                least_inside[l] = if inside < least_inside[l] {
                    inside
                } else {
                    least_inside[l]
                };
            }
        }
        (num, den, least_inside)
    }

    /// The facet a ray from `origin` along `dir` leaves through
    /// (Haines 1991: the nearest crossing among the planes it moves
    /// towards).
    #[inline]
    pub fn exit(&self, origin: DVec3, dir: DVec3) -> Exit {
        if !(origin.is_finite() && dir.is_finite()) {
            return Exit::Unsure;
        }
        let (o, d) = (origin, dir);
        #[cfg(feature = "native")]
        if let Some(l) =
            crate::native::simd::nearest_crossing(&self.blocks, o.to_array(), d.to_array())
        {
            return self.nearest_of(l.num, l.den, l.least_inside, |lane| {
                Some(l.plane[lane])
                    .filter(|&p| p >= 0.0)
                    .map(|p| p as usize)
            });
        }
        let (num, den, least_inside) = self.lanes(o, d);
        // The plane of a lane's winner: the first whose distance and speed
        // are the winner's, bit for bit.
        self.nearest_of(num, den, least_inside, |lane| {
            self.blocks
                .iter()
                .position(|b| approach(b, lane, o, d) == (num[lane], den[lane]))
                .map(|k| k * LANES + lane)
        })
    }

    /// The exit from the lanes of the plane loop; `plane(lane)` names the
    /// plane of a lane's winner.
    #[inline(always)]
    fn nearest_of(
        &self,
        num: [f64; LANES],
        den: [f64; LANES],
        least_inside: [f64; LANES],
        plane: impl Fn(usize) -> Option<usize>,
    ) -> Exit {
        let inside = least_inside.into_iter().fold(f64::INFINITY, f64::min);
        if !(inside > 0.0) {
            return Exit::Unsure;
        }
        // The nearest over the lanes (on a tie, the lowest lane).
        let mut best = (f64::INFINITY, usize::MAX);
        for l in 0..LANES {
            let t = num[l] / den[l];
            if den[l] > 0.0 && t < best.0 {
                best = (t, l);
            }
        }
        let (t, lane) = best;
        if !t.is_finite() {
            return Exit::Unsure;
        }
        match plane(lane) {
            Some(i) if i < self.prims.len() => Exit::Facet {
                t,
                facet: i as u32,
                prim: self.prims[i],
            },
            _ => Exit::Unsure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::asc::load_asc_stone;
    use crate::geometry::cuts::Cut;
    use crate::geometry::obj::{load_obj, parse_obj};

    /// The first hit of a ray on a mesh, by brute force over its triangles
    /// (Möller & Trumbore 1997, written out here): (t, facet).
    fn brute_force(mesh: &Mesh, o: DVec3, d: DVec3) -> Option<(f64, u32)> {
        let mut best: Option<(f64, u32)> = None;
        for (tri, &facet) in mesh.triangles.iter().zip(&mesh.triangle_facet) {
            let [a, b, c] = tri.map(|v| mesh.positions[v as usize]);
            let (e1, e2) = (b - a, c - a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-300 {
                continue;
            }
            let s = o - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = d.dot(q) / det;
            let t = e2.dot(q) / det;
            let slack = 1e-12;
            let inside = u >= -slack && v >= -slack && u + v <= 1.0 + slack;
            if inside && t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, facet));
            }
        }
        best
    }

    /// A small deterministic generator for test rays (splitmix64).
    fn uniforms(seed: u64) -> impl FnMut() -> f64 {
        let mut z = seed;
        move || {
            z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut x = z;
            x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((x ^ (x >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn brilliant() -> Mesh {
        Cut::by_name("round-brilliant").unwrap().mesh().unwrap()
    }

    #[test]
    fn exits_where_brute_force_over_the_triangles_does() {
        // Random points inside a round brilliant (rejection sampling in its
        // box, kept when 1e-6 of its size inside every facet plane), random
        // directions: the exit agrees with the nearest triangle hit to
        // 1e-12 of the stone's size, on the same facet unless the ray
        // leaves within 1e-9 of an edge.
        let mesh = brilliant();
        let cell = ConvexInterior::new(&mesh).expect("a cut stone is convex");
        let (lo, hi) = mesh.bounds();
        let size = (hi - lo).length();
        let mut u = uniforms(7);
        let mut tested = 0;
        let mut same_facet = 0;
        while tested < 2000 {
            let o = lo + (hi - lo) * DVec3::new(u(), u(), u());
            let inside = mesh
                .facets
                .iter()
                .all(|f| f.normal.dot(o) - f.offset < -1e-6 * size);
            if !inside {
                continue;
            }
            let z = 2.0 * u() - 1.0;
            let phi = std::f64::consts::TAU * u();
            let r = (1.0 - z * z).sqrt();
            let d = DVec3::new(r * phi.cos(), r * phi.sin(), z) * (0.5 + u());
            let (t, facet) = brute_force(&mesh, o, d).expect("a ray from inside hits");
            let Exit::Facet {
                t: t2,
                facet: f2,
                prim,
            } = cell.exit(o, d)
            else {
                panic!("no exit from {o} along {d}");
            };
            assert!(
                ((t2 - t) * d.length()).abs() < 1e-12 * size,
                "t {t2} vs {t}"
            );
            assert_eq!(mesh.triangle_facet[prim as usize], f2);
            if f2 == facet {
                same_facet += 1;
            } else {
                let p = o + t2 * d;
                let n = &mesh.facets[facet as usize];
                assert!(
                    (n.normal.dot(p) - n.offset).abs() < 1e-9 * size,
                    "facet {f2} instead of {facet} away from their edge"
                );
            }
            tested += 1;
        }
        assert!(same_facet > 1990, "{same_facet} of 2000 on the same facet");
    }

    #[cfg(feature = "native")]
    #[test]
    fn the_avx_loop_gives_the_portable_loops_bits() {
        // Same lanes bit for bit (renders on machines with and without AVX
        // merge), and each lane's plane is the first one of that lane with
        // the lane's distance and speed.
        let mesh = brilliant();
        let cell = ConvexInterior::new(&mesh).unwrap();
        let (lo, hi) = mesh.bounds();
        let mut u = uniforms(3);
        let mut checked = 0;
        for _ in 0..3000 {
            let o = lo + (hi - lo) * DVec3::new(u(), u(), u());
            let d = DVec3::new(2.0 * u() - 1.0, 2.0 * u() - 1.0, 2.0 * u() - 1.0);
            let Some(avx) =
                crate::native::simd::nearest_crossing(&cell.blocks, o.to_array(), d.to_array())
            else {
                eprintln!("this CPU has no AVX: nothing to compare");
                return;
            };
            let (num, den, least) = cell.lanes(o, d);
            let bits = |a: [f64; LANES]| a.map(f64::to_bits);
            assert_eq!(bits(avx.num), bits(num));
            assert_eq!(bits(avx.den), bits(den));
            assert_eq!(bits(avx.least_inside), bits(least));
            for l in 0..LANES {
                let first = cell.blocks.iter().enumerate().find_map(|(k, b)| {
                    (approach(b, l, o, d) == (num[l], den[l])).then_some((k * LANES + l) as f64)
                });
                assert_eq!(avx.plane[l], first.unwrap_or(-1.0), "lane {l}");
            }
            checked += 1;
        }
        assert_eq!(checked, 3000);
    }

    #[test]
    fn an_origin_outside_or_on_a_plane_or_not_finite_is_left_to_the_backend() {
        let mesh = brilliant();
        let cell = ConvexInterior::new(&mesh).unwrap();
        let (lo, hi) = mesh.bounds();
        let centre = 0.5 * (lo + hi);
        let d = DVec3::new(0.3, -0.2, 0.9);
        assert!(matches!(cell.exit(centre, d), Exit::Facet { .. }));
        // Outside, beyond the highest point (the table), moving away or
        // back towards the stone.
        let above = DVec3::new(centre.x, centre.y, hi.z + 0.1);
        assert_eq!(cell.exit(above, d), Exit::Unsure);
        assert_eq!(cell.exit(above, -d), Exit::Unsure);
        // On a facet's plane.
        let f = &mesh.facets[0];
        let on = centre - (f.normal.dot(centre) - f.offset) * f.normal;
        assert_eq!(cell.exit(on, d), Exit::Unsure);
        for bad in [f64::NAN, f64::INFINITY] {
            assert_eq!(cell.exit(DVec3::splat(bad), d), Exit::Unsure);
            assert_eq!(cell.exit(centre, DVec3::new(bad, 0.0, 1.0)), Exit::Unsure);
        }
        assert_eq!(cell.exit(centre, DVec3::ZERO), Exit::Unsure);
    }

    #[test]
    fn a_mesh_with_a_dent_or_a_hole_takes_no_shortcut() {
        // A cube with one face replaced by a pyramid pointing inward.
        let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
        let sides = "f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
        let top = "f 5 6 7 8\n";
        let convex = parse_obj(&format!("{cube}{sides}{top}"), "cube.obj").unwrap();
        assert!(ConvexInterior::new(&convex).is_some());
        let dent = "v 0.5 0.5 0.6\nf 5 6 9\nf 6 7 9\nf 7 8 9\nf 8 5 9\n";
        let dented = parse_obj(&format!("{cube}{sides}{dent}"), "dent.obj").unwrap();
        assert!(ConvexInterior::new(&dented).is_none());
        // The cube without its top: every vertex inside every plane, but
        // open.
        let open = parse_obj(&format!("{cube}{sides}"), "open.obj").unwrap();
        assert!(ConvexInterior::new(&open).is_none());
        // A bump of 1e-6 (above the tolerance) is not convex either; one of
        // 1e-11 is.
        for (h, convex) in [(1e-6, false), (1e-11, true)] {
            let bump = format!(
                "v 0.5 0.5 {}\nf 5 6 9\nf 6 7 9\nf 7 8 9\nf 8 5 9\n",
                1.0 - h
            );
            let mesh = parse_obj(&format!("{cube}{sides}{bump}"), "bump.obj").unwrap();
            assert_eq!(ConvexInterior::new(&mesh).is_some(), convex, "dent {h}");
        }
    }

    #[test]
    fn the_shipped_gems_and_cuts_take_the_shortcut() {
        let gems = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems");
        for entry in std::fs::read_dir(&gems).unwrap() {
            let path = entry.unwrap().path();
            let mesh = match path.extension().and_then(|e| e.to_str()) {
                Some("obj") => load_obj(&path).unwrap(),
                Some("asc") => load_asc_stone(&path).unwrap().mesh,
                _ => continue,
            };
            assert!(ConvexInterior::new(&mesh).is_some(), "{}", path.display());
        }
        for name in ["round-brilliant", "oval", "princess", "emerald"] {
            let mesh = Cut::by_name(name).unwrap().mesh().unwrap();
            assert!(ConvexInterior::new(&mesh).is_some(), "{name}");
        }
    }
}
