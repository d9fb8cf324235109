//! Sample blocks and the one summation order every render uses.
//!
//! A pixel's value is the sum of its samples `0..S`. Floating-point sums
//! depend on their order, so spar fixes one: the samples are the leaves of
//! a binary tree over `0..P` (`P` = `S` rounded up to a power of two), and
//! every tree node is the `f32` sum of its two children, left + right. A
//! node whose right child holds no sample (all its indices are ≥ `S`) is
//! its left child unchanged — nothing is added, so not even the sign of a
//! zero changes. Each sample's value is rounded to `f32` once, as a leaf.
//! The root is the pixel's sum; the division by `S` happens once, when
//! the film is read.
//!
//! The nodes are the aligned power-of-two ranges of sample indices
//! ([`Node`]). A render of samples `k0..k1` computes the largest nodes
//! inside that range (at most two per tree level; one when the range is
//! itself a node, as the ranges `spar plan` makes are) and stores them
//! as they are. Whoever holds nodes that tile `0..S` rebuilds every
//! ancestor, and so the root, exactly as a one-machine render computes
//! it: the tree is the same, and so is every addition in it. That is how
//! sample blocks rendered on different machines merge bit for bit.
//!
//! [`Accumulator`] computes the nodes of a range from its samples in order
//! (a binary counter: each new leaf merges with its left sibling while
//! that is complete) and also assembles a root from stored nodes. The
//! extra work is one `f32` addition per sample and value, beside the
//! `f64` one it replaces.

use std::fmt;

/// An aligned range of sample indices: `start .. start + len`, `len` a
/// power of two dividing `start`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Node {
    pub start: u64,
    pub len: u64,
}

impl Node {
    /// The end of the range (exclusive).
    pub fn end(self) -> u64 {
        self.start + self.len
    }

    /// Whether `start .. start + len` is an aligned power-of-two range.
    pub fn is_aligned(self) -> bool {
        self.len.is_power_of_two() && self.start % self.len == 0
    }

    /// Whether this node is the left child of its parent.
    fn is_left_child(self) -> bool {
        self.start % (2 * self.len) == 0
    }
}

impl fmt::Display for Node {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}", self.start, self.end())
    }
}

impl std::str::FromStr for Node {
    type Err = String;
    fn from_str(s: &str) -> Result<Node, String> {
        let (a, b) = s
            .split_once('-')
            .ok_or_else(|| format!("`{s}` is not a sample node START-END"))?;
        let parse = |v: &str| {
            v.parse::<u64>()
                .map_err(|_| format!("`{s}` is not a sample node START-END"))
        };
        let (start, end) = (parse(a)?, parse(b)?);
        let node = Node {
            start,
            len: end.wrapping_sub(start),
        };
        if end <= start || !node.is_aligned() {
            return Err(format!(
                "`{s}` is not an aligned power-of-two range of samples"
            ));
        }
        Ok(node)
    }
}

/// The samples of one unit of work: `start .. end` of `total`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SampleRange {
    pub start: u32,
    pub end: u32,
    pub total: u32,
}

impl SampleRange {
    /// All samples of a render of `total` samples per pixel.
    pub fn all(total: u32) -> SampleRange {
        SampleRange {
            start: 0,
            end: total,
            total,
        }
    }

    /// A block `start..end` of `total`; `None` unless `start < end ≤ total`.
    pub fn new(start: u32, end: u32, total: u32) -> Option<SampleRange> {
        (start < end && end <= total).then_some(SampleRange { start, end, total })
    }

    /// Whether this is every sample.
    pub fn is_all(&self) -> bool {
        self.start == 0 && self.end == self.total
    }

    /// Samples in the block.
    pub fn count(&self) -> u32 {
        self.end - self.start
    }

    /// The size of the padded tree, `total` rounded up to a power of two.
    pub fn padded(&self) -> u64 {
        (self.total.max(1) as u64).next_power_of_two()
    }

    /// The nodes this block stores, in order: what [`Accumulator`] leaves
    /// after the block's samples. One node, `0-P`, for a whole render.
    pub fn nodes(&self) -> Vec<Node> {
        let mut acc = Accumulator::new(0);
        for k in self.start..self.end {
            acc.push(
                Node {
                    start: k as u64,
                    len: 1,
                },
                &[],
            );
        }
        if self.end == self.total {
            acc.finish(self.total);
        }
        acc.nodes
    }

    /// `start..end/total`, the form `--samples` takes.
    pub fn label(&self) -> String {
        format!("{}..{}/{}", self.start, self.end, self.total)
    }

