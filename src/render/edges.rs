//! Edge-adaptive sampling (`edges`, docs/speed-vs-error.md): every pixel
//! takes `min_samples` samples; a pixel goes on to all its samples only
//! where what it shows differs from one of its eight neighbours by more
//! than a threshold ([`super::adaptive::contrast`]).
//!
//! Why neighbours and not a pixel's own spread: the error of an exact
//! tree is almost all where an edge (a facet's, a light's, a shadow's)
//! crosses a pixel, and a pixel whose first samples all fall on one side
//! of its edge has no spread at all, though it differs from its neighbour
//! across the edge. Measured on the Mitsuba cross-check cube (128², DoP at
//! 580 nm): half of the squared DoP error at 256 samples is in 0.1 % of
//! the pixels and 90 % in 0.5 %, all on edges.
//!
//! A pixel's flag depends on its own and its neighbours' first samples,
//! each a pure function of (seed, pixel, sample): a region renders a
//! one-pixel border of first samples around itself, so regions and tiles
//! give the pixels of a whole render bit for bit. Sample blocks cannot
//! decide and are refused, as with adaptive sampling.
//!
//! Edge refinement (`max_samples`; `refine` in `render_part`): a flagged
//! pixel that has taken all its samples compares what it shows with what
//! it showed after its first samples ([`contrast`], the same threshold)
//! and, if that moved, takes four times as many, and again while its
//! value moves from one step to the next, up to `max_samples`.
//! Its own samples decide, so tiles still merge bit for bit. Why its own
//! value's movement: on the cube, a flagged pixel's error is mostly luck
//! (where its samples fell against its edge), which its neighbours
//! cannot show but the change of its own value can.

use super::adaptive::{contrast, PixelNoise, SHOWN};
use super::blocks::{Accumulator, Node};
use super::integrator::Stats;
use super::region::Rect;
use super::PixelScratch;
use rayon::prelude::*;

/// The first samples of a region's pixels and of the border around it.
pub(super) struct FirstSamples {
    /// The region grown by one pixel, within the image.
    apron: Rect,
    region: Rect,
    /// What each pixel of `apron` shows after its first samples, row-major.
    shown: Vec<[f64; SHOWN]>,
    saved: Saved,
}

/// The region's pixels' sums after their first samples, row-major: the
/// same nodes for every pixel (they depend only on the count), so one
/// flat array of values, and each pixel's noise sums only where a later
/// check needs them (adaptive sampling or edge refinement on). About
/// four `f32` per wavelength and pixel, as the film itself.
#[derive(Default)]
struct Saved {
    nodes: Vec<Node>,
    /// Values per pixel: `nodes.len()` × channels.
    width: usize,
    values: Vec<f32>,
    noise: Vec<PixelNoise>,
}

impl Saved {
    fn push(&mut self, acc: &Accumulator, noise: &PixelNoise, keep_noise: bool) {
        if self.width == 0 {
            self.nodes = acc.nodes().to_vec();
            self.width = acc.values().len();
        }
        debug_assert_eq!(acc.nodes(), &self.nodes[..]);
        self.values.extend_from_slice(acc.values());
        if keep_noise {
            self.noise.push(noise.clone());
        }
    }

    fn extend(&mut self, other: Saved) {
        if self.width == 0 {
            self.nodes = other.nodes;
            self.width = other.width;
        }
        self.values.extend(other.values);
        self.noise.extend(other.noise);
    }
}

/// The region grown by one pixel on every side, clipped to the image.
fn apron(region: Rect, width: u32, height: u32) -> Rect {
    Rect {
        x0: region.x0.saturating_sub(1),
        x1: (region.x1 + 1).min(width),
        y0: region.y0.saturating_sub(1),
        y1: (region.y1 + 1).min(height),
    }
}

/// Renders the first samples of every pixel of `region` and its border
/// (`pixel` renders one into the scratch and returns what it shows), rows
/// spread over rayon's threads; their statistics are added to `stats`.
/// Once `stopped()` holds, the remaining rows are skipped (their values
/// are meaningless, and the caller renders no tile after a stop). A
/// pixel's noise sums are kept when `keep_noise` (a later check reads
/// them).
#[allow(clippy::too_many_arguments)]
pub(super) fn first_samples(
    region: Rect,
    width: u32,
    height: u32,
    channels: usize,
    keep_noise: bool,
    stats: &mut Stats,
    stopped: &(dyn Fn() -> bool + Sync),
    pixel: impl Fn(u32, u32, &mut PixelScratch, &mut Stats) -> [f64; SHOWN] + Sync,
) -> FirstSamples {
    let apron = apron(region, width, height);
    type Row = (Vec<[f64; SHOWN]>, Saved, Stats);
    let rows: Vec<Row> = (apron.y0..apron.y1)
        .into_par_iter()
        .map(|y| {
            let mut scratch = PixelScratch::new(channels, channels / 4);
            let mut row: Row = (Vec::new(), Saved::default(), Stats::default());
            let skip = stopped();
            for x in apron.x0..apron.x1 {
                scratch.acc.clear();
                scratch.noise.clear();
                row.0.push(if skip {
                    [0.0; SHOWN]
                } else {
                    pixel(x, y, &mut scratch, &mut row.2)
                });
                if region.contains(x, y) && !skip {
                    row.1.push(&scratch.acc, &scratch.noise, keep_noise);
                }
            }
            row
        })
        .collect();
    let mut pass = FirstSamples {
        apron,
        region,
        shown: Vec::with_capacity(apron.area()),
        saved: Saved::default(),
    };
    for (shown, saved, s) in rows {
        pass.shown.extend(shown);
        pass.saved.extend(saved);
        *stats += s;
    }
    pass
}

impl FirstSamples {
    /// Flags the region's pixels that differ from a neighbour by more than
    /// `threshold`.
    pub(super) fn flag(self, threshold: f64) -> Edges {
        let a = self.apron;
        let aw = a.width() as usize;
        let at = |x: u32, y: u32| &self.shown[(y - a.y0) as usize * aw + (x - a.x0) as usize];
        let mut flags = Vec::with_capacity(self.region.area());
        for y in self.region.y0..self.region.y1 {
            for x in self.region.x0..self.region.x1 {
                let me = at(x, y);
                let ys = y.saturating_sub(1).max(a.y0)..(y + 2).min(a.y1);
                let edge = ys.into_iter().any(|ny| {
                    (x.saturating_sub(1).max(a.x0)..(x + 2).min(a.x1))
                        .any(|nx| contrast(me, at(nx, ny)) > threshold)
                });
                flags.push(edge);
            }
        }
        Edges {
            region: self.region,
            flags,
            saved: self.saved,
        }
    }
}

/// Which of a region's pixels take all their samples, and every pixel's
/// sums after its first samples.
pub(super) struct Edges {
    region: Rect,
    flags: Vec<bool>,
    saved: Saved,
}

impl Edges {
    /// Whether pixel (x, y) is at an edge; puts its sums after its first
    /// samples into `acc` and `noise` (noise sums only where kept, else
    /// none).
    pub(super) fn pixel(
        &self,
        x: u32,
        y: u32,
        acc: &mut Accumulator,
        noise: &mut PixelNoise,
    ) -> bool {
        let r = self.region;
        let i = (y - r.y0) as usize * r.width() as usize + (x - r.x0) as usize;
        let s = &self.saved;
        acc.restore(&s.nodes, &s.values[i * s.width..(i + 1) * s.width]);
        match s.noise.get(i) {
            Some(n) => noise.clone_from(n),
            None => noise.clear(),
        }
        self.flags[i]
    }
}
