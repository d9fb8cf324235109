//! Safe wrapper over the OpenImageIO shim in `spar-sys` (`sys/shim/`).
//!
//! Two calls, [`write`] and [`read`], each on one file. Both are plain
//! functions over owned or borrowed Rust data: no pointer, handle or C
//! string escapes this module. Errors are the shim's messages as they are;
//! [`crate::image`] adds the file name and decides what a caller sees.
//!
//! What the shim does on top of OpenImageIO (see `oiio_shim.h`): it refuses
//! pixel types and channel counts that a format would silently replace,
//! compresses EXR and TIFF losslessly, records the colour space it is given,
//! and decodes files that declare a non-linear colour space to linear on
//! read. Nothing here encodes colours.

use spar_sys::oiio as sys;
use std::ffi::{c_char, CStr, CString};
use std::path::Path;
use std::ptr::{self, NonNull};

/// The shim's or OpenImageIO's description of a failure.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct OiioError(pub String);

/// Sample type stored in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelType {
    U8,
    U16,
    Half,
    F32,
}

/// How the values handed to [`write`] are encoded; recorded in the file,
/// never applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorSpace {
    Linear,
    Srgb,
}

/// One image to write. `pixels` holds `width * height * channel_names.len()`
/// interleaved values, top row first.
#[derive(Debug, Clone, Copy)]
pub struct WriteRequest<'a> {
    /// The file; its extension selects the format.
    pub path: &'a Path,
    pub width: usize,
    pub height: usize,
    pub channel_names: &'a [String],
    pub pixels: &'a [f32],
    pub pixel_type: PixelType,
    /// Index of the alpha channel, if any.
    pub alpha_channel: Option<usize>,
    /// Colours are not premultiplied by alpha.
    pub unassociated_alpha: bool,
    pub color_space: ColorSpace,
    /// String metadata, as (key, value).
    pub metadata: &'a [(&'a str, &'a str)],
}

/// An image as read: float, interleaved, top row first, linear.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadImage {
    pub width: usize,
    pub height: usize,
    pub channel_names: Vec<String>,
    pub pixels: Vec<f32>,
    /// Colours are not premultiplied by alpha.
    pub unassociated_alpha: bool,
    /// The file's string metadata (without OpenImageIO's `oiio:` hints).
    pub metadata: Vec<(String, String)>,
}

/// Writes `request.path` in one go. An existing file is overwritten.
pub fn write(request: &WriteRequest<'_>) -> Result<(), OiioError> {
    let nchannels = request.channel_names.len();
    let expected = request
        .width
        .checked_mul(request.height)
        .and_then(|n| n.checked_mul(nchannels));
    if expected != Some(request.pixels.len()) {
        return Err(OiioError(format!(
            "{} pixel values for {}x{} pixels of {nchannels} channel(s)",
            request.pixels.len(),
            request.width,
            request.height
        )));
    }
    let width = to_i32(request.width, "width")?;
    let height = to_i32(request.height, "height")?;
    let nchannels_c = to_i32(nchannels, "channel count")?;
    let alpha_channel = match request.alpha_channel {
        Some(a) if a < nchannels => to_i32(a, "alpha channel")?,
        Some(a) => {
            return Err(OiioError(format!(
                "alpha channel {a} of {nchannels} channel(s)"
            )))
        }
        None => -1,
    };

    // Owned C strings first; the pointer arrays below borrow from them and
    // all of them outlive the call.
    let path = path_to_cstring(request.path)?;
    let names = request
        .channel_names
        .iter()
        .map(|n| c_string(n, "channel name"))
        .collect::<Result<Vec<_>, _>>()?;
    let name_ptrs: Vec<*const c_char> = names.iter().map(|n| n.as_ptr()).collect();
    let metadata = request
        .metadata
        .iter()
        .map(|(k, v)| Ok((c_string(k, "metadata key")?, c_string(v, "metadata value")?)))
        .collect::<Result<Vec<_>, OiioError>>()?;
    let metadata_c: Vec<sys::SparOiioKeyValue> = metadata
        .iter()
        .map(|(k, v)| sys::SparOiioKeyValue {
            key: k.as_ptr(),
            value: v.as_ptr(),
        })
        .collect();
    let color_space: &CStr = match request.color_space {
        ColorSpace::Linear => c"linear",
        ColorSpace::Srgb => c"sRGB",
    };

    let c_request = sys::SparOiioWriteRequest {
        path: path.as_ptr(),
        width,
        height,
        nchannels: nchannels_c,
        pixels: request.pixels.as_ptr(),
        channel_names: name_ptrs.as_ptr(),
        pixel_type: match request.pixel_type {
            PixelType::U8 => sys::SPAR_OIIO_PIXEL_U8,
            PixelType::U16 => sys::SPAR_OIIO_PIXEL_U16,
            PixelType::Half => sys::SPAR_OIIO_PIXEL_HALF,
            PixelType::F32 => sys::SPAR_OIIO_PIXEL_F32,
        },
        alpha_channel,
        unassociated_alpha: i32::from(request.unassociated_alpha),
        color_space: color_space.as_ptr(),
        metadata: if metadata_c.is_empty() {
            ptr::null()
        } else {
            metadata_c.as_ptr()
        },
        metadata_len: metadata_c.len(),
    };
    // SAFETY: every pointer in `c_request` points into a live Rust value of
    // this frame (`path`, `names`/`name_ptrs`, `request.pixels` whose length
    // was checked against width * height * nchannels, `metadata`/
    // `metadata_c`, a static C string), all NUL-terminated where the header
    // asks for strings. The shim only reads them during the call and
    // catches every C++ exception.
    let message = unsafe { sys::spar_oiio_write(&c_request) };
    match take_message(message) {
        None => Ok(()),
        Some(m) => Err(OiioError(m)),
    }
}

