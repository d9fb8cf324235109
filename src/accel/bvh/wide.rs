//! The wide BVH the traversal reads: each node holds the boxes of up to
//! [`WIDTH`] children in structure-of-arrays form (two SSE registers per
//! bound), each leaf a run of triangle packets.
//!
//! It is made from the binary SAH tree by the dynamic programme of Ylitie,
//! Karras & Laine ("Efficient Incoherent Ray Traversal on GPUs Through
//! Compressed Wide BVHs", HPG 2017, §4.1): for every binary node and every
//! number of slots `i ≤ WIDTH`, the least SAH cost of representing its
//! subtree as at most `i` children of a wide node, where a subtree may
//! become one leaf (all its triangles), one wide node, or hand its slots
//! down to its two children. Unlike pulling up grandchildren greedily, this
//! fills nodes (eight children, not four on average) and merges small
//! subtrees into leaves where the SAH says so.

use super::sah::{Aabb, BinaryNode};
use super::triangle::{Tri4, LANES};

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// Tuning of the wide tree's SAH.
#[derive(Clone, Copy, Debug)]
pub(super) struct WideConfig {
    /// Cost of testing a node's children's boxes, relative to one packet
    /// test.
    pub node_cost: f64,
    /// Most packets in one leaf (at most [`ChildRef::MAX_PACKETS`]); the
    /// SAH decides below that.
    pub max_leaf_packets: usize,
}

/// A node: child boxes and child references (256 bytes for eight children,
/// four cache lines, fetched together).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Node {
    /// `bounds[axis][0 = min, 1 = max][child]`. Unused slots hold the empty
    /// box, which every ray misses.
    pub bounds: [[[f32; WIDTH]; 2]; 3],
    /// Child references, see [`ChildRef`].
    pub children: [u32; WIDTH],
}

/// How a `u32` child reference is read: the top bit marks a leaf; a leaf
/// holds its first packet index in the low 27 bits and its packet count
/// minus one in the 4 bits above; an inner child is a node index.
pub(super) struct ChildRef;

impl ChildRef {
    pub const LEAF: u32 = 1 << 31;
    const COUNT_SHIFT: u32 = 27;
    const INDEX_MASK: u32 = (1 << Self::COUNT_SHIFT) - 1;
    /// Most packets a leaf can hold.
    pub const MAX_PACKETS: usize = 16;
    /// Most packets the whole structure can hold.
    pub const MAX_TOTAL_PACKETS: usize = 1 << Self::COUNT_SHIFT;

    fn leaf(first: usize, count: usize) -> u32 {
        debug_assert!((1..=Self::MAX_PACKETS).contains(&count));
        debug_assert!(first + count <= Self::MAX_TOTAL_PACKETS);
        Self::LEAF | ((count as u32 - 1) << Self::COUNT_SHIFT) | first as u32
    }

    /// The packet range of a leaf reference.
    #[inline(always)]
    pub fn packets(r: u32) -> std::ops::Range<usize> {
        let first = (r & Self::INDEX_MASK) as usize;
        let count = ((r >> Self::COUNT_SHIFT) & 0xF) as usize + 1;
        first..first + count
    }
}

impl Node {
    const EMPTY: Node = Node {
        bounds: [[[f32::INFINITY; WIDTH], [f32::NEG_INFINITY; WIDTH]]; 3],
        children: [0; WIDTH],
    };

    fn set_child(&mut self, slot: usize, bounds: &Aabb, child: u32) {
        for axis in 0..3 {
            self.bounds[axis][0][slot] = bounds.lo[axis];
            self.bounds[axis][1][slot] = bounds.hi[axis];
        }
        self.children[slot] = child;
    }
}

/// Nodes (the root first) and the packets their leaves point into.
pub(super) struct WideBvh {
    pub nodes: Vec<Node>,
    pub packets: Vec<Tri4>,
    /// Nodes on the longest path from the root to a leaf.
    pub depth: usize,
}

type Triangle = (u32, u32, [[f32; 3]; 3]);

/// The dynamic programme's table for one binary node.
struct Plan {
    /// `cost[i]`: least SAH cost (times the root's area, which cancels) of
    /// the subtree as at most `i` wide-node children, `i = 1..=WIDTH`.
    cost: [f64; WIDTH + 1],
    /// For `i ≥ 2`: 0 when `i − 1` slots do as well, else the number of
    /// slots given to the left child (the rest go to the right).
    split: [u8; WIDTH + 1],
    /// For one slot: whether the subtree is best a single leaf (else a
    /// wide node).
    as_leaf: bool,
    /// As a wide node: the slots given to the left child.
    node_split: usize,
    children: Option<Box<[Plan; 2]>>,
}

fn packets(count: usize) -> usize {
    count.div_ceil(LANES)
}

