//! Whether closed triangle meshes meet: two meshes that intersect, touch or
//! lie one inside the other, a mesh whose non-adjacent triangles intersect,
//! and whether a point is inside a closed mesh. All in f64.
//!
//! Triangle pairs are found by a bounding-box tree per mesh walked in pairs
//! (so two gems of 10 000 triangles cost milliseconds, not 10⁸ tests), and
//! each pair is decided by the separating-axis theorem: two triangles are
//! disjoint exactly when their projections onto one of 17 axes (the two
//! normals, the nine edge–edge cross products, the six in-plane edge
//! normals) are disjoint. A pair counts as meeting when no axis separates
//! it by more than a tolerance: a positive tolerance catches triangles that
//! touch or nearly do; a negative one demands a real crossing.

use super::Mesh;
use glam::DVec3;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    fn grow(self, p: DVec3) -> Aabb {
        Aabb {
            lo: self.lo.min(p),
            hi: self.hi.max(p),
        }
    }

    fn union(self, o: Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Whether the boxes come within `gap` of each other.
    fn near(&self, o: &Aabb, gap: f64) -> bool {
        (self.lo - gap).cmple(o.hi).all() && (o.lo - gap).cmple(self.hi).all()
    }
}

/// A node of a triangle tree: a box and either two children or a range of
/// the tree's triangle order.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Children (`left`, `left + 1`... stored as indices) or, for a leaf,
    /// `count > 0` triangles from `first`.
    first: u32,
    count: u32,
    left: u32,
    right: u32,
}

/// A bounding-box tree over one mesh's triangles (median splits).
struct Tree<'a> {
    mesh: &'a Mesh,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

const LEAF: usize = 4;

impl<'a> Tree<'a> {
    fn new(mesh: &'a Mesh) -> Tree<'a> {
        let mut order: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
        let boxes: Vec<Aabb> = mesh
            .triangles
            .iter()
            .map(|t| {
                t.iter()
                    .fold(Aabb::EMPTY, |b, &i| b.grow(mesh.positions[i as usize]))
            })
            .collect();
        let mut tree = Tree {
            mesh,
            nodes: Vec::with_capacity(2 * order.len() / LEAF + 1),
            order: Vec::new(),
        };
        if !order.is_empty() {
            let n = order.len();
            tree.build(&mut order, 0, n, &boxes);
        }
        tree.order = order;
        tree
    }

    fn build(&mut self, order: &mut [u32], first: usize, end: usize, boxes: &[Aabb]) -> u32 {
        let slice = &mut order[first..end];
        let bounds = slice
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
        let index = self.nodes.len() as u32;
        self.nodes.push(Node {
            bounds,
            first: first as u32,
            count: slice.len() as u32,
            left: 0,
            right: 0,
        });
        if slice.len() <= LEAF {
            return index;
        }
        let centre = |i: u32| {
            let b = boxes[i as usize];
            b.lo + b.hi
        };
        let extent = bounds.hi - bounds.lo;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = slice.len() / 2;
        slice.select_nth_unstable_by(mid, |&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]));
        let left = self.build(order, first, first + mid, boxes);
        let right = self.build(order, first + mid, end, boxes);
        let node = &mut self.nodes[index as usize];
        node.count = 0;
        node.left = left;
        node.right = right;
        index
    }

    fn corners(&self, t: u32) -> [DVec3; 3] {
        self.mesh.triangles[t as usize].map(|i| self.mesh.positions[i as usize])
    }

    /// Calls `f` with every pair of triangles (one of `self`, one of
    /// `other`) whose boxes come within `gap`; stops when `f` returns true
    /// and returns that pair.
    fn pairs(
        &self,
        other: &Tree<'_>,
        gap: f64,
        mut f: impl FnMut(u32, u32) -> bool,
    ) -> Option<(u32, u32)> {
        if self.nodes.is_empty() || other.nodes.is_empty() {
            return None;
        }
        let mut stack = vec![(0u32, 0u32)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (&self.nodes[a as usize], &other.nodes[b as usize]);
            if !na.bounds.near(&nb.bounds, gap) {
                continue;
            }
            match (na.count > 0, nb.count > 0) {
                (true, true) => {
                    for &ta in &self.order[na.first as usize..(na.first + na.count) as usize] {
                        for &tb in &other.order[nb.first as usize..(nb.first + nb.count) as usize] {
                            if f(ta, tb) {
                                return Some((ta, tb));
                            }
                        }
                    }
                }
                (false, true) => stack.extend([(na.left, b), (na.right, b)]),
                (true, false) => stack.extend([(a, nb.left), (a, nb.right)]),
                (false, false) => {
                    // Split the larger box.
                    let size = |n: &Node| (n.bounds.hi - n.bounds.lo).length_squared();
                    if size(na) >= size(nb) {
                        stack.extend([(na.left, b), (na.right, b)]);
                    } else {
                        stack.extend([(a, nb.left), (a, nb.right)]);
                    }
                }
            }
        }
        None
    }
}

