//! A binary BVH over triangle bounding boxes by binned SAH (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", IEEE Symposium on
//! Interactive Ray Tracing 2007), built in parallel with rayon: large nodes
//! bin their primitives in parallel, and the two subtrees of every large
//! node are built at the same time.
//!
//! The tree goes down to leaves of at most one packet (four triangles, the
//! triangle test's width): which subtrees become leaves of the wide tree is
//! decided later, by the SAH of the wide tree (see `wide`). The surface
//! area heuristic here counts primitives in packets of four, as one to four
//! triangles cost one packet test.

use super::triangle::LANES;
use rayon::prelude::*;

/// An axis-aligned box in f32 (boxes of f32 vertices are exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Aabb {
    pub lo: [f32; 3],
    pub hi: [f32; 3],
}

impl Aabb {
    /// The empty box: `lo = +∞`, `hi = −∞`, so that every ray misses it and
    /// growing it by anything gives that thing.
    pub const EMPTY: Aabb = Aabb {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    pub fn of_points(points: &[[f32; 3]]) -> Aabb {
        points
            .iter()
            .fold(Aabb::EMPTY, |b, p| b.union(&Aabb { lo: *p, hi: *p }))
    }

    #[inline]
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            lo: [0, 1, 2].map(|a| self.lo[a].min(o.lo[a])),
            hi: [0, 1, 2].map(|a| self.hi[a].max(o.hi[a])),
        }
    }

    pub fn center(&self) -> [f32; 3] {
        [0, 1, 2].map(|a| 0.5 * self.lo[a] + 0.5 * self.hi[a])
    }

    pub fn is_empty(&self) -> bool {
        (0..3).any(|a| !(self.lo[a] <= self.hi[a]))
    }

    /// Half the surface area, in f64 so that no scale overflows; 0 for the
    /// empty box.
    pub fn half_area(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let e = [0, 1, 2].map(|a| self.hi[a] as f64 - self.lo[a] as f64);
        e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
    }
}

/// A node of the binary tree: its primitives are `order[first..first +
/// count]` (a subtree's primitives are contiguous), and it is a leaf when it
/// has no children.
#[derive(Debug)]
pub(super) struct BinaryNode {
    pub bounds: Aabb,
    pub first: usize,
    pub count: usize,
    pub children: Option<Box<[BinaryNode; 2]>>,
}

/// Tuning of the binary builder.
#[derive(Clone, Copy, Debug)]
pub(super) struct SahConfig {
    /// Bins per axis (at most [`MAX_BINS`]).
    pub bins: usize,
}

/// Depth after which splits stop following the SAH and halve the node
/// (object median), so that the depth stays below [`MAX_DEPTH`] whatever
/// the input (the traversal's stack is sized from it).
const SAH_DEPTH_LIMIT: usize = 48;

/// Bound on the depth of the binary tree (and so of the 4-wide tree made
/// from it): SAH splits up to [`SAH_DEPTH_LIMIT`], then at most 32 halvings.
pub(super) const MAX_DEPTH: usize = SAH_DEPTH_LIMIT + 33;

/// Nodes with more primitives than this are binned and split in parallel.
const PARALLEL_THRESHOLD: usize = 4096;

fn packets(n: usize) -> f64 {
    n.div_ceil(LANES) as f64
}

/// The primitives as the builder sees them: one box and one centroid each.
pub(super) struct Primitives<'a> {
    pub boxes: &'a [Aabb],
    pub centroids: &'a [[f32; 3]],
}

/// Builds the tree. Returns the root and the primitive order the leaves'
/// ranges refer to.
pub(super) fn build(prims: &Primitives<'_>, config: &SahConfig) -> (BinaryNode, Vec<u32>) {
    let mut order: Vec<u32> = (0..prims.boxes.len() as u32).collect();
    let root = build_node(prims, config, &mut order, 0, 0);
    (root, order)
}

/// Bounds and centroid bounds of a range of primitives.
fn range_bounds(prims: &Primitives<'_>, order: &[u32]) -> (Aabb, Aabb) {
    let one = |&i: &u32| {
        let c = prims.centroids[i as usize];
        (prims.boxes[i as usize], Aabb { lo: c, hi: c })
    };
    let merge = |a: (Aabb, Aabb), b: (Aabb, Aabb)| (a.0.union(&b.0), a.1.union(&b.1));
    if order.len() > PARALLEL_THRESHOLD {
        order
            .par_iter()
            .with_min_len(1024)
            .map(one)
            .reduce(|| (Aabb::EMPTY, Aabb::EMPTY), merge)
    } else {
        order
            .iter()
            .map(one)
            .fold((Aabb::EMPTY, Aabb::EMPTY), merge)
    }
}

