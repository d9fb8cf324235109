//! Images in memory and on disk, whatever the file format.
//!
//! An [`Image`] is `width × height` pixels of named `f32` channels,
//! interleaved (all channels of a pixel are adjacent), row-major, top row
//! first. Channels are found **by name**, never by position: EXR stores them
//! sorted as strings, so `S10` comes back before `S2`.
//!
//! [`write`] picks the format from the file's extension (`.exr`, `.png`,
//! `.tif`/`.tiff`, `.jpg`/`.jpeg`, …) and stores the sample type asked for
//! in [`WriteOptions`]; [`read`] returns linear floats whatever the file
//! held. OpenEXR and PNG go through spar's pure-Rust codecs ([`pure`]) in
//! every build; every other format goes through OpenImageIO when spar is
//! built with the `native` feature. Without it, TIFF, JPEG and the rest are
//! refused with an error saying that they need the `native` feature, and
//! [`draw_text`] is unavailable.
//!
//! OpenImageIO is not linked into spar: the first read or write through it
//! loads spar's shim library (`libspar_oiio.so`; see `spar::native::oiio`
//! for where it is looked for and `SPAR_OIIO_SHIM`). If it cannot be loaded
//! that read or write fails with `Cause::Unavailable`.
//!
//! # Values, colour and alpha
//! - Writing never changes colours: the [`Encoding`] in the options says
//!   how the values already are encoded and is recorded in the file. For
//!   8- and 16-bit display images the caller passes sRGB-encoded values
//!   (the sRGB curve belongs to [`crate::spectrum`]).
//! - 8- and 16-bit outputs store `[0, 1]` over the full integer range:
//!   values are clamped to `[0, 1]` and NaN is written as 0 (so `+∞ → 1`,
//!   `−∞ → 0`). Half and float outputs keep NaN and infinities; half turns
//!   finite values above 65504 into infinity.
//! - Half and float files hold linear values: [`write`] refuses
//!   [`Encoding::Srgb`] for them, and [`read`] returns them as stored.
//! - Reading decodes integer files whose colour space is declared
//!   non-linear to linear: 8/16-bit PNG and JPEG (sRGB unless the file says
//!   otherwise, a PNG gamma included) and TIFF tagged sRGB. Untagged TIFF is
//!   returned as stored. Alpha is never decoded.
//! - Alpha is the channel named `A` (or `Alpha`); [`AlphaMode`] says whether
//!   colours are premultiplied by it. PNG stores straight alpha: [`write`]
//!   divides premultiplied colours by alpha (as given, whatever their
//!   encoding; colours under zero alpha are kept), and PNGs are read back
//!   straight. EXR's convention is premultiplied: values are stored as
//!   given and read back as [`AlphaMode::Premultiplied`].
//!
//! # What each format keeps
//! Channel names: EXR keeps any; PNG, TIFF and JPEG return `R`, `G`, `B`,
//! `A` (or `Y` for one channel) whatever was written, and a PNG's fourth
//! channel is read back as alpha (so it is not decoded). Metadata: EXR keeps
//! every string key; PNG keeps them as text chunks; TIFF and JPEG keep only
//! the keys their formats know (`ImageDescription`, `Artist`, …). Both
//! backends store the standard keys under the format's own names (EXR's
//! `comments`, `owner`, `capDate` for `ImageDescription`, `Copyright`,
//! `DateTime`; PNG's `Description`, `Author`, `Title` for
//! `ImageDescription`, `Artist`, `DocumentName`) and read them back under
//! spar's. Keys starting with `oiio:` are OpenImageIO's settings: [`write`]
//! refuses them. Formats that cannot store a sample type, a channel count
//! or alpha make [`write`] fail rather than store something else (e.g.
//! float PNG, alpha in JPEG).
//!
//! # Writes are atomic
//! [`write`] writes `.<name>.tmp-<pid>-<n>.<ext>` in the destination
//! directory, then renames it over the destination. On failure the
//! temporary is removed and the destination is left as it was.
//!
//! Read back: [`read`] takes the first subimage, top MIP level, data window.

mod backend;
mod io;
pub mod pure;