/// Whether triangles `a` and `b` come within `tol` of each other by the
/// separating-axis theorem: false when some axis separates their
/// projections by more than `tol` (negative: they must cross by more than
/// `-tol` along every axis).
pub fn triangles_meet(a: &[DVec3; 3], b: &[DVec3; 3], tol: f64) -> bool {
    let ea = [a[1] - a[0], a[2] - a[1], a[0] - a[2]];
    let eb = [b[1] - b[0], b[2] - b[1], b[0] - b[2]];
    let na = ea[0].cross(ea[1]);
    let nb = eb[0].cross(eb[1]);
    let scale = ea
        .iter()
        .chain(&eb)
        .map(|e| e.length_squared())
        .fold(0.0, f64::max);
    let separates = |axis: DVec3| -> bool {
        let len2 = axis.length_squared();
        // Axes from (nearly) parallel edges carry no information.
        if !(len2 > 1e-24 * scale * scale) {
            return false;
        }
        let axis = axis / len2.sqrt();
        let (mut lo_a, mut hi_a) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in a {
            let d = p.dot(axis);
            lo_a = lo_a.min(d);
            hi_a = hi_a.max(d);
        }
        let (mut lo_b, mut hi_b) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in b {
            let d = p.dot(axis);
            lo_b = lo_b.min(d);
            hi_b = hi_b.max(d);
        }
        (lo_b - hi_a).max(lo_a - hi_b) > tol
    };
    if separates(na) || separates(nb) {
        return false;
    }
    for x in &ea {
        for y in &eb {
            if separates(x.cross(*y)) {
                return false;
            }
        }
    }
    // Coplanar (or nearly) triangles: the edge normals in each plane.
    for e in &ea {
        if separates(na.cross(*e)) {
            return false;
        }
    }
    for e in &eb {
        if separates(nb.cross(*e)) {
            return false;
        }
    }
    true
}

/// Largest side of a mesh's bounding box.
fn size(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).max_element()
}

/// Whether `p` is inside the closed mesh `mesh` (or on its surface, within
/// about 1e-9 of its size), by the parity of the crossings of rays from
/// `p`, in f64. A ray that passes within 1e-9 of an edge or a vertex is
/// replaced by one in another direction, so edges and vertices never
/// decide.
pub fn point_inside(mesh: &Mesh, p: DVec3) -> bool {
    let (lo, hi) = mesh.bounds();
    let s = size(mesh).max(f64::MIN_POSITIVE);
    if (p - hi).max_element() > 1e-9 * s || (lo - p).max_element() > 1e-9 * s {
        return false;
    }
    // Directions with no special relation to the axes or to each other.
    const DIRS: [[f64; 3]; 8] = [
        [0.5377, 0.1834, 0.8228],
        [-0.3129, 0.8632, -0.3961],
        [0.7013, -0.6143, 0.3504],
        [-0.1924, -0.4279, -0.8832],
        [0.9013, 0.3217, -0.2901],
        [-0.6671, 0.2103, 0.7147],
        [0.0911, -0.9452, 0.3133],
        [-0.4487, -0.3761, 0.8109],
    ];
    let eps = 1e-9;
    'dir: for d in DIRS {
        let d = DVec3::from_array(d).normalize();
        let mut crossings = 0u32;
        for t in &mesh.triangles {
            let [v0, v1, v2] = t.map(|i| mesh.positions[i as usize]);
            let e1 = v1 - v0;
            let e2 = v2 - v0;
            let pv = d.cross(e2);
            let det = e1.dot(pv);
            let area = e1.cross(e2).length();
            if !(area > 0.0) {
                continue; // a degenerate sliver: no surface of its own
            }
            let s0 = p - v0;
            // Distance of p from the triangle's plane, for "on the surface".
            let height = s0.dot(e1.cross(e2)) / area;
            if det.abs() <= 1e-12 * area {
                // The ray runs along the triangle's plane: if it lies in
                // it, another direction decides.
                if height.abs() <= eps * s {
                    continue 'dir;
                }
                continue;
            }
            let inv = 1.0 / det;
            let u = s0.dot(pv) * inv;
            let q = s0.cross(e1);
            let v = d.dot(q) * inv;
            let t = e2.dot(q) * inv;
            let w = 1.0 - u - v;
            // Barycentric margins in lengths: how far inside the triangle.
            let margin = eps * s * s / area;
            if u < -margin || v < -margin || w < -margin {
                continue;
            }
            if height.abs() <= eps * s {
                return true; // on the surface
            }
            if t <= 0.0 {
                continue; // behind p
            }
            if u <= margin || v <= margin || w <= margin {
                continue 'dir; // near an edge or vertex: undecided
            }
            crossings += 1;
        }
        return crossings % 2 == 1;
    }
    // Every direction grazed an edge: fall back on the first one's answer
    // by the winding number, which needs no choice of ray.
    winding_number(mesh, p).abs() > 0.5
}

