//! Closest-hit traversal of the wide BVH for one ray: a stack of nodes
//! still to visit, children visited nearest first, the robust slab test of
//! Ize ("Robust BVH Ray Traversal", JCGT 2(2), 2013) on all children of a
//! node at once.

use super::lanes::{F8, M8};
use super::ray::{PreparedRay, FAR_FACTOR};
use super::sah::MAX_DEPTH;
use super::triangle::LaneHit;
use super::wide::{ChildRef, Node, WideBvh, WIDTH};

/// Each visited node leaves at most `WIDTH − 1` siblings on the stack, so a
/// tree `depth` nodes deep needs this many entries.
pub(super) const fn stack_entries(depth: usize) -> usize {
    (WIDTH - 1) * depth + 1
}

/// Stack sizes the traversal is compiled for. Safe Rust must initialize
/// the stack of every ray, so a small tree gets a small stack (zeroing the
/// largest one would cost more than tracing a ray through a gem).
pub(super) const STACK_SIZES: [usize; 3] = [
    stack_entries(4),
    stack_entries(12),
    stack_entries(MAX_DEPTH),
];

/// The closest hit: the packet index and the lane hit within it.
#[inline]
pub(super) fn closest_hit<C: Counter>(
    bvh: &WideBvh,
    ray: &PreparedRay,
    counter: &mut C,
) -> Option<(usize, LaneHit)> {
    let needed = stack_entries(bvh.depth);
    if needed <= STACK_SIZES[0] {
        closest_hit_with::<{ STACK_SIZES[0] }, C>(bvh, ray, counter)
    } else if needed <= STACK_SIZES[1] {
        closest_hit_with::<{ STACK_SIZES[1] }, C>(bvh, ray, counter)
    } else {
        closest_hit_with::<{ STACK_SIZES[2] }, C>(bvh, ray, counter)
    }
}

impl Node {
    /// Entry distances of the ray into the child boxes, and which
    /// boxes it meets within `[ray.tmin, t_far]` (slab test; NaN from
    /// `0 · ∞`, a ray in a slab's plane, is ignored, which keeps the box).
    #[inline(always)]
    fn intersect(&self, ray: &PreparedRay, t_far: f32) -> (F8, M8) {
        let slab = |axis: usize| {
            let bounds = &self.bounds[axis];
            let near = F8::load(&bounds[ray.enters_at_max[axis] as usize]);
            let far = F8::load(&bounds[!ray.enters_at_max[axis] as usize]);
            let (o, inv) = (ray.org[axis], ray.inv_dir[axis]);
            ((near - o) * inv, (far - o) * inv)
        };
        let (nx, fx) = slab(0);
        let (ny, fy) = slab(1);
        let (nz, fz) = slab(2);
        let t_near = nx.max_or(ny.max_or(nz.max_or(F8::splat(ray.tmin))));
        let t_exit = fx.min_or(fy.min_or(fz.min_or(F8::splat(t_far))));
        (t_near, t_near.le(t_exit * FAR_FACTOR))
    }
}

/// What a traversal did, for tuning and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounts {
    /// Nodes whose children's boxes were tested.
    pub nodes: u64,
    /// Triangle packets tested.
    pub packets: u64,
}

/// Counts traversal steps; `()` counts nothing and costs nothing.
pub(super) trait Counter {
    fn node(&mut self);
    fn packet(&mut self);
}

impl Counter for () {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn packet(&mut self) {}
}

impl Counter for TraversalCounts {
    fn node(&mut self) {
        self.nodes += 1;
    }
    fn packet(&mut self) {
        self.packets += 1;
    }
}

/// [`closest_hit`] with a stack of `N` entries.
#[inline(always)]
fn closest_hit_with<const N: usize, C: Counter>(
    bvh: &WideBvh,
    ray: &PreparedRay,
    counter: &mut C,
) -> Option<(usize, LaneHit)> {
    let mut stack = [(0u32, 0f32); N];
    let mut sp = 0;
    let mut current = 0u32; // the root node
    let mut t_best = ray.tmax;
    let mut best = None;
    loop {
        if current & ChildRef::LEAF != 0 {
            for p in ChildRef::packets(current) {
                counter.packet();
                if let Some(hit) = bvh.packets[p].intersect(ray, t_best) {
                    t_best = hit.t;
                    best = Some((p, hit));
                }
            }
        } else {
            counter.node();
            let node = &bvh.nodes[current as usize];
            let (t_near, hit) = node.intersect(ray, t_best);
            let mut mask = hit.bits();
            if mask != 0 {
                let first = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if mask == 0 {
                    current = node.children[first];
                    continue;
                }
                let second = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if mask == 0 {
                    let (near, far) = if t_near.lane(first) <= t_near.lane(second) {
                        (first, second)
                    } else {
                        (second, first)
                    };
                    stack[sp] = (node.children[far], t_near.lane(far));
                    sp += 1;
                    current = node.children[near];
                    continue;
                }
                // Three or more children: push them all, sort the pushed
                // entries farthest first, continue with the nearest.
                let base = sp;
                for lane in [first, second] {
                    stack[sp] = (node.children[lane], t_near.lane(lane));
                    sp += 1;
                }
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    stack[sp] = (node.children[lane], t_near.lane(lane));
                    sp += 1;
                }
                let pushed = &mut stack[base..sp];
                for i in 1..pushed.len() {
                    let mut j = i;
                    while j > 0 && pushed[j - 1].1 < pushed[j].1 {
                        pushed.swap(j - 1, j);
                        j -= 1;
                    }
                }
                sp -= 1;
                current = stack[sp].0;
                continue;
            }
        }
        // Pop the next node the ray may still reach before its best hit.
        loop {
            if sp == 0 {
                return best;
            }
            sp -= 1;
            let (child, t_near) = stack[sp];
            if t_near <= t_best * FAR_FACTOR {
                current = child;
                break;
            }
        }
    }
}