/// Draws `text` into `pixels` (`width × height × colour.len()` floats,
/// interleaved) with its baseline starting at (x, y), `size` pixels high,
/// in `font` (a font name found through the system's font directories, or a
/// font file's path).
#[allow(clippy::too_many_arguments)]
pub fn render_text(
    pixels: &mut [f32],
    width: usize,
    height: usize,
    x: i32,
    y: i32,
    text: &str,
    font: &str,
    size: u32,
    colour: &[f32],
) -> Result<(), OiioError> {
    let nchannels = colour.len();
    if nchannels == 0
        || width == 0
        || height == 0
        || width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(nchannels))
            != Some(pixels.len())
    {
        return Err(OiioError(format!(
            "render_text: {} values for {width}x{height} pixels of {nchannels} channel(s)",
            pixels.len()
        )));
    }
    let dims = (
        i32::try_from(width),
        i32::try_from(height),
        i32::try_from(nchannels),
        i32::try_from(size),
    );
    let (Ok(w), Ok(h), Ok(c), Ok(size)) = dims else {
        return Err(OiioError("render_text: image or text too large".into()));
    };
    let text =
        CString::new(text).map_err(|_| OiioError("render_text: text contains NUL".into()))?;
    let font =
        CString::new(font).map_err(|_| OiioError("render_text: font name contains NUL".into()))?;
    // SAFETY: `pixels` holds exactly w·h·c floats (checked above) and is
    // borrowed mutably for the call; `colour` holds c floats; both strings
    // are NUL-terminated and live across the call; the shim writes only
    // inside the buffer it was given and catches every C++ exception.
    let message = unsafe {
        sys::spar_oiio_render_text(
            pixels.as_mut_ptr(),
            w,
            h,
            c,
            x,
            y,
            text.as_ptr(),
            font.as_ptr(),
            size,
            colour.as_ptr(),
        )
    };
    match take_message(message) {
        None => Ok(()),
        Some(m) => Err(OiioError(m)),
    }
}

/// Reads the first subimage of `path` as linear floats.
pub fn read(path: &Path) -> Result<ReadImage, OiioError> {
    let c_path = path_to_cstring(path)?;
    let mut message: *mut c_char = ptr::null_mut();
    // SAFETY: `c_path` is NUL-terminated and lives across the call;
    // `message` is a valid place for the shim to store an owned string.
    let raw = unsafe { sys::spar_oiio_read(c_path.as_ptr(), &mut message) };
    let error = take_message(message);
    let Some(raw) = NonNull::new(raw) else {
        return Err(OiioError(error.unwrap_or_else(|| {
            "the shim returned no image and no error".into()
        })));
    };
    let image = OwnedImage(raw);
    image.to_read_image()
}

/// A `SparOiioImage` owned by Rust, freed on drop.
struct OwnedImage(NonNull<sys::SparOiioImage>);