/// The generalized winding number of a closed oriented mesh about `p`
/// (van Oosterom & Strackee's solid angle of each triangle over 4π): 1
/// inside, 0 outside.
fn winding_number(mesh: &Mesh, p: DVec3) -> f64 {
    let mut sum = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize] - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        sum += 2.0 * num.atan2(den);
    }
    sum / (4.0 * std::f64::consts::PI)
}

/// How two meshes meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Meeting {
    /// Triangle `0` of the first mesh and triangle `1` of the second
    /// intersect or come within the tolerance.
    Surfaces(u32, u32),
    /// The first mesh is inside the second.
    FirstInside,
    /// The second mesh is inside the first.
    SecondInside,
}

/// Whether two closed meshes overlap, touch (come within `tol`) or lie one
/// inside the other; `None` when they are apart.
pub fn meshes_meet(a: &Mesh, b: &Mesh, tol: f64) -> Option<Meeting> {
    let (alo, ahi) = a.bounds();
    let (blo, bhi) = b.bounds();
    let boxes = |lo: DVec3, hi: DVec3| Aabb { lo, hi };
    if !boxes(alo, ahi).near(&boxes(blo, bhi), tol) {
        return None;
    }
    let (ta, tb) = (Tree::new(a), Tree::new(b));
    if let Some((x, y)) = ta.pairs(&tb, tol, |x, y| {
        triangles_meet(&ta.corners(x), &tb.corners(y), tol)
    }) {
        return Some(Meeting::Surfaces(x, y));
    }
    // No surfaces meet: one is inside the other or they are apart.
    if let Some(&p) = a.positions.first() {
        if point_inside(b, p) {
            return Some(Meeting::FirstInside);
        }
    }
    if let Some(&p) = b.positions.first() {
        if point_inside(a, p) {
            return Some(Meeting::SecondInside);
        }
    }
    None
}

