//! The convex polyhedron bounded by a set of facet planes (the intersection
//! of their half-spaces), in f64, with exact planes kept per facet.
//!
//! A faceting design is a list of planes; the stone is what remains of a
//! block after every plane has cut it. That is how this module computes it:
//! a large box is clipped by one plane after another, keeping the polyhedron
//! as polygons that share vertices. Each clip classifies every vertex once
//! (inside, on the plane within a small tolerance, outside), so the faces a
//! cut touches always agree about which vertices survive; the new face is
//! closed from the boundary of the hole the cut left. Gem designs make many
//! planes meet at one point (eight pavilion mains at the culet); the
//! tolerance makes such a vertex one vertex, not a cloud of tiny edges.
//!
//! After the last cut every vertex is recomputed from the planes of the
//! faces that meet there (a least-squares solve, exact when three planes
//! meet). Edges shorter than the weld tolerance are contracted: their
//! vertices become the point solved from all of their planes, if that point
//! lies within the tolerance of every one of them; otherwise they stay apart
//! (a short edge), so no facet ever bends by more than the tolerance. If
//! welding would leave the surface inconsistent (short edges crowding), the
//! unwelded polyhedron is returned. Planes that end up without a facet are
//! reported with the reason ([`PlaneFate`]).

use super::mesh::{Mesh, Polygon, TopologyError};
use glam::DVec3;
use std::collections::HashMap;

/// The closed half-space `normal · x <= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    /// Outward normal of the facet (any length, not zero).
    pub normal: DVec3,
    /// Offset along the normal, in units of the normal's length.
    pub offset: f64,
}

impl HalfSpace {
    /// The half-space `normal · x <= offset`.
    pub fn new(normal: DVec3, offset: f64) -> HalfSpace {
        HalfSpace { normal, offset }
    }

    /// The same half-space with a unit normal.
    fn normalized(self) -> Option<HalfSpace> {
        let len = self.normal.length();
        (len > 0.0 && len.is_finite() && self.offset.is_finite()).then(|| HalfSpace {
            normal: self.normal / len,
            offset: self.offset / len,
        })
    }

    /// Signed distance of `p` from the plane (positive outside), for a unit
    /// normal.
    #[inline]
    fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// What became of one input plane.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneFate {
    /// The plane bounds a facet of the polyhedron.
    Facet,
    /// The plane never reached the stone: every vertex was strictly inside
    /// when it was applied, the nearest one `clearance` away.
    Redundant { clearance: f64 },
    /// The plane touched the stone only at a vertex or along an edge.
    Touching,
    /// The plane is (within tolerance) the plane of another input plane's
    /// facet, which keeps the facet.
    Coincident { with: usize },
    /// The plane cut a facet, but planes applied later removed all of it.
    CutAway,
    /// The plane's facet was narrower than the weld tolerance and vanished
    /// when its vertices were welded.
    Collapsed,
}

/// One face: the input plane it lies in and its vertices, counter-clockwise
/// seen from outside.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    pub plane: usize,
    pub vertices: Vec<u32>,
}

/// A convex polyhedron from [`intersect`].
#[derive(Clone, Debug)]
pub struct Polytope {
    pub positions: Vec<DVec3>,
    /// Faces in the order of their planes.
    pub faces: Vec<Face>,
    /// The unit-normal planes, as given but normalized.
    pub planes: Vec<HalfSpace>,
    /// What became of each input plane.
    pub fates: Vec<PlaneFate>,
    /// The largest distance of a vertex from the plane of a face it is on
    /// (after welding).
    pub max_plane_deviation: f64,
    /// The weld tolerance used.
    pub weld: f64,
}

/// A stone built from planes: its mesh (facets named), notes on planes
/// that have no facet (and anything else the builder tolerated), and the
/// intersection itself.
#[derive(Clone, Debug)]
pub struct Stone {
    pub mesh: Mesh,
    pub notes: Vec<String>,
    pub polytope: Polytope,
}

