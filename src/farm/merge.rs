//! `spar merge`: parts of one render into the whole.
//!
//! Every part is checked on its own ([`super::part::read_part`]: float32,
//! lossless, spar's metadata), then against the first (identity), then all
//! together: cut the image along every part's region edges; in each cell,
//! the sample blocks of the parts covering it must tile `0..S` — an
//! overlap or a gap is an error naming the pixels and samples. Each
//! pixel's stored tree nodes are then added in the order of
//! [`crate::render::blocks`], which gives the bits a one-machine render gives.
//! Merging is generic over channels: whatever raw channels the parts list
//! (`spar:channels`), each is summed the same way.

use super::part::LoadedPart;
use super::MergeError;
use crate::render::blocks::{Accumulator, Node, SampleRange};
use crate::render::region::Rect;

/// The merged whole: every pixel, every sample, one tree node.
#[derive(Clone, Debug)]
pub struct Merged {
    pub width: u32,
    pub height: u32,
    pub channels: Vec<String>,
    pub samples: SampleRange,
    /// `pixel * channels + channel`.
    pub data: Vec<f32>,
}

/// Merges parts that were each read and checked by
/// [`super::part::read_part`].
pub fn merge(parts: &[LoadedPart]) -> Result<Merged, MergeError> {
    let first = parts.first().ok_or(MergeError::NoParts)?;
    for part in &parts[1..] {
        for ((key, ours), (_, theirs)) in first.identity.iter().zip(&part.identity) {
            if ours != theirs {
                return Err(MergeError::Mismatch {
                    path: part.path.clone(),
                    first: first.path.clone(),
                    key: key.clone(),
                    theirs: theirs.clone(),
                    ours: ours.clone(),
                });
            }
        }
        if part.spec.samples.total != first.spec.samples.total {
            return Err(MergeError::Mismatch {
                path: part.path.clone(),
                first: first.path.clone(),
                key: "samples per pixel".into(),
                theirs: part.spec.samples.total.to_string(),
                ours: first.spec.samples.total.to_string(),
            });
        }
    }
    let total = first.spec.samples.total;
    let (w, h) = first
        .metadata
        .get("spar:resolution")
        .and_then(|r| r.split_once('x'))
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
        .expect("checked by read_part");
    let channels = first.channels.clone();
    let nch = channels.len();

    // Cells between every region edge: inside one, the same parts cover
    // every pixel.
    let mut xs: Vec<u32> = vec![0, w];
    let mut ys: Vec<u32> = vec![0, h];
    for p in parts {
        xs.extend([p.spec.region.x0, p.spec.region.x1]);
        ys.extend([p.spec.region.y0, p.spec.region.y1]);
    }
    xs.sort_unstable();
    xs.dedup();
    ys.sort_unstable();
    ys.dedup();

    // Every part was read whole, but the whole image can be far larger
    // than its parts claim to cover.
    super::memory::check(
        w as f64 * h as f64 * nch as f64 * 4.0 * 2.0,
        &format!("the merged {w}x{h} image of {nch} channels"),
    )
    .map_err(|message| MergeError::TooLarge {
        path: first.path.clone(),
        message,
    })?;
    let mut out = vec![0.0f32; w as usize * h as usize * nch];
    let mut acc = Accumulator::new(nch);
    for yc in ys.windows(2) {
        for xc in xs.windows(2) {
            let cell = Rect {
                x0: xc[0],
                x1: xc[1],
                y0: yc[0],
                y1: yc[1],
            };
            let mut here: Vec<&LoadedPart> = parts
                .iter()
                .filter(|p| p.spec.region.contains(cell.x0, cell.y0))
                .collect();
            here.sort_by_key(|p| (p.spec.samples.start, p.spec.samples.end));
            let mut at = 0u32;
            for (i, p) in here.iter().enumerate() {
                let s = p.spec.samples;
                if s.start > at {
                    return Err(MergeError::Missing {
                        region: cell.to_string(),
                        samples: format!("{at}..{}", s.start),
                    });
                }
                if s.start < at {
                    let other = here[..i]
                        .iter()
                        .rev()
                        .find(|q| q.spec.samples.end > s.start)
                        .expect("an earlier part reaches past this start");
                    return Err(MergeError::Overlap {
                        a: other.path.clone(),
                        b: p.path.clone(),
                        region: cell.to_string(),
                        samples: format!("{}..{}", s.start, s.end.min(other.spec.samples.end)),
                    });
                }
                at = s.end;
            }
            if at < total {
                return Err(MergeError::Missing {
                    region: cell.to_string(),
                    samples: format!("{at}..{total}"),
                });
            }
            // Add, pixel by pixel, in the tree order.
            let root = Node {
                start: 0,
                len: SampleRange::all(total).padded(),
            };
            for y in cell.y0..cell.y1 {
                for x in cell.x0..cell.x1 {
                    acc.clear();
                    for p in &here {
                        let r = p.spec.region;
                        let npix = r.area();
                        let pix = (y - r.y0) as usize * r.width() as usize + (x - r.x0) as usize;
                        for (j, &node) in p.nodes.iter().enumerate() {
                            let at = (j * npix + pix) * nch;
                            acc.push(node, &p.data[at..at + nch]);
                        }
                    }
                    acc.finish(total);
                    assert_eq!(acc.nodes(), &[root], "parts tile the samples");
                    let o = (y as usize * w as usize + x as usize) * nch;
                    out[o..o + nch].copy_from_slice(acc.values());
                }
            }
        }
    }
    // Finite parts can still add up past float32's largest value.
    if let Some((first, count)) = super::non_finite(&out) {
        let pix = first / nch;
        return Err(MergeError::Overflow {
            x: (pix % w as usize) as u32,
            y: (pix / w as usize) as u32,
            channel: channels[first % nch].clone(),
            count,
        });
    }
    Ok(Merged {
        width: w,
        height: h,
        channels,
        samples: SampleRange::all(total),
        data: out,
    })
}
