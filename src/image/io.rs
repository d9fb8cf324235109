//! What every backend of [`super::write`] and [`super::read`] shares: the
//! checks ([`write_with`], [`read_with`]) and atomic writes through a
//! temporary file. [`super::backend`] chooses the backend.

use super::{Cause, Encoding, Image, ImageError, WriteOptions};
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// What [`write_with`] and [`read_with`] hand a file to. Errors are
/// [`Cause::Backend`] for what the format or codec refused and
/// [`Cause::Io`] for what the file system refused.
pub(super) struct Backend {
    /// Writes `pixels` (the image's values, already clamped for integer
    /// outputs) to `path`, whose extension names the format.
    pub write: fn(&Path, &Image, &[f32], WriteOptions) -> Result<(), Cause>,
    /// Reads `path`: linear floats, as the module documentation says.
    pub read: fn(&Path) -> Result<Image, Cause>,
}

/// Metadata keys in OpenImageIO's own namespace (`oiio:`, any case):
/// refused by [`super::write`], left out by the pure-Rust backend's reads.
pub(super) fn is_reserved_key(key: &str) -> bool {
    key.get(..5)
        .is_some_and(|prefix| prefix.eq_ignore_ascii_case("oiio:"))
}

/// [`super::write`] through `backend`.
pub(super) fn write_with(
    backend: &Backend,
    path: &Path,
    image: &Image,
    options: WriteOptions,
) -> Result<(), ImageError> {
    let fail = |cause| ImageError::Write {
        path: path.to_path_buf(),
        cause,
    };
    if let Some(key) = image
        .metadata
        .keys()
        .find(|k| k.is_empty() || is_reserved_key(k))
    {
        return Err(fail(Cause::Invalid(format!(
            "metadata key '{key}' is empty or reserved (the oiio: namespace holds OpenImageIO's settings)"
        ))));
    }
    // No format stores a NUL inside a name or a text value (C strings end
    // there); refuse rather than cut it.
    let has_nul = |s: &String| s.contains('\0');
    if let Some((key, _)) = image
        .metadata
        .iter()
        .find(|(k, v)| has_nul(k) || has_nul(v))
    {
        return Err(fail(Cause::Invalid(format!(
            "metadata entry '{}' contains a NUL character",
            key.escape_debug()
        ))));
    }
    if let Some(name) = image.channels.iter().find(|n| has_nul(n)) {
        return Err(fail(Cause::Invalid(format!(
            "channel name '{}' contains a NUL character",
            name.escape_debug()
        ))));
    }
    if !options.pixel_type.is_integer() && options.encoding != Encoding::Linear {
        return Err(fail(Cause::Invalid(
            "half and float files hold linear values; sRGB encoding is for 8- and 16-bit files"
                .into(),
        )));
    }
    let temp = TempFile::beside(path).map_err(fail)?;

    let sanitized;
    let pixels: &[f32] = if options.pixel_type.is_integer() {
        sanitized = image.data.iter().map(|&v| to_unit(v)).collect::<Vec<_>>();
        &sanitized
    } else {
        &image.data
    };
    (backend.write)(&temp.path, image, pixels, options).map_err(|cause| {
        fail(match cause {
            // The backend saw the temporary's name; the caller knows the
            // destination's.
            Cause::Backend(message) => Cause::Backend(message.replace(
                temp.path.to_string_lossy().as_ref(),
                path.to_string_lossy().as_ref(),
            )),
            other => other,
        })
    })?;
    temp.persist(path).map_err(|e| fail(Cause::Io(e)))
}

/// [`super::read`] through `backend`.
pub(super) fn read_with(backend: &Backend, path: &Path) -> Result<Image, ImageError> {
    let fail = |cause| ImageError::Read {
        path: path.to_path_buf(),
        cause,
    };
    // Ask the file system first: its message for a missing or unreadable
    // file is clearer than a decoder's.
    let meta = fs::metadata(path).map_err(|e| fail(Cause::Io(e)))?;
    if meta.is_dir() {
        return Err(fail(Cause::Invalid("it is a directory".into())));
    }
    let mut image = (backend.read)(path).map_err(fail)?;
    image.source = Some(path.to_path_buf());
    Ok(image)
}