/// Maps a centroid coordinate to its bin: `k` bins over `[lo, lo + extent]`.
#[derive(Clone, Copy)]
struct Binning {
    axis: usize,
    lo: f32,
    scale: f32,
    bins: usize,
}

impl Binning {
    #[inline]
    fn bin(&self, c: &[f32; 3]) -> usize {
        // A float-to-int cast saturates (NaN → 0), so this never panics.
        (((c[self.axis] - self.lo) * self.scale) as usize).min(self.bins - 1)
    }
}

/// Most bins per axis the builder supports.
pub(super) const MAX_BINS: usize = 32;

/// Per-bin counts and bounds along one axis (the first `bins` used).
#[derive(Clone)]
struct Bins {
    count: [usize; MAX_BINS],
    bounds: [Aabb; MAX_BINS],
}

impl Bins {
    fn new() -> Bins {
        Bins {
            count: [0; MAX_BINS],
            bounds: [Aabb::EMPTY; MAX_BINS],
        }
    }

    #[inline]
    fn add(&mut self, prims: &Primitives<'_>, binning: &Binning, i: u32) {
        let b = binning.bin(&prims.centroids[i as usize]);
        self.count[b] += 1;
        self.bounds[b] = self.bounds[b].union(&prims.boxes[i as usize]);
    }

    fn merge(mut self, o: Bins) -> Bins {
        for b in 0..MAX_BINS {
            self.count[b] += o.count[b];
            self.bounds[b] = self.bounds[b].union(&o.bounds[b]);
        }
        self
    }
}

/// The best SAH split: its binning, the first bin of the right side, and
/// its cost relative to a packet test over the parent's area.
struct Split {
    binning: Binning,
    first_right_bin: usize,
    cost: f64,
}

