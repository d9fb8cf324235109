//! Render farms: units of work, raw parts, merging, checkpoints, progress
//! lines and job scripts. See `docs/farm.md` for the user's view.
//!
//! - [`part`]: the render's identity and raw EXR parts.
//! - [`exr`]: an EXR header reader (sample types, compression, windows).
//! - [`merge`]: parts into the whole, with named errors.
//! - [`memory`]: the machine's available memory, checked before large allocations.
//! - [`checkpoint`]: finished tiles saved on a signal, resumed later.
//! - [`progress`]: plain and OpenJD progress lines on stdout.
//! - [`plan`]: Slurm and OpenJD job scripts.

pub mod checkpoint;
pub mod exr;
pub mod memory;
pub mod merge;
pub mod part;
pub mod plan;
pub mod progress;

use std::path::PathBuf;

/// Why parts cannot be merged (or a raw file developed). Each has a
/// [`name`](MergeError::name) that starts its message.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("no parts given")]
    NoParts,
    #[error("unreadable: {}: {message}", path.display())]
    Unreadable { path: PathBuf, message: String },
    #[error("not-a-part: {}: {why}", path.display())]
    NotAPart { path: PathBuf, why: String },
    #[error(
        "half-float: {}: channel {channel} is stored as half float; parts must be float32 \
         (half keeps 11 bits of a sum)",
        path.display()
    )]
    HalfFloat { path: PathBuf, channel: String },
    #[error(
        "lossy: {}: compressed with {method}, a method that need not keep float32 exactly; \
         parts must use zip, zips, piz, rle or no compression",
        path.display()
    )]
    Lossy { path: PathBuf, method: String },
    #[error(
        "mismatch: {} has {key} `{theirs}` but {} has `{ours}`: they are parts of different renders",
        path.display(),
        first.display()
    )]
    Mismatch {
        path: PathBuf,
        first: PathBuf,
        key: String,
        theirs: String,
        ours: String,
    },
    #[error(
        "overlap: {} and {} both hold samples {samples} of pixels x,x,y,y = {region}",
        a.display(),
        b.display()
    )]
    Overlap {
        a: PathBuf,
        b: PathBuf,
        region: String,
        samples: String,
    },
    #[error(
        "non-finite: {}: {count} value(s) are NaN or infinite, the first at pixel x,y = {x},{y} \
         channel {channel}; raw sums are finite (render this part again)",
        path.display()
    )]
    NonFinite {
        path: PathBuf,
        x: u32,
        y: u32,
        channel: String,
        count: usize,
    },
    #[error(
        "overflow: the parts' sums at pixel x,y = {x},{y} channel {channel} exceed float32 \
         ({count} value(s) in all)"
    )]
    Overflow {
        x: u32,
        y: u32,
        channel: String,
        count: usize,
    },
    #[error("too-large: {}: {message}", path.display())]
    TooLarge { path: PathBuf, message: String },
    #[error("missing: no part holds samples {samples} of pixels x,x,y,y = {region}")]
    Missing { region: String, samples: String },
    #[error(
        "incomplete: {} holds pixels {region} and samples {samples}, not the whole render; \
         merge its parts first",
        path.display()
    )]
    Incomplete {
        path: PathBuf,
        region: String,
        samples: String,
    },
}

/// Where the non-finite values (NaN, ±∞) of `values` are: the index of
/// the first and how many there are, or `None` when all are finite. The
/// one check of every path that writes pixels (`spar render`, `merge`,
/// `develop`).
pub fn non_finite<'a>(values: impl IntoIterator<Item = &'a f32>) -> Option<(usize, usize)> {
    let mut found = None;
    for (i, v) in values.into_iter().enumerate() {
        if !v.is_finite() {
            found.get_or_insert((i, 0)).1 += 1;
        }
    }
    found
}

impl MergeError {
    /// The error's name, as its message starts.
    pub fn name(&self) -> &'static str {
        match self {
            MergeError::NoParts => "no-parts",
            MergeError::Unreadable { .. } => "unreadable",
            MergeError::NotAPart { .. } => "not-a-part",
            MergeError::HalfFloat { .. } => "half-float",
            MergeError::Lossy { .. } => "lossy",
            MergeError::Mismatch { .. } => "mismatch",
            MergeError::Overlap { .. } => "overlap",
            MergeError::NonFinite { .. } => "non-finite",
            MergeError::Overflow { .. } => "overflow",
            MergeError::TooLarge { .. } => "too-large",
            MergeError::Missing { .. } => "missing",
            MergeError::Incomplete { .. } => "incomplete",
        }
    }
}