/// Why half-spaces did not give a polyhedron.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConvexError {
    #[error("plane {plane} is not usable (zero or non-finite normal, or non-finite offset)")]
    BadPlane { plane: usize },
    #[error("there are no planes")]
    NoPlanes,
    #[error("the planes leave nothing: plane {plane} removes all that the planes before it left")]
    Empty { plane: usize },
    #[error("the planes do not enclose a finite solid: it is open toward {direction}")]
    Unbounded { direction: DVec3 },
    #[error("welding vertices closer than {weld:e} would bend the facet of plane {plane} by {deviation:e}")]
    Bent {
        plane: usize,
        deviation: f64,
        weld: f64,
    },
    #[error(
        "the facets do not form a closed surface ({0}); the planes are numerically degenerate"
    )]
    Topology(TopologyError),
}

/// Options of [`intersect`].
#[derive(Clone, Copy, Debug)]
pub struct IntersectOptions {
    /// Vertices closer than this (absolute, in the planes' units) are
    /// merged into one.
    pub weld: f64,
}

/// The polyhedron `{x : n_i · x <= d_i for all i}`.
pub fn intersect(planes: &[HalfSpace], options: IntersectOptions) -> Result<Polytope, ConvexError> {
    if planes.is_empty() {
        return Err(ConvexError::NoPlanes);
    }
    let planes: Vec<HalfSpace> = planes
        .iter()
        .enumerate()
        .map(|(i, p)| p.normalized().ok_or(ConvexError::BadPlane { plane: i }))
        .collect::<Result<_, _>>()?;
    let weld = if options.weld.is_finite() && options.weld > 0.0 {
        options.weld
    } else {
        0.0
    };
    let scale = planes
        .iter()
        .map(|p| p.offset.abs())
        .fold(0.0, f64::max)
        .max(weld)
        .max(f64::MIN_POSITIVE);
    // A bounded solid may still reach far beyond its planes' offsets when
    // planes are nearly parallel: grow the starting box before giving up.
    let mut last = None;
    for factor in [1e1, 1e3, 1e5, 1e7] {
        let half = factor * scale.max(1e-300);
        let mut clip = Clipper::new(&planes, half, weld);
        let fates = clip.apply_all()?;
        if let Some(face) = clip.faces.iter().find(|f| f.plane >= planes.len()) {
            last = Some(clip.plane(face.plane).normal);
            continue;
        }
        return clip.finish(fates);
    }
    Err(ConvexError::Unbounded {
        direction: last.unwrap_or(DVec3::Z),
    })
}

/// Where a vertex is with respect to the plane being applied.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Side {
    In,
    On,
    Out,
}

/// The clipping state: a convex polyhedron as faces over shared vertices.
struct Clipper<'a> {
    planes: &'a [HalfSpace],
    /// The six planes of the starting box, numbered after the input planes.
    box_planes: [HalfSpace; 6],
    positions: Vec<DVec3>,
    faces: Vec<Face>,
    /// Classification tolerance: distances within it are "on" the plane.
    eps: f64,
    weld: f64,
}

