//! spar's pure-Rust image backend: OpenEXR through the [`exr`] crate and PNG
//! through the [`png`] crate, no native library.
//!
//! [`super::write`] and [`super::read`] use it for these two formats in
//! every build (and a native build for the rest goes through OpenImageIO).
//! [`write`] and [`read`] here reach it directly — with the same checks,
//! atomic write and errors as [`super::write`] and [`super::read`] — and
//! `image::oiio_only` reaches OpenImageIO directly, so that a native build
//! can check one against the other, file for file.
//!
//! It keeps the contract of the [module documentation](super), within two
//! formats:
//! - **OpenEXR** (`.exr`): half or float samples; any number of channels
//!   with any names, stored sorted as the format requires; lossless ZIP
//!   compression (16 scanlines per block, as OpenImageIO writes); every
//!   metadata entry as a string attribute, with OpenImageIO's names for
//!   the standard ones (`ImageDescription` is stored as `comments`,
//!   `Copyright` as `owner`, `DateTime` as `capDate`). Reads scanline and
//!   tiled files: the first part, its largest resolution level, its data
//!   window. Read back premultiplied, EXR's convention; [`write`] stores
//!   the values as given.
//! - **PNG** (`.png`): 8- or 16-bit samples; 1 to 4 channels, stored as
//!   grey, grey + alpha, RGB or RGBA, and read back as `Y`, `Y A`,
//!   `R G B` and `R G B A`. An alpha channel (named `A` or `Alpha`) must
//!   be the last of 2 or 4. The encoding is recorded (an `sRGB` chunk, or
//!   `gAMA` 1.0 for linear values) and decoded on read: `sRGB` chunk or no
//!   colour information → the sRGB curve ([`crate::spectrum::srgb::decode`]),
//!   a `gAMA` chunk → its power law (gamma 1 is linear). Alpha is never
//!   decoded. Premultiplied colours are divided by alpha before writing
//!   (PNG stores straight alpha). Metadata become text chunks (`tEXt`,
//!   or `iTXt` when the value is not Latin-1); keywords are limited to
//!   1–79 Latin-1 characters by the format.
//!
//! Other formats (TIFF, JPEG, …) are refused with an error that says they
//! need the `native` feature; so is [`super::draw_text`].

mod exr_file;
mod png_file;

pub(super) use super::io::is_reserved_key as is_reserved;
use super::io::{self, Backend};
use super::{Cause, Image, ImageError, WriteOptions};
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

/// [`super::write`] through this backend whatever the build.
pub fn write(path: &Path, image: &Image, options: WriteOptions) -> Result<(), ImageError> {
    io::write_with(&BACKEND, path, image, options)
}

/// [`super::read`] through this backend whatever the build.
pub fn read(path: &Path) -> Result<Image, ImageError> {
    io::read_with(&BACKEND, path)
}

pub(super) const BACKEND: Backend = Backend {
    write: write_file,
    read: read_file,
};

/// What the formats this backend does not handle need.
const OTHER_FORMATS: &str =
    "TIFF, JPEG and other formats need spar's `native` feature (OpenImageIO)";

/// A format this backend handles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Exr,
    Png,
}

fn format_from_extension(path: &Path) -> Result<Format, Cause> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "exr" => Ok(Format::Exr),
        "png" => Ok(Format::Png),
        _ => Err(Cause::Backend(format!(
            "spar's pure-Rust image backend writes OpenEXR (.exr) and PNG (.png) only, not \
             '.{ext}'; {OTHER_FORMATS}"
        ))),
    }
}

/// The format `file`'s first bytes announce, whatever its name.
fn format_from_signature(file: &mut File) -> Result<Format, Cause> {
    const PNG: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
    const EXR: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    let mut head = Vec::with_capacity(8);
    Read::by_ref(file)
        .take(8)
        .read_to_end(&mut head)
        .map_err(Cause::Io)?;
    if head.starts_with(&EXR) {
        Ok(Format::Exr)
    } else if head == PNG {
        Ok(Format::Png)
    } else if head.is_empty() {
        Err(Cause::Backend("the file is empty".into()))
    } else {
        Err(Cause::Backend(format!(
            "not an OpenEXR or PNG file, the only formats spar's pure-Rust image backend \
             reads; {OTHER_FORMATS}"
        )))
    }
}

/// Whether [`write`] handles `path`'s extension.
#[cfg(feature = "native")]
pub(super) fn writes(path: &Path) -> bool {
    format_from_extension(path).is_ok()
}

/// Whether [`read`] handles `path`: its first bytes are an OpenEXR or PNG
/// signature, or it cannot be opened (so the error is this backend's, a
/// plain file-system error).
#[cfg(feature = "native")]
pub(super) fn reads(path: &Path) -> bool {
    File::open(path).map_or(true, |mut file| format_from_signature(&mut file).is_ok())
}

fn write_file(
    path: &Path,
    image: &Image,
    pixels: &[f32],
    options: WriteOptions,
) -> Result<(), Cause> {
    // Everything the format refuses is refused before the file exists.
    match format_from_extension(path)? {
        Format::Exr => {
            let exr = exr_file::prepare(image, pixels, options)?;
            write_through(path, |out| exr_file::write(exr, out))
        }
        Format::Png => {
            let png = png_file::prepare(image, pixels, options)?;
            write_through(path, |out| png_file::write(&png, out))
        }
    }
}

/// Creates `path` and lets `encode` fill it; a failure to create or
/// finish the file is the file system's.
fn write_through(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<(), Cause>,
) -> Result<(), Cause> {
    let mut out = BufWriter::new(File::create(path).map_err(Cause::Io)?);
    encode(&mut out)?;
    out.flush().map_err(Cause::Io)
}

fn read_file(path: &Path) -> Result<Image, Cause> {
    let mut file = File::open(path).map_err(Cause::Io)?;
    let format = format_from_signature(&mut file)?;
    // Each decoder reads from the start, signature included.
    file.seek(SeekFrom::Start(0)).map_err(Cause::Io)?;
    let input = BufReader::new(file);
    match format {
        Format::Exr => exr_file::read(input),
        Format::Png => png_file::read(input),
    }
}

/// A zeroed buffer of `len` values, or an error if memory is short (a
/// corrupt header can claim any size).
fn try_buffer<T: Clone + Default>(len: usize) -> Result<Vec<T>, Cause> {
    let mut buffer = Vec::new();
    buffer.try_reserve_exact(len).map_err(|_| {
        Cause::Backend(format!(
            "the image needs {len} values, more than this machine can allocate"
        ))
    })?;
    buffer.resize(len, T::default());
    Ok(buffer)
}

/// Text read from a file: UTF-8 if it is, else Latin-1 (each byte one
/// character), so nothing is lost to a decoding error.
fn text_from_bytes(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_owned(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}