impl Drop for OwnedImage {
    fn drop(&mut self) {
        // SAFETY: the pointer came from `spar_oiio_read`, is owned by this
        // value alone and is freed exactly once, here.
        unsafe { sys::spar_oiio_image_free(self.0.as_ptr()) }
    }
}

impl OwnedImage {
    /// Copies the image out of the shim's memory.
    fn to_read_image(&self) -> Result<ReadImage, OiioError> {
        let mut view = sys::SparOiioImageView {
            width: 0,
            height: 0,
            nchannels: 0,
            pixels: ptr::null(),
            channel_names: ptr::null(),
            alpha_channel: -1,
            unassociated_alpha: 0,
            metadata: ptr::null(),
            metadata_len: 0,
        };
        // SAFETY: `self.0` is a live image from the shim; `view` is a valid
        // place to write a `SparOiioImageView`.
        unsafe { sys::spar_oiio_image_view(self.0.as_ptr(), &mut view) };

        let width = from_i32(view.width, "width")?;
        let height = from_i32(view.height, "height")?;
        let nchannels = from_i32(view.nchannels, "channel count")?;
        let count = width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(nchannels))
            .ok_or_else(|| OiioError("image too large".into()))?;
        if view.pixels.is_null() || view.channel_names.is_null() {
            return Err(OiioError("the shim returned an empty image".into()));
        }
        // SAFETY: the view's pointers stay valid while `self` lives (the
        // header's contract); `pixels` holds width * height * nchannels
        // floats, `channel_names` holds nchannels NUL-terminated strings,
        // `metadata` holds `metadata_len` pairs of them. Everything is
        // copied before this function returns.
        let (pixels, channel_names, metadata) = unsafe {
            let pixels = std::slice::from_raw_parts(view.pixels, count).to_vec();
            let names = std::slice::from_raw_parts(view.channel_names, nchannels)
                .iter()
                .map(|&p| c_to_string(p))
                .collect::<Vec<_>>();
            let metadata = if view.metadata.is_null() || view.metadata_len == 0 {
                Vec::new()
            } else {
                std::slice::from_raw_parts(view.metadata, view.metadata_len)
                    .iter()
                    .map(|kv| (c_to_string(kv.key), c_to_string(kv.value)))
                    .collect()
            };
            (pixels, names, metadata)
        };
        Ok(ReadImage {
            width,
            height,
            channel_names,
            pixels,
            unassociated_alpha: view.unassociated_alpha != 0,
            metadata,
        })
    }
}

/// Takes ownership of a message from the shim (NULL: none) and frees it.
fn take_message(message: *mut c_char) -> Option<String> {
    if message.is_null() {
        return None;
    }
    // SAFETY: a non-null message from the shim is a NUL-terminated string
    // that the caller owns; it is copied, then freed exactly once with the
    // shim's own deallocator.
    unsafe {
        let text = CStr::from_ptr(message).to_string_lossy().into_owned();
        sys::spar_oiio_string_free(message);
        Some(text)
    }
}

/// Copies a C string owned by the shim (NULL reads as empty).
///
/// # Safety
/// `p` is null or points to a NUL-terminated string alive for the call.
unsafe fn c_to_string(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: guaranteed by the caller (see above).
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

fn c_string(s: &str, what: &str) -> Result<CString, OiioError> {
    CString::new(s).map_err(|_| OiioError(format!("{what} {s:?} contains a NUL byte")))
}

#[cfg(unix)]
fn path_to_cstring(path: &Path) -> Result<CString, OiioError> {
    use std::os::unix::ffi::OsStrExt;
    CString::new(path.as_os_str().as_bytes())
        .map_err(|_| OiioError("the file name contains a NUL byte".into()))
}

#[cfg(not(unix))]
fn path_to_cstring(path: &Path) -> Result<CString, OiioError> {
    // OpenImageIO takes UTF-8 file names.
    let s = path
        .to_str()
        .ok_or_else(|| OiioError("the file name is not valid UTF-8".into()))?;
    c_string(s, "file name")
}

fn to_i32(n: usize, what: &str) -> Result<i32, OiioError> {
    i32::try_from(n).map_err(|_| OiioError(format!("{what} {n} is too large")))
}

fn from_i32(n: i32, what: &str) -> Result<usize, OiioError> {
    usize::try_from(n).map_err(|_| OiioError(format!("negative {what} {n}")))
}