impl<'a> Clipper<'a> {
    /// The cube `[-half, half]³` as six faces, counter-clockwise from outside.
    fn new(planes: &'a [HalfSpace], half: f64, weld: f64) -> Clipper<'a> {
        let positions = (0..8)
            .map(|i| {
                let s = |bit: usize| if i & bit != 0 { half } else { -half };
                DVec3::new(s(1), s(2), s(4))
            })
            .collect();
        let n = planes.len();
        let corners = [
            ([0, 2, 3, 1], -DVec3::Z),
            ([4, 5, 7, 6], DVec3::Z),
            ([0, 1, 5, 4], -DVec3::Y),
            ([2, 6, 7, 3], DVec3::Y),
            ([0, 4, 6, 2], -DVec3::X),
            ([1, 3, 7, 5], DVec3::X),
        ];
        let faces = corners
            .iter()
            .enumerate()
            .map(|(k, (v, _))| Face {
                plane: n + k,
                vertices: v.to_vec(),
            })
            .collect();
        let box_planes = corners.map(|(_, normal)| HalfSpace {
            normal,
            offset: half,
        });
        // Rounding in vertices built from the box grows with its size; the
        // tolerance stays well below the weld so that welding, not
        // classification, decides what merges.
        let eps = (1e-4 * weld).max(1e-13 * half);
        Clipper {
            planes,
            box_planes,
            positions,
            faces,
            eps,
            weld,
        }
    }

    fn plane(&self, id: usize) -> HalfSpace {
        if id < self.planes.len() {
            self.planes[id]
        } else {
            self.box_planes[id - self.planes.len()]
        }
    }

    /// Applies every input plane in order; returns each one's fate so far
    /// (`Facet` for those that cut).
    fn apply_all(&mut self) -> Result<Vec<PlaneFate>, ConvexError> {
        let mut fates = Vec::with_capacity(self.planes.len());
        for id in 0..self.planes.len() {
            fates.push(self.apply(id)?);
            if self.positions.len() > 4096 {
                self.compact();
            }
        }
        Ok(fates)
    }

    /// Drops vertices no face uses any more (cut away), renumbering the
    /// rest, when they outnumber the live ones.
    fn compact(&mut self) {
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut live = Vec::new();
        for face in &self.faces {
            for &v in &face.vertices {
                if remap[v as usize] == u32::MAX {
                    remap[v as usize] = live.len() as u32;
                    live.push(self.positions[v as usize]);
                }
            }
        }
        if 2 * live.len() > self.positions.len() {
            return;
        }
        for face in &mut self.faces {
            for v in &mut face.vertices {
                *v = remap[*v as usize];
            }
        }
        self.positions = live;
    }

    /// Clips the polyhedron by plane `id`, closing the hole with a new face.
    fn apply(&mut self, id: usize) -> Result<PlaneFate, ConvexError> {
        let plane = self.planes[id];
        let eps = self.eps;
        let distance: Vec<f64> = self.positions.iter().map(|&p| plane.distance(p)).collect();
        let side = |v: u32| {
            let d = distance[v as usize];
            if d > eps {
                Side::Out
            } else if d < -eps {
                Side::In
            } else {
                Side::On
            }
        };
        let used = self.faces.iter().flat_map(|f| f.vertices.iter().copied());
        let (mut any_in, mut any_out, mut on) = (false, false, 0usize);
        let mut clearance = f64::INFINITY;
        let mut seen = vec![false; self.positions.len()];
        for v in used {
            if std::mem::replace(&mut seen[v as usize], true) {
                continue;
            }
            match side(v) {
                Side::In => any_in = true,
                Side::Out => any_out = true,
                Side::On => on += 1,
            }
            clearance = clearance.min(-distance[v as usize]);
        }
        if !any_out {
            return Ok(if on == 0 {
                PlaneFate::Redundant { clearance }
            } else if let Some(with) = self.coplanar_face(&side) {
                PlaneFate::Coincident { with }
            } else {
                PlaneFate::Touching
            });
        }
        if !any_in {
            return Err(ConvexError::Empty { plane: id });
        }
        // Clip every face; an edge crossing the plane gets one new vertex,
        // shared by the two faces along it.
        let mut split: HashMap<(u32, u32), u32> = HashMap::new();
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        for face in &self.faces {
            if face.vertices.iter().all(|&v| side(v) != Side::Out) {
                faces.push(face.clone());
                continue;
            }
            let n = face.vertices.len();
            let mut kept = Vec::with_capacity(n + 1);
            let mut inside = false;
            for i in 0..n {
                let (a, b) = (face.vertices[i], face.vertices[(i + 1) % n]);
                let (sa, sb) = (side(a), side(b));
                if sa != Side::Out {
                    kept.push(a);
                    inside |= sa == Side::In;
                }
                if (sa == Side::In && sb == Side::Out) || (sa == Side::Out && sb == Side::In) {
                    let key = (a.min(b), a.max(b));
                    let v = *split.entry(key).or_insert_with(|| {
                        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
                        let (da, db) = (distance[a as usize], distance[b as usize]);
                        // The point of segment a–b where the distance is zero.
                        let t = da / (da - db);
                        self.positions.push(pa + t * (pb - pa));
                        (self.positions.len() - 1) as u32
                    });
                    kept.push(v);
                }
            }
            // A face left with no vertex strictly inside lies in the cutting
            // plane (or touches it): the new face replaces it.
            if inside && kept.len() >= 3 {
                faces.push(Face {
                    plane: face.plane,
                    vertices: kept,
                });
            }
        }
        // The hole's rim lies in the plane: only edges between vertices on
        // it (classified on, or just made) can bound it.
        let made = distance.len() as u32;
        let in_plane = |v: u32| v >= made || side(v) == Side::On;
        let cap = close_hole(&faces, &in_plane, &self.positions, plane.normal);
        if cap.len() >= 3 {
            faces.push(Face {
                plane: id,
                vertices: cap,
            });
        }
        self.faces = faces;
        Ok(PlaneFate::Facet)
    }

    /// An input plane whose face has every vertex on the plane being tested.
    fn coplanar_face(&self, side: &dyn Fn(u32) -> Side) -> Option<usize> {
        self.faces
            .iter()
            .find(|f| {
                f.plane < self.planes.len() && f.vertices.iter().all(|&v| side(v) == Side::On)
            })
            .map(|f| f.plane)
    }

    /// Recomputes vertices from their planes, welds, and builds the result.
    fn finish(mut self, fates: Vec<PlaneFate>) -> Result<Polytope, ConvexError> {
        // Keep only the vertices the faces use.
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        for face in &mut self.faces {
            for v in &mut face.vertices {
                if remap[*v as usize] == u32::MAX {
                    remap[*v as usize] = positions.len() as u32;
                    positions.push(self.positions[*v as usize]);
                }
                *v = remap[*v as usize];
            }
        }
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); positions.len()];
        for face in &self.faces {
            for &v in &face.vertices {
                incident[v as usize].push(face.plane);
            }
        }
        // Each vertex exactly where its planes meet.
        for (p, planes) in positions.iter_mut().zip(&incident) {
            *p = solve_point(planes.iter().map(|&i| self.planes[i]), *p);
        }
        match self.weld_and_build(&positions, &incident, fates.clone(), self.weld) {
            // Welding can pinch a surface where short edges crowd; the
            // unwelded polyhedron is still exact, with short edges.
            Err(ConvexError::Topology(_)) if self.weld > 0.0 => {
                self.weld_and_build(&positions, &incident, fates, 0.0)
            }
            result => result,
        }
    }

    /// Contracts every connected set of edges shorter than `weld` into one
    /// vertex where that vertex stays within `weld` of all their planes, drops
    /// faces left with fewer than three vertices, and checks the result.
    fn weld_and_build(
        &self,
        positions: &[DVec3],
        incident: &[Vec<usize>],
        mut fates: Vec<PlaneFate>,
        weld: f64,
    ) -> Result<Polytope, ConvexError> {
        let cluster = short_edge_clusters(&self.faces, positions, weld);
        let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
        for (v, &c) in cluster.iter().enumerate() {
            members.entry(c).or_default().push(v);
        }
        let mut id_of = vec![0u32; positions.len()];
        let mut welded = Vec::new();
        let mut roots: Vec<usize> = members.keys().copied().collect();
        roots.sort_unstable();
        for root in roots {
            let group = &members[&root];
            let centroid = group.iter().map(|&v| positions[v]).sum::<DVec3>() / group.len() as f64;
            let mut planes: Vec<usize> = group
                .iter()
                .flat_map(|&v| incident[v].iter().copied())
                .collect();
            planes.sort_unstable();
            planes.dedup();
            let merged = solve_point(planes.iter().map(|&i| self.planes[i]), centroid);
            let bend = planes
                .iter()
                .map(|&i| self.planes[i].distance(merged).abs())
                .fold(0.0, f64::max);
            if group.len() > 1 && bend <= weld {
                for &v in group {
                    id_of[v] = welded.len() as u32;
                }
                welded.push(merged);
            } else {
                // One vertex, or a cluster whose planes do not meet within
                // the tolerance: welding would bend a facet, so its short
                // edges stay (validation reports them).
                for &v in group {
                    id_of[v] = welded.len() as u32;
                    welded.push(positions[v]);
                }
            }
        }
        let mut faces = Vec::with_capacity(self.faces.len());
        for face in &self.faces {
            let mut vertices: Vec<u32> = Vec::with_capacity(face.vertices.len());
            for &v in &face.vertices {
                let w = id_of[v as usize];
                if vertices.last() != Some(&w) {
                    vertices.push(w);
                }
            }
            while vertices.len() > 1 && vertices.first() == vertices.last() {
                vertices.pop();
            }
            let mut distinct = vertices.clone();
            distinct.sort_unstable();
            distinct.dedup();
            if distinct.len() < 3 {
                fates[face.plane] = PlaneFate::Collapsed;
                continue;
            }
            faces.push(Face {
                plane: face.plane,
                vertices,
            });
        }
        // Planes that cut once but have no face now were cut away later.
        let mut has_face = vec![false; self.planes.len()];
        for f in &faces {
            has_face[f.plane] = true;
        }
        for (fate, &has) in fates.iter_mut().zip(&has_face) {
            if *fate == PlaneFate::Facet && !has {
                *fate = PlaneFate::CutAway;
            }
        }
        faces.sort_by_key(|f| f.plane);
        let mut max_dev: f64 = 0.0;
        for f in &faces {
            let plane = self.planes[f.plane];
            for &v in &f.vertices {
                let dev = plane.distance(welded[v as usize]).abs();
                if dev > weld.max(self.eps) {
                    return Err(ConvexError::Bent {
                        plane: f.plane,
                        deviation: dev,
                        weld,
                    });
                }
                max_dev = max_dev.max(dev);
            }
        }
        let polytope = Polytope {
            positions: welded,
            faces,
            planes: self.planes.to_vec(),
            fates,
            max_plane_deviation: max_dev,
            weld,
        };
        polytope
            .to_mesh(|_| None)
            .check_closed_and_oriented()
            .map_err(ConvexError::Topology)?;
        Ok(polytope)
    }
}