/// Two triangles of `mesh` that share no vertex (by index or position) and
/// cross each other by more than 1e-9 of the mesh's size, if any: the mesh
/// intersects itself. Triangles that share a vertex are not tested (a fold
/// through a shared vertex is not found).
pub fn self_intersection(mesh: &Mesh) -> Option<(u32, u32)> {
    let tree = Tree::new(mesh);
    let tol = -1e-9 * size(mesh);
    tree.pairs(&tree, 0.0, |x, y| {
        if x >= y {
            return false;
        }
        let (tx, ty) = (mesh.triangles[x as usize], mesh.triangles[y as usize]);
        if tx.iter().any(|i| ty.contains(i)) {
            return false;
        }
        let (a, b) = (tree.corners(x), tree.corners(y));
        if a.iter().any(|p| b.contains(p)) {
            return false;
        }
        triangles_meet(&a, &b, tol)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [DVec3; 3] {
        [a, b, c].map(DVec3::from_array)
    }

    #[test]
    fn crossing_touching_and_apart_triangles() {
        let flat = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let through = tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.25, 0.0]);
        assert!(triangles_meet(&flat, &through, 0.0));
        assert!(triangles_meet(&flat, &through, -1e-6));
        // Resting on the plane at one vertex: touches, does not cross.
        let resting = tri([0.2, 0.2, 0.0], [0.2, 0.3, 1.0], [0.3, 0.2, 1.0]);
        assert!(triangles_meet(&flat, &resting, 1e-12));
        assert!(!triangles_meet(&flat, &resting, -1e-9));
        // Above by 1e-3.
        let above = tri([0.2, 0.2, 1e-3], [0.2, 0.3, 1.0], [0.3, 0.2, 1.0]);
        assert!(!triangles_meet(&flat, &above, 1e-4));
        assert!(triangles_meet(&flat, &above, 1e-2));
        // Coplanar: overlapping and side by side.
        let over = tri([0.5, 0.0, 0.0], [1.5, 0.0, 0.0], [0.5, 1.0, 0.0]);
        assert!(triangles_meet(&flat, &over, 1e-12));
        let beside = tri([1.1, 0.0, 0.0], [2.0, 0.0, 0.0], [1.1, 1.0, 0.0]);
        assert!(!triangles_meet(&flat, &beside, 1e-3));
        // Near miss across the hypotenuse: SAT's in-plane axis separates.
        let across = tri([0.6, 0.6, -1.0], [0.6, 0.6, 1.0], [0.9, 0.9, 0.0]);
        assert!(!triangles_meet(&flat, &across, 1e-3));
    }

    fn cube(lo: f64, hi: f64) -> Mesh {
        let text = {
            let mut s = String::new();
            for i in 0..8 {
                let c = |b: usize| if i & b == 0 { lo } else { hi };
                s += &format!("v {} {} {}\n", c(1), c(2), c(4));
            }
            for f in [
                [1, 3, 4, 2],
                [5, 6, 8, 7],
                [1, 2, 6, 5],
                [3, 7, 8, 4],
                [1, 5, 7, 3],
                [2, 4, 8, 6],
            ] {
                s += &format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]);
            }
            s
        };
        crate::geometry::parse_obj(&text, "cube.obj").unwrap()
    }

    #[test]
    fn points_inside_outside_and_on_edges() {
        let m = cube(-1.0, 1.0);
        assert!(point_inside(&m, DVec3::ZERO));
        assert!(point_inside(&m, DVec3::new(0.99, -0.99, 0.5)));
        assert!(!point_inside(&m, DVec3::new(1.01, 0.0, 0.0)));
        assert!(!point_inside(&m, DVec3::new(0.0, 0.0, 5.0)));
        // On a face, an edge, a vertex: on the surface counts as inside.
        assert!(point_inside(&m, DVec3::new(1.0, 0.2, 0.3)));
        assert!(point_inside(&m, DVec3::new(1.0, 1.0, 0.3)));
        assert!(point_inside(&m, DVec3::ONE));
        // Rays from these points run through the cube's diagonals and
        // edges in axis directions; the answer must not care.
        for x in [-0.5, 0.0, 0.5] {
            assert!(point_inside(&m, DVec3::new(x, x, x)));
            assert!(!point_inside(&m, DVec3::new(x, x, 1.5)));
        }
        assert!((winding_number(&m, DVec3::ZERO) - 1.0).abs() < 1e-12);
        assert!(winding_number(&m, DVec3::splat(3.0)).abs() < 1e-12);
    }

    #[test]
    fn meshes_overlapping_touching_nested_and_apart() {
        let a = cube(0.0, 1.0);
        let shifted = |m: &Mesh, d: DVec3| m.transformed(&glam::DAffine3::from_translation(d));
        let overlap = shifted(&a, DVec3::new(0.5, 0.3, 0.2));
        assert!(matches!(
            meshes_meet(&a, &overlap, 1e-9),
            Some(Meeting::Surfaces(..))
        ));
        let touching = shifted(&a, DVec3::new(1.0, 0.3, 0.2));
        assert!(matches!(
            meshes_meet(&a, &touching, 1e-9),
            Some(Meeting::Surfaces(..))
        ));
        let apart = shifted(&a, DVec3::new(1.001, 0.3, 0.2));
        assert_eq!(meshes_meet(&a, &apart, 1e-5), None);
        let inner = cube(0.25, 0.75);
        assert_eq!(meshes_meet(&inner, &a, 1e-9), Some(Meeting::FirstInside));
        assert_eq!(meshes_meet(&a, &inner, 1e-9), Some(Meeting::SecondInside));
    }

    #[test]
    fn a_closed_cube_does_not_intersect_itself() {
        assert_eq!(self_intersection(&cube(-1.0, 1.0)), None);
    }
}