/// Fills the table bottom-up; large subtrees in parallel.
fn plan(node: &BinaryNode, config: &WideConfig) -> Plan {
    let area = node.bounds.half_area();
    let max_leaf = config.max_leaf_packets.clamp(1, ChildRef::MAX_PACKETS);
    let leaf_cost = if packets(node.count) <= max_leaf {
        area * packets(node.count) as f64
    } else {
        f64::INFINITY
    };
    let Some(children) = &node.children else {
        // A binary leaf (at most one packet: the binary build goes down to
        // packet size) is a leaf whatever the slots.
        return Plan {
            cost: [leaf_cost; WIDTH + 1],
            split: [0; WIDTH + 1],
            as_leaf: true,
            node_split: 0,
            children: None,
        };
    };
    let (l, r) = if node.count > 4096 {
        rayon::join(|| plan(&children[0], config), || plan(&children[1], config))
    } else {
        (plan(&children[0], config), plan(&children[1], config))
    };
    // Distribute i slots: k to the left, i − k to the right.
    let distribute = |i: usize| -> (f64, u8) {
        (1..i)
            .map(|k| (l.cost[k] + r.cost[i - k], k as u8))
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
    };
    let mut cost = [f64::INFINITY; WIDTH + 1];
    let mut split = [0u8; WIDTH + 1];
    let (below, node_split) = distribute(WIDTH);
    let internal_cost = config.node_cost * area + below;
    let as_leaf = leaf_cost <= internal_cost;
    cost[1] = leaf_cost.min(internal_cost);
    for i in 2..=WIDTH {
        let (d, k) = distribute(i);
        if d < cost[i - 1] {
            cost[i] = d;
            split[i] = k;
        } else {
            cost[i] = cost[i - 1];
        }
    }
    Plan {
        cost,
        split,
        as_leaf,
        node_split: node_split as usize,
        children: Some(Box::new([l, r])),
    }
}

/// Builds the wide tree from a binary tree whose ranges index `order`,
/// which indexes `triangles`.
pub(super) fn collapse(
    root: &BinaryNode,
    order: &[u32],
    triangles: &[Triangle],
    config: &WideConfig,
) -> WideBvh {
    let mut out = WideBvh {
        nodes: Vec::new(),
        packets: Vec::with_capacity(order.len().div_ceil(LANES)),
        depth: 1,
    };
    if root.children.is_none() {
        // Too small for a node: a root with one leaf child (or none).
        out.nodes.push(Node::EMPTY);
        if root.count > 0 {
            let leaf = out.leaf(root, order, triangles);
            out.nodes[0].set_child(0, &root.bounds, leaf);
        }
        return out;
    }
    let plan = plan(root, config);
    out.node(root, &plan, order, triangles, 1);
    out
}

/// The subtrees that take one slot each when `node` gets `slots` slots.
fn slot_items<'a>(
    node: &'a BinaryNode,
    plan: &'a Plan,
    slots: usize,
    items: &mut Vec<(&'a BinaryNode, &'a Plan)>,
) {
    let mut i = slots;
    while i > 1 && plan.split[i] == 0 {
        i -= 1;
    }
    match (&node.children, &plan.children) {
        (Some(c), Some(p)) if i > 1 => {
            let k = plan.split[i] as usize;
            slot_items(&c[0], &p[0], k, items);
            slot_items(&c[1], &p[1], i - k, items);
        }
        _ => items.push((node, plan)),
    }
}

impl WideBvh {
    /// Emits a wide node for `binary` (an inner node); returns its index.
    fn node(
        &mut self,
        binary: &BinaryNode,
        plan: &Plan,
        order: &[u32],
        triangles: &[Triangle],
        depth: usize,
    ) -> u32 {
        self.depth = self.depth.max(depth);
        let (Some(children), Some(plans)) = (&binary.children, &plan.children) else {
            unreachable!("a wide node comes from an inner binary node")
        };
        let mut items = Vec::with_capacity(WIDTH);
        let k = plan.node_split;
        slot_items(&children[0], &plans[0], k, &mut items);
        slot_items(&children[1], &plans[1], WIDTH - k, &mut items);
        debug_assert!(items.len() <= WIDTH);
        let index = self.nodes.len();
        self.nodes.push(Node::EMPTY);
        for (slot, (kid, kid_plan)) in items.into_iter().enumerate() {
            let child = if kid_plan.as_leaf {
                self.leaf(kid, order, triangles)
            } else {
                self.node(kid, kid_plan, order, triangles, depth + 1)
            };
            self.nodes[index].set_child(slot, &kid.bounds, child);
        }
        index as u32
    }

    /// Packs a subtree's triangles into one leaf; returns its reference.
    fn leaf(&mut self, binary: &BinaryNode, order: &[u32], triangles: &[Triangle]) -> u32 {
        let start = self.packets.len();
        let tris: Vec<Triangle> = order[binary.first..binary.first + binary.count]
            .iter()
            .map(|&i| triangles[i as usize])
            .collect();
        for chunk in tris.chunks(LANES) {
            self.packets.push(Tri4::pack(chunk));
        }
        ChildRef::leaf(start, self.packets.len() - start)
    }
}