#[cfg(feature = "native")]
pub use backend::oiio_only;
pub use backend::{read, write};
pub use io::draw_text;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Sample type stored in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PixelType {
    /// 8-bit unsigned integer, `[0, 1]` → `0..=255` (PNG, TIFF, JPEG).
    U8,
    /// 16-bit unsigned integer, `[0, 1]` → `0..=65535` (PNG, TIFF).
    U16,
    /// IEEE half float (EXR, TIFF).
    Half,
    /// IEEE single float (EXR, TIFF).
    F32,
}

impl PixelType {
    /// Whether values are stored as integers over `[0, 1]`.
    pub fn is_integer(self) -> bool {
        matches!(self, PixelType::U8 | PixelType::U16)
    }
}

/// How the values given to [`write`] are encoded. Recorded in the file so
/// that [`read`] can decode them; never applied by [`write`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Linear values (renderer output, data maps).
    Linear,
    /// Values already passed through the sRGB transfer curve.
    Srgb,
}

/// Whether colour channels are premultiplied by alpha.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AlphaMode {
    /// Colours are not multiplied by alpha (PNG's convention).
    #[default]
    Straight,
    /// Colours are multiplied by alpha (EXR's convention).
    Premultiplied,
}

/// How [`write`] stores an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct WriteOptions {
    pub pixel_type: PixelType,
    pub encoding: Encoding,
}

impl WriteOptions {
    /// Options for `pixel_type`, with the usual encoding for it: sRGB for
    /// 8/16-bit (display images), linear for half and float.
    pub fn new(pixel_type: PixelType) -> WriteOptions {
        let encoding = if pixel_type.is_integer() {
            Encoding::Srgb
        } else {
            Encoding::Linear
        };
        WriteOptions {
            pixel_type,
            encoding,
        }
    }

    /// The same options with another encoding.
    pub fn with_encoding(self, encoding: Encoding) -> WriteOptions {
        WriteOptions { encoding, ..self }
    }
}

impl Default for WriteOptions {
    /// Linear 32-bit float.
    fn default() -> WriteOptions {
        WriteOptions::new(PixelType::F32)
    }
}

/// Why an image operation failed.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// Writing failed; the destination is as it was and no temporary is
    /// left beside it.
    #[error("cannot write image '{}': {cause}", path.display())]
    Write { path: PathBuf, cause: Cause },
    /// Reading failed.
    #[error("cannot read image '{}': {cause}", path.display())]
    Read { path: PathBuf, cause: Cause },
    /// A channel looked up by name does not exist.
    #[error(
        "{} has no channel '{name}' (it has: {})",
        file.as_ref().map_or_else(|| "the image".to_string(), |p| format!("image '{}'", p.display())),
        available.join(", ")
    )]
    MissingChannel {
        /// The file the image came from, if it was read.
        file: Option<PathBuf>,
        name: String,
        available: Vec<String>,
    },
    /// Dimensions, data length or channel names are inconsistent.
    #[error("invalid image: {0}")]
    Invalid(String),
}

/// The underlying reason of a failed read or write.
#[derive(Debug, thiserror::Error)]
pub enum Cause {
    /// The file system refused (missing file, permissions, rename).
    #[error("{0}")]
    Io(std::io::Error),
    /// The backend (OpenImageIO through spar's shim, or the pure-Rust
    /// codecs) refused: unknown or unsupported extension, corrupt file, a
    /// format that cannot store what was asked.
    #[error("{0}")]
    Backend(String),
    /// The request itself is wrong (no extension, reserved metadata key, a
    /// NUL character in a name or value, inconsistent image).
    #[error("{0}")]
    Invalid(String),
    /// OpenImageIO, which the file needs, cannot be loaded: spar's shim
    /// library (`libspar_oiio.so`) is missing or from another build. The
    /// error names each place it was looked for and `SPAR_OIIO_SHIM`.
    #[cfg(feature = "native")]
    #[error(transparent)]
    Unavailable(crate::native::oiio::LoadError),
}

/// An image: named `f32` channels, interleaved, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    width: usize,
    height: usize,
    channels: Vec<String>,
    data: Vec<f32>,
    alpha: AlphaMode,
    metadata: BTreeMap<String, String>,
    source: Option<PathBuf>,
}

