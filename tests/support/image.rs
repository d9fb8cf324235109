//! Shared helpers of the image tests: test patterns, tolerances, the sRGB
//! curve for checking values, and the image backends of this build.

use spar::image::{self, Image, ImageError, WriteOptions};
use std::path::Path;

/// The sRGB transfer curve (IEC 61966-2-1), for checking values only.
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

pub fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// A deterministic value in [0, 1) for test pattern `seed`.
pub fn unit(seed: u64) -> f32 {
    let mut x = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 40) as f32 / (1u64 << 24) as f32
}

pub fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// An image whose values are `pattern(channel, pixel)`.
pub fn patterned(
    w: usize,
    h: usize,
    channels: &[&str],
    pattern: impl Fn(usize, usize) -> f32,
) -> Image {
    let n = channels.len();
    let data = (0..w * h * n).map(|i| pattern(i % n, i / n)).collect();
    Image::new(w, h, names(channels), data).unwrap()
}

pub fn assert_close(got: f32, want: f32, tol: f32, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (tolerance {tol})"
    );
}

/// Bits of each value of channel `name`, for exact comparisons (NaN
/// included).
pub fn bits(image: &Image, name: &str) -> Vec<u32> {
    image
        .channel(name)
        .unwrap()
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

pub type WriteFn = fn(&Path, &Image, WriteOptions) -> Result<(), ImageError>;
pub type ReadFn = fn(&Path) -> Result<Image, ImageError>;

/// A way to write and read images.
#[derive(Clone, Copy)]
pub struct Backend {
    pub name: &'static str,
    pub write: WriteFn,
    pub read: ReadFn,
    /// Whether EXR and PNG go through OpenImageIO rather than the pure-Rust
    /// codecs.
    pub oiio: bool,
}

/// `spar::image::{write, read}`: the pure-Rust codecs for EXR and PNG, and
/// OpenImageIO for the other formats in a native build.
pub const DEFAULT: Backend = Backend {
    name: "image::write/read",
    write: image::write,
    read: image::read,
    oiio: false,
};

/// `spar::image::pure::{write, read}`, in every build.
pub const PURE: Backend = Backend {
    name: "image::pure",
    write: image::pure::write,
    read: image::pure::read,
    oiio: false,
};

/// `spar::image::oiio_only::{write, read}`: OpenImageIO for every format.
#[cfg(feature = "native")]
pub const OIIO: Backend = Backend {
    name: "image::oiio_only",
    write: image::oiio_only::write,
    read: image::oiio_only::read,
    oiio: true,
};

/// Every backend of this build.
pub fn backends() -> Vec<Backend> {
    #[cfg(feature = "native")]
    return vec![DEFAULT, PURE, OIIO];
    #[cfg(not(feature = "native"))]
    vec![DEFAULT]
}