fn best_split(
    prims: &Primitives<'_>,
    config: &SahConfig,
    order: &[u32],
    centroid_bounds: &Aabb,
    parent_area: f64,
) -> Option<Split> {
    let k = config.bins.clamp(2, MAX_BINS);
    let mut best: Option<Split> = None;
    for axis in 0..3 {
        let extent = centroid_bounds.hi[axis] - centroid_bounds.lo[axis];
        if !(extent > 0.0) {
            continue;
        }
        let binning = Binning {
            axis,
            lo: centroid_bounds.lo[axis],
            scale: (k as f64 / extent as f64) as f32,
            bins: k,
        };
        let bins = if order.len() > PARALLEL_THRESHOLD {
            order
                .par_iter()
                .with_min_len(1024)
                .fold(Bins::new, |mut b, &i| {
                    b.add(prims, &binning, i);
                    b
                })
                .reduce(Bins::new, Bins::merge)
        } else {
            let mut b = Bins::new();
            for &i in order.iter() {
                b.add(prims, &binning, i);
            }
            b
        };
        // Sweep from the right: area and count of bins [b, k).
        let mut right_area = [0.0; MAX_BINS];
        let mut right_count = [0usize; MAX_BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for b in (1..k).rev() {
            acc = acc.union(&bins.bounds[b]);
            n += bins.count[b];
            right_area[b] = acc.half_area();
            right_count[b] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for b in 1..k {
            acc = acc.union(&bins.bounds[b - 1]);
            n += bins.count[b - 1];
            if n == 0 || right_count[b] == 0 {
                continue;
            }
            let cost = (acc.half_area() * packets(n) + right_area[b] * packets(right_count[b]))
                / parent_area;
            if best.as_ref().is_none_or(|s| cost < s.cost) {
                best = Some(Split {
                    binning,
                    first_right_bin: b,
                    cost,
                });
            }
        }
    }
    best
}

/// Moves the primitives for which `left` holds to the front; returns how
/// many there are.
fn partition(order: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..order.len() {
        if left(order[i]) {
            order.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

fn build_node(
    prims: &Primitives<'_>,
    config: &SahConfig,
    order: &mut [u32],
    first: usize,
    depth: usize,
) -> BinaryNode {
    let n = order.len();
    let (bounds, centroid_bounds) = range_bounds(prims, order);
    let leaf = BinaryNode {
        bounds,
        first,
        count: n,
        children: None,
    };
    if n <= LANES {
        return leaf;
    }
    let area = bounds.half_area();
    let split = if depth < SAH_DEPTH_LIMIT && area > 0.0 {
        best_split(prims, config, order, &centroid_bounds, area)
    } else {
        None
    };
    let mid = match split {
        Some(Split {
            binning,
            first_right_bin,
            ..
        }) => partition(order, |i| {
            binning.bin(&prims.centroids[i as usize]) < first_right_bin
        }),
        None => {
            // No SAH split (all centroids equal, a flat node, or too deep):
            // the object median on the widest centroid axis, which always
            // halves the node.
            let axis = (0..3)
                .max_by(|&a, &b| {
                    let ea = centroid_bounds.hi[a] - centroid_bounds.lo[a];
                    let eb = centroid_bounds.hi[b] - centroid_bounds.lo[b];
                    ea.total_cmp(&eb)
                })
                .unwrap_or(0);
            let mid = n / 2;
            order.select_nth_unstable_by(mid, |&a, &b| {
                prims.centroids[a as usize][axis].total_cmp(&prims.centroids[b as usize][axis])
            });
            mid
        }
    };
    debug_assert!(mid > 0 && mid < n);
    let (left, right) = order.split_at_mut(mid);
    let (l, r) = if n > PARALLEL_THRESHOLD {
        rayon::join(
            || build_node(prims, config, left, first, depth + 1),
            || build_node(prims, config, right, first + mid, depth + 1),
        )
    } else {
        (
            build_node(prims, config, left, first, depth + 1),
            build_node(prims, config, right, first + mid, depth + 1),
        )
    };
    BinaryNode {
        bounds,
        first,
        count: n,
        children: Some(Box::new([l, r])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(node: &BinaryNode, order: &[u32], prims: &Primitives<'_>, depth: usize) -> usize {
        assert!(depth <= MAX_DEPTH);
        match &node.children {
            None => {
                for &i in &order[node.first..node.first + node.count] {
                    let b = prims.boxes[i as usize];
                    assert_eq!(
                        node.bounds.union(&b),
                        node.bounds,
                        "leaf box must contain its boxes"
                    );
                }
                node.count
            }
            Some(children) => {
                assert_eq!(children[0].first, node.first);
                assert_eq!(children[1].first, node.first + children[0].count);
                for c in children.iter() {
                    assert_eq!(node.bounds.union(&c.bounds), node.bounds);
                }
                let n = children
                    .iter()
                    .map(|c| check(c, order, prims, depth + 1))
                    .sum();
                assert_eq!(n, node.count);
                n
            }
        }
    }

    fn boxes_at(points: &[[f32; 3]]) -> (Vec<Aabb>, Vec<[f32; 3]>) {
        let boxes: Vec<Aabb> = points
            .iter()
            .map(|p| Aabb::of_points(&[*p, [p[0] + 0.5, p[1] + 0.25, p[2]]]))
            .collect();
        let centroids = boxes.iter().map(Aabb::center).collect();
        (boxes, centroids)
    }

    #[test]
    fn every_primitive_is_in_exactly_one_leaf() {
        let points: Vec<[f32; 3]> = (0..20_000)
            .map(|i| {
                let f = i as f32;
                [
                    (f * 0.618).fract() * 100.0,
                    (f * 0.414).fract() * 50.0,
                    (f * 0.732).fract(),
                ]
            })
            .collect();
        let (boxes, centroids) = boxes_at(&points);
        let prims = Primitives {
            boxes: &boxes,
            centroids: &centroids,
        };
        let (root, order) = build(&prims, &SahConfig { bins: 16 });
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert!(sorted.iter().enumerate().all(|(i, &j)| i as u32 == j));
        assert_eq!(check(&root, &order, &prims, 0), points.len());
    }

    #[test]
    fn identical_primitives_still_split_into_one_packet_leaves() {
        // Equal centroids leave the SAH nothing to bin: object medians.
        let points = vec![[1.0f32, 2.0, 3.0]; 1000];
        let (boxes, centroids) = boxes_at(&points);
        let prims = Primitives {
            boxes: &boxes,
            centroids: &centroids,
        };
        let (root, order) = build(&prims, &SahConfig { bins: 16 });
        assert_eq!(check(&root, &order, &prims, 0), 1000);
        fn max_leaf(n: &BinaryNode) -> usize {
            match &n.children {
                None => n.count,
                Some(c) => max_leaf(&c[0]).max(max_leaf(&c[1])),
            }
        }
        assert!(max_leaf(&root) <= LANES);
    }

    #[test]
    fn half_area_of_empty_and_flat_boxes() {
        assert_eq!(Aabb::EMPTY.half_area(), 0.0);
        let flat = Aabb::of_points(&[[0.0, 0.0, 0.0], [2.0, 3.0, 0.0]]);
        assert_eq!(flat.half_area(), 6.0);
    }
}