/// The face that closes the hole a cut left: the boundary edges a–b (edges
/// between vertices `in_plane`, used by one face only) traversed backwards,
/// chained into one loop. Falls back
/// to ordering the boundary vertices by angle about the plane normal if the
/// edges do not chain into a single loop.
fn close_hole(
    faces: &[Face],
    in_plane: &dyn Fn(u32) -> bool,
    positions: &[DVec3],
    normal: DVec3,
) -> Vec<u32> {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for f in faces {
        let n = f.vertices.len();
        for i in 0..n {
            let (a, b) = (f.vertices[i], f.vertices[(i + 1) % n]);
            if in_plane(a) && in_plane(b) {
                *directed.entry((a, b)).or_default() += 1;
            }
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut chainable = true;
    let mut boundary: Vec<(u32, u32)> = directed
        .keys()
        .filter(|&&(a, b)| !directed.contains_key(&(b, a)))
        .copied()
        .collect();
    boundary.sort_unstable();
    for &(a, b) in &boundary {
        // The cap walks b → a.
        if next.insert(b, a).is_some() {
            chainable = false;
        }
    }
    if boundary.is_empty() {
        return Vec::new();
    }
    if chainable {
        let start = boundary[0].1;
        let mut cap = vec![start];
        let mut v = start;
        while let Some(&w) = next.get(&v) {
            if w == start {
                break;
            }
            if cap.len() > boundary.len() {
                chainable = false;
                break;
            }
            cap.push(w);
            v = w;
        }
        if chainable && cap.len() == boundary.len() && next.get(&v) == Some(&start) {
            return cap;
        }
    }
    // Fallback: the hole is convex; sort its vertices by angle.
    let mut verts: Vec<u32> = boundary.iter().flat_map(|&(a, b)| [a, b]).collect();
    verts.sort_unstable();
    verts.dedup();
    let centroid = verts.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / verts.len() as f64;
    let (u, w) = normal.any_orthonormal_pair();
    let angle = |v: u32| {
        let d = positions[v as usize] - centroid;
        d.dot(w).atan2(d.dot(u))
    };
    verts.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    verts
}

/// The point nearest (least squares) to all the planes, pulled very weakly
/// toward `guess` so that the solve stays defined when fewer than three
/// independent planes meet.
fn solve_point(planes: impl Iterator<Item = HalfSpace>, guess: DVec3) -> DVec3 {
    // Solve for the step y = x − guess: rows n · y = d − n · guess, plus
    // Tikhonov rows s·y = 0 (weight s² = 1e-12). Householder QR, not the
    // normal equations, whose squared condition number would let nearly
    // coplanar normals put the point ~1e-8 off its planes.
    let s = 1e-6;
    let mut rows: Vec<[f64; 4]> = planes
        .map(|p| {
            let n = p.normal;
            [n.x, n.y, n.z, p.offset - n.dot(guess)]
        })
        .collect();
    rows.extend([[s, 0.0, 0.0, 0.0], [0.0, s, 0.0, 0.0], [0.0, 0.0, s, 0.0]]);
    match least_squares(&mut rows) {
        Some(y) if y.is_finite() => guess + y,
        _ => guess,
    }
}

/// Least-squares solution of the rows `[a0 a1 a2 | b]` (at least three) by
/// Householder QR; `None` if rank-deficient.
fn least_squares(rows: &mut [[f64; 4]]) -> Option<DVec3> {
    for j in 0..3 {
        let norm = rows[j..].iter().map(|r| r[j] * r[j]).sum::<f64>().sqrt();
        if !(norm > 0.0) {
            return None;
        }
        // Reflect column j below the diagonal onto ∓norm·e_j.
        let alpha = if rows[j][j] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = rows[j..].iter().map(|r| r[j]).collect();
        v[0] -= alpha;
        let vv: f64 = v.iter().map(|x| x * x).sum();
        if vv == 0.0 {
            continue;
        }
        for c in j..4 {
            let below = &mut rows[j..];
            let dot: f64 = below.iter().zip(&v).map(|(row, vi)| vi * row[c]).sum();
            let f = 2.0 * dot / vv;
            for (row, vi) in below.iter_mut().zip(&v) {
                row[c] -= f * vi;
            }
        }
    }
    // Back substitution in the 3×3 upper triangle.
    let mut x = [0.0; 3];
    for j in (0..3).rev() {
        let r = rows[j][j];
        if r == 0.0 {
            return None;
        }
        x[j] = (rows[j][3] - (j + 1..3).map(|k| rows[j][k] * x[k]).sum::<f64>()) / r;
    }
    Some(DVec3::from_array(x))
}

/// Cluster id (a representative vertex) of each vertex, joining the ends
/// of every face edge shorter than `tol` (transitively).
fn short_edge_clusters(faces: &[Face], points: &[DVec3], tol: f64) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..points.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for f in faces {
        let n = f.vertices.len();
        for k in 0..n {
            let (a, b) = (f.vertices[k] as usize, f.vertices[(k + 1) % n] as usize);
            if points[a].distance(points[b]) < tol {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    (0..points.len()).map(|i| root(&mut parent, i)).collect()
}

impl Polytope {
    /// The polyhedron as a [`Mesh`] whose facets carry their exact planes;
    /// `name(plane)` names each facet.
    pub fn to_mesh(&self, name: impl Fn(usize) -> Option<String>) -> Mesh {
        let polygons = self
            .faces
            .iter()
            .map(|f| Polygon {
                vertices: f.vertices.clone(),
                name: name(f.plane),
                line: None,
            })
            .collect();
        // The faces are convex, so a fan from the first vertex is exact.
        let mut mesh = match Mesh::from_convex_polygons(self.positions.clone(), polygons) {
            Ok(mesh) => mesh,
            // Every face has three distinct vertices on its plane, so
            // Newell's area vector is never zero; keep a mesh regardless.
            Err(_) => Mesh {
                positions: self.positions.clone(),
                facets: Vec::new(),
                triangles: Vec::new(),
                triangle_facet: Vec::new(),
                vertex_numbers: Vec::new(),
            },
        };
        for (facet, face) in mesh.facets.iter_mut().zip(&self.faces) {
            let plane = self.planes[face.plane];
            facet.normal = plane.normal;
            facet.offset = plane.offset;
        }
        mesh
    }

    /// One line per plane that has no facet, saying why; `describe(plane)`
    /// names a plane.
    pub fn fate_notes(&self, describe: impl Fn(usize) -> String) -> Vec<String> {
        self.fates
            .iter()
            .enumerate()
            .filter_map(|(i, fate)| {
                let why = match fate {
                    PlaneFate::Facet => return None,
                    PlaneFate::Redundant { clearance } => {
                        format!("never reaches the stone (misses it by {clearance:.3e})")
                    }
                    PlaneFate::Touching => "only touches the stone at a vertex or an edge".into(),
                    PlaneFate::Coincident { with } => {
                        format!("lies in the same plane as {}", describe(*with))
                    }
                    PlaneFate::CutAway => "is cut away entirely by facets cut after it".into(),
                    PlaneFate::Collapsed => format!(
                        "is narrower than the weld tolerance {:e} and was welded away",
                        self.weld
                    ),
                };
                Some(format!("{} {why}: no facet", describe(i)))
            })
            .collect()
    }

    /// Enclosed volume (divergence theorem over the faces).
    pub fn volume(&self) -> f64 {
        self.faces
            .iter()
            .map(|f| {
                let p = |i: usize| self.positions[f.vertices[i] as usize];
                (1..f.vertices.len() - 1)
                    .map(|i| p(0).dot(p(i).cross(p(i + 1))) / 6.0)
                    .sum::<f64>()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> IntersectOptions {
        IntersectOptions { weld: 1e-9 }
    }

    fn cube_planes(h: f64) -> Vec<HalfSpace> {
        [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ]
        .iter()
        .map(|&n| HalfSpace::new(n, h))
        .collect()
    }

    #[test]
    fn cube_from_six_planes() {
        let p = intersect(&cube_planes(0.5), opts()).unwrap();
        assert_eq!(p.faces.len(), 6);
        assert_eq!(p.positions.len(), 8);
        assert!((p.volume() - 1.0).abs() < 1e-14);
        assert!(p.fates.iter().all(|f| *f == PlaneFate::Facet));
    }

    #[test]
    fn octahedron_has_six_four_plane_vertices() {
        // |x|+|y|+|z| <= 1: eight planes, four meeting at each vertex.
        let mut planes = Vec::new();
        for i in 0..8 {
            let s = |b: usize| if i & b != 0 { -1.0 } else { 1.0 };
            planes.push(HalfSpace::new(DVec3::new(s(1), s(2), s(4)), 1.0));
        }
        let p = intersect(&planes, opts()).unwrap();
        assert_eq!(p.positions.len(), 6);
        assert_eq!(p.faces.len(), 8);
        assert!(p.faces.iter().all(|f| f.vertices.len() == 3));
        // Volume of the octahedron of "radius" 1: 4/3.
        assert!((p.volume() - 4.0 / 3.0).abs() < 1e-14);
    }

    #[test]
    fn fates_of_planes_without_facets() {
        let mut planes = cube_planes(0.5);
        planes.push(HalfSpace::new(DVec3::X, 2.0)); // far outside
        planes.push(HalfSpace::new(DVec3::new(1.0, 1.0, 0.0), 1.0)); // along an edge
        planes.push(HalfSpace::new(DVec3::Z, 0.5)); // the top again
        planes.push(HalfSpace::new(DVec3::new(1.0, 1.0, 1.0), 1.5 - 1e-10)); // a 1e-10 corner
        let p = intersect(&planes, IntersectOptions { weld: 1e-9 }).unwrap();
        assert_eq!(p.fates[6], PlaneFate::Redundant { clearance: 1.5 });
        assert_eq!(p.fates[7], PlaneFate::Touching);
        assert_eq!(p.fates[8], PlaneFate::Coincident { with: 4 });
        assert_eq!(p.fates[9], PlaneFate::Collapsed);
        assert_eq!(p.positions.len(), 8);
    }

    #[test]
    fn unbounded_and_empty_are_errors() {
        let mut open = cube_planes(0.5);
        open.remove(5); // no bottom
        match intersect(&open, opts()) {
            Err(ConvexError::Unbounded { direction }) => assert_eq!(direction, -DVec3::Z),
            other => panic!("{other:?}"),
        }
        let mut empty = cube_planes(0.5);
        empty.push(HalfSpace::new(-DVec3::X, -1.0)); // x >= 1
        assert_eq!(
            intersect(&empty, opts()).unwrap_err(),
            ConvexError::Empty { plane: 6 }
        );
        let bad = [HalfSpace::new(DVec3::ZERO, 1.0)];
        assert_eq!(
            intersect(&bad, opts()).unwrap_err(),
            ConvexError::BadPlane { plane: 0 }
        );
    }

    #[test]
    fn near_meeting_planes_weld_into_one_vertex() {
        // A square pyramid whose four faces miss a common apex by ~1e-8.
        let mut planes = vec![HalfSpace::new(-DVec3::Z, 0.0)];
        for (k, d) in [1.0, 1.0 + 1e-8, 1.0 - 1e-8, 1.0 + 2e-8].iter().enumerate() {
            let a = k as f64 * std::f64::consts::FRAC_PI_2;
            planes.push(HalfSpace::new(DVec3::new(a.cos(), a.sin(), 1.0), *d));
        }
        let p = intersect(&planes, IntersectOptions { weld: 1e-6 }).unwrap();
        assert_eq!(p.positions.len(), 5);
        assert_eq!(p.faces.len(), 5);
        assert!(p.max_plane_deviation < 1e-6);
        let fine = intersect(&planes, IntersectOptions { weld: 1e-12 }).unwrap();
        assert!(fine.positions.len() > 5);
    }
}