    /// Parses [`Self::label`]'s form.
    pub fn parse_label(s: &str) -> Option<SampleRange> {
        let (range, total) = s.split_once('/')?;
        let (a, b) = range.split_once("..")?;
        SampleRange::new(a.parse().ok()?, b.parse().ok()?, total.parse().ok()?)
    }
}

/// A stack of tree nodes with `width` values each (one per channel): the
/// canonical sum of a run of samples, or of stored nodes, in the order of
/// the module documentation.
#[derive(Clone, Debug)]
pub struct Accumulator {
    width: usize,
    nodes: Vec<Node>,
    values: Vec<f32>,
}

impl Accumulator {
    /// An empty stack for `width` values per node.
    pub fn new(width: usize) -> Accumulator {
        Accumulator {
            width,
            nodes: Vec::with_capacity(34),
            values: Vec::with_capacity(34 * width),
        }
    }

    /// Empties the stack, keeping its memory.
    pub fn clear(&mut self) {
        self.nodes.clear();
        self.values.clear();
    }

    /// Pushes the next node (a leaf: one sample) to the right of the
    /// others, then adds every pair of complete siblings on top.
    pub fn push(&mut self, node: Node, values: &[f32]) {
        debug_assert_eq!(values.len(), self.width);
        debug_assert!(node.is_aligned());
        debug_assert!(self.nodes.last().is_none_or(|t| t.end() == node.start));
        self.nodes.push(node);
        self.values.extend_from_slice(values);
        self.collapse();
    }

    /// Pushes a leaf whose values the caller writes into the slice given to
    /// `fill` (zeroed first).
    #[inline]
    pub fn push_with(&mut self, node: Node, fill: impl FnOnce(&mut [f32])) {
        self.nodes.push(node);
        let n = self.values.len();
        self.values.resize(n + self.width, 0.0);
        fill(&mut self.values[n..]);
        self.collapse();
    }

    #[inline]
    fn collapse(&mut self) {
        let w = self.width;
        while let [.., a, b] = self.nodes[..] {
            if !(a.len == b.len && a.is_left_child()) {
                break;
            }
            let n = self.nodes.len();
            let (left, right) = self.values.split_at_mut((n - 1) * w);
            for (l, r) in left[(n - 2) * w..].iter_mut().zip(&*right) {
                *l += *r;
            }
            self.values.truncate((n - 1) * w);
            self.nodes.pop();
            self.nodes[n - 2].len *= 2;
        }
    }

    /// Completes the tree of a render of `total` samples whose last sample
    /// has been pushed: a left child whose right sibling holds no sample
    /// becomes its parent unchanged, and merges on.
    pub fn finish(&mut self, total: u32) {
        let padded = (total.max(1) as u64).next_power_of_two();
        while let Some(&top) = self.nodes.last() {
            if top.is_left_child() && top.end() >= total as u64 && 2 * top.len <= padded {
                self.nodes.last_mut().expect("non-empty").len *= 2;
                self.collapse();
            } else {
                break;
            }
        }
    }

    /// Replaces the stack with `nodes` and their `values` (node after
    /// node), as [`Self::nodes`] and [`Self::values`] gave them.
    pub fn restore(&mut self, nodes: &[Node], values: &[f32]) {
        debug_assert_eq!(values.len(), nodes.len() * self.width);
        self.nodes.clear();
        self.nodes.extend_from_slice(nodes);
        self.values.clear();
        self.values.extend_from_slice(values);
    }

