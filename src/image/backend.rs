//! The one place that chooses the backend of [`write`] and [`read`]:
//! spar's pure-Rust codecs ([`super::pure`]) for OpenEXR and PNG in every
//! build, and OpenImageIO ([`super::oiio`]) for every other format with the
//! `native` feature. A render to PNG or EXR thus never loads OpenImageIO's
//! ~260 shared libraries (issue 13's start-up target), and both builds
//! write and read these two formats with the same code.

use super::io::{self, Backend};
use super::{Image, ImageError, WriteOptions};
use std::path::Path;

/// Writes `image` to `path`, in the format its extension names, atomically
/// (see the [module documentation](super)). The image's metadata is stored
/// as string attributes where the format allows.
///
/// 8- and 16-bit outputs clamp values to `[0, 1]` and write NaN as 0; the
/// values must already be in `options.encoding`.
pub fn write(path: &Path, image: &Image, options: WriteOptions) -> Result<(), ImageError> {
    io::write_with(DEFAULT, path, image, options)
}

/// Reads `path` (first subimage, top MIP level): linear floats, the file's
/// channel names and string metadata. See the [module documentation](super)
/// for what is decoded.
pub fn read(path: &Path) -> Result<Image, ImageError> {
    io::read_with(DEFAULT, path)
}

#[cfg(not(feature = "native"))]
const DEFAULT: &Backend = &super::pure::BACKEND;

/// By extension on write and by signature on read: the pure-Rust codecs for
/// what they handle, OpenImageIO for the rest.
#[cfg(feature = "native")]
const DEFAULT: &Backend = &Backend {
    write: |path, image, pixels, options| {
        let backend = if super::pure::writes(path) {
            &super::pure::BACKEND
        } else {
            &oiio::BACKEND
        };
        (backend.write)(path, image, pixels, options)
    },
    read: |path| {
        let backend = if super::pure::reads(path) {
            &super::pure::BACKEND
        } else {
            &oiio::BACKEND
        };
        (backend.read)(path)
    },
};

/// Every format through OpenImageIO (PNG and EXR included), for checking
/// the pure-Rust codecs against it, file for file.
#[cfg(feature = "native")]
pub mod oiio_only {
    use super::io;
    use crate::image::{Image, ImageError, WriteOptions};
    use std::path::Path;

    /// [`super::write`] through OpenImageIO whatever the format.
    pub fn write(path: &Path, image: &Image, options: WriteOptions) -> Result<(), ImageError> {
        io::write_with(&super::oiio::BACKEND, path, image, options)
    }

    /// [`super::read`] through OpenImageIO whatever the format.
    pub fn read(path: &Path) -> Result<Image, ImageError> {
        io::read_with(&super::oiio::BACKEND, path)
    }
}

/// OpenImageIO, through the shim library of `spar-sys`, loaded by
/// [`crate::native::oiio`] at the first read or write (not at start-up).
#[cfg(feature = "native")]
mod oiio {
    use crate::image::io::Backend;
    use crate::image::{AlphaMode, Cause, Encoding, Image, PixelType, WriteOptions};
    use crate::native::oiio;
    use std::path::Path;

    pub const BACKEND: Backend = Backend { write, read };

    fn cause(error: oiio::OiioError) -> Cause {
        match error {
            oiio::OiioError::Unavailable(e) => Cause::Unavailable(e),
            oiio::OiioError::Failed(message) => Cause::Backend(message),
        }
    }

    fn write(
        path: &Path,
        image: &Image,
        pixels: &[f32],
        options: WriteOptions,
    ) -> Result<(), Cause> {
        let metadata: Vec<(&str, &str)> = image
            .metadata
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect();
        oiio::write(&oiio::WriteRequest {
            path,
            width: image.width,
            height: image.height,
            channel_names: &image.channels,
            pixels,
            pixel_type: match options.pixel_type {
                PixelType::U8 => oiio::PixelType::U8,
                PixelType::U16 => oiio::PixelType::U16,
                PixelType::Half => oiio::PixelType::Half,
                PixelType::F32 => oiio::PixelType::F32,
            },
            alpha_channel: image.alpha_channel(),
            unassociated_alpha: image.alpha == AlphaMode::Straight,
            color_space: match options.encoding {
                Encoding::Linear => oiio::ColorSpace::Linear,
                Encoding::Srgb => oiio::ColorSpace::Srgb,
            },
            metadata: &metadata,
        })
        .map_err(cause)
    }

    fn read(path: &Path) -> Result<Image, Cause> {
        let raw = oiio::read(path).map_err(cause)?;
        let mut image = Image::new(raw.width, raw.height, raw.channel_names, raw.pixels)
            .map_err(|e| Cause::Backend(e.to_string()))?;
        image.alpha = if raw.unassociated_alpha {
            AlphaMode::Straight
        } else {
            AlphaMode::Premultiplied
        };
        image.metadata = raw.metadata.into_iter().collect();
        Ok(image)
    }
}