impl Image {
    /// An image from interleaved `data` (`width * height * channels.len()`
    /// values). Channel names must be non-empty and distinct.
    pub fn new(
        width: usize,
        height: usize,
        channels: Vec<String>,
        data: Vec<f32>,
    ) -> Result<Image, ImageError> {
        if width == 0 || height == 0 {
            return Err(ImageError::Invalid(format!(
                "{width}x{height} pixels: both must be at least 1"
            )));
        }
        if channels.is_empty() {
            return Err(ImageError::Invalid("no channels".into()));
        }
        for (i, name) in channels.iter().enumerate() {
            if name.is_empty() {
                return Err(ImageError::Invalid(format!("channel {i} has no name")));
            }
            if channels[..i].contains(name) {
                return Err(ImageError::Invalid(format!(
                    "channel name '{name}' appears twice"
                )));
            }
        }
        let expected = width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(channels.len()));
        if expected != Some(data.len()) {
            return Err(ImageError::Invalid(format!(
                "{} values for {width}x{height} pixels of {} channel(s)",
                data.len(),
                channels.len()
            )));
        }
        Ok(Image {
            width,
            height,
            channels,
            data,
            alpha: AlphaMode::default(),
            metadata: BTreeMap::new(),
            source: None,
        })
    }

    /// An image from one plane per channel (each `width * height` values,
    /// row-major), in the order given.
    pub fn from_planes<N: Into<String>>(
        width: usize,
        height: usize,
        planes: impl IntoIterator<Item = (N, Vec<f32>)>,
    ) -> Result<Image, ImageError> {
        let planes: Vec<(String, Vec<f32>)> =
            planes.into_iter().map(|(n, p)| (n.into(), p)).collect();
        let npixels = width.saturating_mul(height);
        if let Some((name, plane)) = planes.iter().find(|(_, p)| p.len() != npixels) {
            return Err(ImageError::Invalid(format!(
                "plane '{name}' has {} values for {width}x{height} pixels",
                plane.len()
            )));
        }
        let nchannels = planes.len();
        let mut data = vec![0.0; npixels.saturating_mul(nchannels)];
        for (c, (_, plane)) in planes.iter().enumerate() {
            for (i, &v) in plane.iter().enumerate() {
                data[i * nchannels + c] = v;
            }
        }
        let channels = planes.into_iter().map(|(n, _)| n).collect();
        Image::new(width, height, channels, data)
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Channel names, in storage order.
    pub fn channels(&self) -> &[String] {
        &self.channels
    }

    /// All values, interleaved.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// All values, interleaved, for changing in place.
    pub fn data_mut(&mut self) -> &mut [f32] {
        &mut self.data
    }

    /// The values of pixel `(x, y)`, one per channel. Panics outside the
    /// image, like slice indexing.
    pub fn pixel(&self, x: usize, y: usize) -> &[f32] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside the image"
        );
        let n = self.channels.len();
        let start = (y * self.width + x) * n;
        &self.data[start..start + n]
    }

    /// The file this image was read from, if any.
    pub fn source(&self) -> Option<&Path> {
        self.source.as_deref()
    }

    /// Whether colours are premultiplied by alpha.
    pub fn alpha_mode(&self) -> AlphaMode {
        self.alpha
    }

    /// The same image with another alpha mode (nothing is converted).
    pub fn with_alpha_mode(mut self, alpha: AlphaMode) -> Image {
        self.alpha = alpha;
        self
    }

    /// Index of the alpha channel (named `A` or `Alpha`), if any.
    pub fn alpha_channel(&self) -> Option<usize> {
        self.channels.iter().position(|n| n == "A" || n == "Alpha")
    }

    /// String metadata (written where the format allows; read back from
    /// the file).
    pub fn metadata(&self) -> &BTreeMap<String, String> {
        &self.metadata
    }

    /// String metadata, for changing. Keys starting with `oiio:` are
    /// OpenImageIO's own and refused by [`write`].
    pub fn metadata_mut(&mut self) -> &mut BTreeMap<String, String> {
        &mut self.metadata
    }

    /// The same image with one more metadata entry.
    pub fn with_metadata(mut self, key: impl Into<String>, value: impl Into<String>) -> Image {
        self.metadata.insert(key.into(), value.into());
        self
    }

    /// Position of channel `name` within a pixel.
    pub fn channel_index(&self, name: &str) -> Result<usize, ImageError> {
        self.channels
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| ImageError::MissingChannel {
                file: self.source.clone(),
                name: name.to_string(),
                available: self.channels.clone(),
            })
    }

    /// The values of channel `name`, one per pixel, row-major.
    pub fn channel(&self, name: &str) -> Result<Vec<f32>, ImageError> {
        let c = self.channel_index(name)?;
        let n = self.channels.len();
        Ok(self.data.iter().skip(c).step_by(n).copied().collect())
    }

    /// Linear RGBA per pixel, for textures: `R`, `G`, `B` by name (or a
    /// grey `Y` repeated), `A` if present else 1. Colours are as stored
    /// (see [`Image::alpha_mode`]); a read image is already linear.
    pub fn rgba(&self) -> Result<Vec<[f32; 4]>, ImageError> {
        let colour = match (
            self.channel_index("R"),
            self.channel_index("G"),
            self.channel_index("B"),
        ) {
            (Ok(r), Ok(g), Ok(b)) => [r, g, b],
            (r, g, b) => match self.channel_index("Y") {
                Ok(y) => [y, y, y],
                // Name the first colour channel that is missing.
                Err(_) => return Err(r.and(g).and(b).unwrap_err()),
            },
        };
        let alpha = self.alpha_channel();
        Ok(self
            .data
            .chunks_exact(self.channels.len())
            .map(|p| {
                [
                    p[colour[0]],
                    p[colour[1]],
                    p[colour[2]],
                    alpha.map_or(1.0, |a| p[a]),
                ]
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn new_checks_shape_and_names() {
        assert!(Image::new(2, 2, names(&["R"]), vec![0.0; 4]).is_ok());
        assert!(Image::new(2, 2, names(&["R"]), vec![0.0; 3]).is_err());
        assert!(Image::new(0, 2, names(&["R"]), vec![]).is_err());
        assert!(Image::new(1, 1, names(&[]), vec![]).is_err());
        assert!(Image::new(1, 1, names(&["S0", "S0"]), vec![0.0; 2]).is_err());
        assert!(Image::new(1, 1, names(&["S0", ""]), vec![0.0; 2]).is_err());
    }

    #[test]
    fn planes_are_interleaved_and_found_by_name() {
        let img =
            Image::from_planes(2, 1, [("S2", vec![1.0, 2.0]), ("S10", vec![3.0, 4.0])]).unwrap();
        assert_eq!(img.data(), &[1.0, 3.0, 2.0, 4.0]);
        assert_eq!(img.pixel(1, 0), &[2.0, 4.0]);
        assert_eq!(img.channel("S10").unwrap(), vec![3.0, 4.0]);
        let err = img.channel("S1").unwrap_err();
        assert_eq!(
            err.to_string(),
            "the image has no channel 'S1' (it has: S2, S10)"
        );
        assert!(Image::from_planes(2, 1, [("S0", vec![1.0])]).is_err());
    }

    #[test]
    fn rgba_fills_grey_and_opaque_alpha() {
        let grey = Image::new(2, 1, names(&["Y"]), vec![0.25, 0.5]).unwrap();
        assert_eq!(
            grey.rgba().unwrap(),
            vec![[0.25, 0.25, 0.25, 1.0], [0.5, 0.5, 0.5, 1.0]]
        );
        let bgra =
            Image::new(1, 1, names(&["B", "G", "R", "A"]), vec![0.1, 0.2, 0.3, 0.4]).unwrap();
        assert_eq!(bgra.alpha_channel(), Some(3));
        assert_eq!(bgra.rgba().unwrap(), vec![[0.3, 0.2, 0.1, 0.4]]);
    }

    #[test]
    fn options_default_to_the_usual_encoding() {
        assert_eq!(WriteOptions::new(PixelType::U8).encoding, Encoding::Srgb);
        assert_eq!(WriteOptions::new(PixelType::U16).encoding, Encoding::Srgb);
        assert_eq!(
            WriteOptions::new(PixelType::Half).encoding,
            Encoding::Linear
        );
        assert_eq!(WriteOptions::default().pixel_type, PixelType::F32);
    }
}