    /// The nodes on the stack, left to right.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The values of every node, node after node.
    pub fn values(&self) -> &[f32] {
        &self.values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The module's definition, written as a recursion.
    fn tree(leaves: &[f32], start: u64, len: u64) -> Option<f32> {
        if start >= leaves.len() as u64 {
            return None;
        }
        if len == 1 {
            return Some(leaves[start as usize]);
        }
        let l = tree(leaves, start, len / 2);
        let r = tree(leaves, start + len / 2, len / 2);
        match (l, r) {
            (Some(l), Some(r)) => Some(l + r),
            (l, None) => l,
            (None, r) => r,
        }
    }

    fn leaves(n: usize) -> Vec<f32> {
        // Values of very different sizes, so that order matters.
        (0..n)
            .map(|i| {
                let x = ((i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) as f32;
                x * 10f32.powi((i % 7) as i32 - 3)
            })
            .collect()
    }

    fn block(leaves: &[f32], r: SampleRange) -> Vec<(Node, f32)> {
        let mut acc = Accumulator::new(1);
        for k in r.start..r.end {
            acc.push(
                Node {
                    start: k as u64,
                    len: 1,
                },
                &[leaves[k as usize]],
            );
        }
        if r.end == r.total {
            acc.finish(r.total);
        }
        acc.nodes()
            .iter()
            .copied()
            .zip(acc.values().iter().copied())
            .collect()
    }

    #[test]
    fn a_whole_render_is_the_tree_root() {
        for s in 1..70u32 {
            let l = leaves(s as usize);
            let r = SampleRange::all(s);
            let nodes = block(&l, r);
            assert_eq!(nodes.len(), 1, "S = {s}");
            assert_eq!(
                nodes[0].0,
                Node {
                    start: 0,
                    len: r.padded()
                }
            );
            assert_eq!(
                nodes[0].1.to_bits(),
                tree(&l, 0, r.padded()).unwrap().to_bits()
            );
            assert_eq!(r.nodes(), vec![nodes[0].0]);
        }
    }

    #[test]
    fn any_split_into_blocks_merges_to_the_same_bits() {
        // Every split of 0..S into up to three blocks, S up to 40.
        for s in 1..40u32 {
            let l = leaves(s as usize);
            let whole = block(&l, SampleRange::all(s))[0].1;
            for a in 1..=s {
                for b in a..=s {
                    let cuts: Vec<u32> = [0, a, b, s].into_iter().collect();
                    let mut acc = Accumulator::new(1);
                    for w in cuts.windows(2) {
                        if w[0] == w[1] {
                            continue;
                        }
                        let r = SampleRange::new(w[0], w[1], s).unwrap();
                        let nodes = block(&l, r);
                        assert_eq!(nodes.iter().map(|n| n.0).collect::<Vec<_>>(), r.nodes());
                        for (node, v) in nodes {
                            // Stored nodes tile the block's own range.
                            assert!(node.start >= w[0] as u64);
                            acc.push(node, &[v]);
                        }
                    }
                    acc.finish(s);
                    assert_eq!(acc.nodes().len(), 1, "S {s} cuts {cuts:?}");
                    assert_eq!(acc.values()[0].to_bits(), whole.to_bits());
                }
            }
        }
    }

    #[test]
    fn order_matters_so_the_test_above_could_fail() {
        let l = leaves(33);
        let seq: f32 = l.iter().sum();
        let t = tree(&l, 0, 64).unwrap();
        assert_ne!(seq.to_bits(), t.to_bits());
    }

    #[test]
    fn aligned_blocks_store_one_node() {
        let r = SampleRange::new(256, 512, 1000).unwrap();
        assert_eq!(
            r.nodes(),
            vec![Node {
                start: 256,
                len: 256
            }]
        );
        let last = SampleRange::new(768, 1000, 1000).unwrap();
        assert_eq!(
            last.nodes(),
            vec![Node {
                start: 768,
                len: 256
            }]
        );
        let odd = SampleRange::new(3, 9, 16).unwrap();
        let got: Vec<String> = odd.nodes().iter().map(|n| n.to_string()).collect();
        assert_eq!(got, ["3-4", "4-8", "8-9"]);
    }

    #[test]
    fn negative_zero_survives_a_missing_sibling() {
        let mut acc = Accumulator::new(1);
        acc.push(Node { start: 0, len: 1 }, &[1.0]);
        acc.push(Node { start: 1, len: 1 }, &[-1.0]);
        acc.push(Node { start: 2, len: 1 }, &[-0.0]);
        acc.finish(3);
        // (1 + −1) + (−0) = +0 + −0 = +0; −0 alone would stay −0.
        assert_eq!(acc.values()[0].to_bits(), 0.0f32.to_bits());
        let mut one = Accumulator::new(1);
        one.push(Node { start: 0, len: 1 }, &[-0.0]);
        one.finish(1);
        assert_eq!(one.values()[0].to_bits(), (-0.0f32).to_bits());
    }

    #[test]
    fn labels_and_nodes_parse_back() {
        let r = SampleRange::new(5, 9, 12).unwrap();
        assert_eq!(SampleRange::parse_label(&r.label()), Some(r));
        assert_eq!(SampleRange::parse_label("9..5/12"), None);
        assert_eq!("8-16".parse::<Node>(), Ok(Node { start: 8, len: 8 }));
        assert!("8-15".parse::<Node>().is_err());
        assert!("4-12".parse::<Node>().is_err());
        assert!("x".parse::<Node>().is_err());
    }
}