/// An integer output's value: clamped to `[0, 1]`, NaN as 0.
fn to_unit(v: f32) -> f32 {
    if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, 1.0)
    }
}

/// A temporary file beside its destination, removed on drop unless it was
/// renamed into place.
struct TempFile {
    path: PathBuf,
    persisted: bool,
}

impl TempFile {
    /// `dir/.name.tmp-<pid>-<n>.ext` for `dir/name`: same directory (so the
    /// rename cannot cross file systems), same extension (so the format is
    /// the same), a name no other writer in this or another process uses.
    fn beside(path: &Path) -> Result<TempFile, Cause> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let name = path
            .file_name()
            .ok_or_else(|| Cause::Invalid("the path names no file".into()))?;
        let ext = path.extension().ok_or_else(|| {
            Cause::Invalid("the file name has no extension to choose a format by".into())
        })?;
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".tmp-{}-{n}.", std::process::id()));
        temp_name.push(ext);
        Ok(TempFile {
            path: path.with_file_name(temp_name),
            persisted: false,
        })
    }

    /// Renames the temporary over `dest`.
    fn persist(mut self, dest: &Path) -> std::io::Result<()> {
        fs::rename(&self.path, dest)?;
        self.persisted = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.persisted {
            // It may never have been created; nothing else to do either way.
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Draws `text` into `image` with its baseline starting at pixel (x, y),
/// `size` pixels high, in the colour `colour` (one value per channel), using
/// `font` (a font name such as "DejaVuSans", found through the system's font
/// directories, or the path of a font file). Text outside the image is
/// clipped. Needs OpenImageIO: without the `native` feature it returns
/// [`ImageError::Invalid`] saying so.
pub fn draw_text(
    image: &mut Image,
    x: i32,
    y: i32,
    text: &str,
    size: u32,
    font: &str,
    colour: &[f32],
) -> Result<(), ImageError> {
    if colour.len() != image.channels.len() {
        return Err(ImageError::Invalid(format!(
            "{} colour values for {} channels",
            colour.len(),
            image.channels.len()
        )));
    }
    #[cfg(feature = "native")]
    {
        let (w, h) = (image.width, image.height);
        crate::native::oiio::render_text(&mut image.data, w, h, x, y, text, font, size, colour)
            .map_err(|e| ImageError::Invalid(e.to_string()))
    }
    #[cfg(not(feature = "native"))]
    {
        let _ = (x, y, text, size, font);
        Err(ImageError::Invalid(
            "drawing text needs OpenImageIO: this build of spar has no `native` feature".into(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_outputs_clamp_and_zero_nan() {
        let cases = [
            (f32::NAN, 0.0),
            (f32::INFINITY, 1.0),
            (f32::NEG_INFINITY, 0.0),
            (-0.5, 0.0),
            (1.5, 1.0),
            (0.25, 0.25),
        ];
        for (v, want) in cases {
            assert_eq!(to_unit(v), want, "{v}");
        }
    }

    #[test]
    fn temporaries_sit_beside_the_destination_with_its_extension() {
        let a = TempFile::beside(Path::new("out/dir/render.png")).unwrap();
        let b = TempFile::beside(Path::new("out/dir/render.png")).unwrap();
        assert_ne!(a.path, b.path);
        assert_eq!(a.path.parent(), Some(Path::new("out/dir")));
        assert_eq!(a.path.extension().unwrap(), "png");
        let name = a.path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".render.png.tmp-"), "{name}");
        assert!(TempFile::beside(Path::new("render")).is_err());
        assert!(TempFile::beside(Path::new("/")).is_err());
    }
}
