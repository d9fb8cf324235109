//! Safe wrapper over the OpenImageIO shim in `spar-sys` (`sys/shim/`).
//!
//! Two calls, [`write`] and [`read`], each on one file, and [`render_text`].
//! All are plain functions over owned or borrowed Rust data: no pointer,
//! handle or C string escapes this module. Errors are the shim's messages as
//! they are; [`crate::image`] adds the file name and decides what a caller
//! sees.
//!
//! What the shim does on top of OpenImageIO (see `oiio_shim.h`): it refuses
//! pixel types and channel counts that a format would silently replace,
//! compresses EXR and TIFF losslessly, records the colour space it is given,
//! and decodes files that declare a non-linear colour space to linear on
//! read. Nothing here encodes colours.
//!
//! # Loading
//! spar does not link OpenImageIO: its ~260 shared libraries would be
//! mapped at every start (0.2 s and 130 MiB even for `spar --version`). The
//! shim is a shared library of its own, `libspar_oiio.so`, linked against
//! OpenImageIO, and the first call here loads it with `dlopen` and resolves
//! its functions once for the whole process ([`library`]). It is looked for
//! at, in order:
//! 1. the path in `SPAR_OIIO_SHIM` ([`LIBRARY_ENV`]), if that is set and not
//!    empty — then nowhere else;
//! 2. `libspar_oiio.so` in the directory of the running executable (where
//!    to put it beside an installed or copied `spar`);
//! 3. the file the build wrote (`target/<profile>/build/spar-sys-*/out/`,
//!    baked into the binary), so that `cargo run`, `cargo test` and
//!    `target/release/spar` work straight from a build;
//! 4. `libspar_oiio.so` through the dynamic linker's own search
//!    (`LD_LIBRARY_PATH`, the system's library directories).
//!
//! A candidate is accepted only if its ABI version and the layout of the
//! shared structs match this build's declarations, so a stale library is
//! refused rather than called. If none loads, every call returns
//! [`OiioError::Unavailable`], which names each place tried and why it
//! failed.

use libloading::Library;
use spar_sys::oiio as sys;
use std::ffi::{c_char, CStr, CString};
use std::fmt;
use std::path::{Path, PathBuf};
use std::ptr::{self, NonNull};
use std::sync::OnceLock;

/// The environment variable that names the shim library to load (a file
/// path). When it is set, no other place is tried.
pub const LIBRARY_ENV: &str = "SPAR_OIIO_SHIM";

/// Why an OpenImageIO call failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OiioError {
    /// The shim library could not be loaded: OpenImageIO is unavailable to
    /// this process.
    #[error(transparent)]
    Unavailable(#[from] LoadError),
    /// The shim's or OpenImageIO's description of a failure.
    #[error("{0}")]
    Failed(String),
}

/// The shim library could not be loaded from any place it was looked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoadError {
    /// Each place tried, in order, with the reason it failed.
    pub attempts: Vec<Attempt>,
}

/// One place the shim library was looked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Attempt {
    /// The file, or a description of the search (the executable's
    /// directory when it is unknown, the dynamic linker's search path).
    pub place: String,
    /// Why it failed (the dynamic linker's message, or the check that
    /// refused it).
    pub reason: String,
}

impl std::error::Error for LoadError {}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "OpenImageIO is unavailable: spar's OpenImageIO library {} could not be loaded (",
            sys::LIBRARY_FILE
        )?;
        for (i, attempt) in self.attempts.iter().enumerate() {
            let sep = if i == 0 { "" } else { "; " };
            write!(f, "{sep}{}: {}", attempt.place, attempt.reason)?;
        }
        write!(
            f,
            "). Set {LIBRARY_ENV} to the library's path, or put it beside the spar executable \
             (a build writes it to target/<profile>/build/spar-sys-*/out/)"
        )
    }
}

/// The shim library, loaded, with each function resolved once. Lives in a
/// static for the rest of the process: the library is never unloaded, so
/// the function pointers stay valid.
struct Shim {
    path: PathBuf,
    write: sys::WriteFn,
    read: sys::ReadFn,
    image_view: sys::ImageViewFn,
    image_free: sys::ImageFreeFn,
    string_free: sys::StringFreeFn,
    render_text: sys::RenderTextFn,
    /// Keeps the code behind the pointers above mapped.
    _library: Library,
}

static SHIM: OnceLock<Result<Shim, LoadError>> = OnceLock::new();

/// The loaded shim, loading it on first use (once per process, whatever
/// the outcome).
fn shim() -> Result<&'static Shim, LoadError> {
    SHIM.get_or_init(|| load_first(&candidates()))
        .as_ref()
        .map_err(Clone::clone)
}

/// Loads the shim library if it is not loaded yet, and returns the file it
/// was loaded from. Every other call of this module loads it the same way;
/// this is for reporting and tests.
pub fn library() -> Result<&'static Path, LoadError> {
    shim().map(|s| s.path.as_path())
}

/// Where to look, in order (see the module documentation): Err holds a
/// place that could not even be named, for the error message.
fn candidates() -> Vec<Result<PathBuf, Attempt>> {
    if let Some(path) = std::env::var_os(LIBRARY_ENV).filter(|p| !p.is_empty()) {
        return vec![Ok(PathBuf::from(path))];
    }
    let mut list = Vec::new();
    match std::env::current_exe() {
        Ok(exe) => match exe.parent() {
            Some(dir) => list.push(Ok(dir.join(sys::LIBRARY_FILE))),
            None => list.push(Err(Attempt {
                place: format!("the directory of {}", exe.display()),
                reason: "the executable's path has no directory".into(),
            })),
        },
        Err(e) => list.push(Err(Attempt {
            place: "the executable's directory".into(),
            reason: format!("cannot find the running executable: {e}"),
        })),
    }
    let built = PathBuf::from(sys::BUILT_LIBRARY);
    if !list.iter().any(|c| c.as_ref() == Ok(&built)) {
        list.push(Ok(built));
    }
    // A bare name: the dynamic linker searches its own path.
    list.push(Ok(PathBuf::from(sys::LIBRARY_FILE)));
    list
}

/// The first candidate that loads and passes the checks.
fn load_first(candidates: &[Result<PathBuf, Attempt>]) -> Result<Shim, LoadError> {
    let mut attempts = Vec::new();
    for candidate in candidates {
        match candidate {
            Err(attempt) => attempts.push(attempt.clone()),
            Ok(path) => match open(path) {
                Ok(shim) => return Ok(shim),
                Err(reason) => attempts.push(Attempt {
                    place: if path.components().count() == 1 {
                        format!("{} on the dynamic linker's search path", path.display())
                    } else {
                        path.display().to_string()
                    },
                    reason,
                }),
            },
        }
    }
    Err(LoadError { attempts })
}

/// Loads one candidate, checks it is the shim this build declares, and
/// resolves its functions.
fn open(path: &Path) -> Result<Shim, String> {
    // The dynamic linker's own "not found" is long-winded for a missing
    // file; say it plainly (a bare name is left to the linker's search).
    if path.components().count() > 1 && !path.exists() {
        return Err("no such file".into());
    }
    // SAFETY: loading a library runs its initializers: the shim's (none of
    // its own) and those of OpenImageIO and its dependencies, which are
    // ordinary C++ static constructors with no precondition on the caller.
    // The candidates are spar's own build product or a file the user named
    // for this purpose; the checks below refuse a library that is not the
    // shim these declarations describe before any other function is called.
    let library = unsafe { Library::new(path) }.map_err(|e| e.to_string())?;

    // SAFETY: each symbol is read as the function-pointer type that
    // spar-sys declares for it from `oiio_shim.h`. The first two,
    // `spar_oiio_abi_version` and `spar_oiio_abi_layout`, are called only
    // after being found; they take no argument or a NUL-terminated string
    // and return integers. The rest are used only after the library said it
    // implements this ABI version with these struct layouts. The pointers
    // are copied out of their `Symbol`s but stay valid because `library` is
    // moved into the returned `Shim`, which lives in a static and is never
    // dropped.
    unsafe {
        let version: sys::AbiVersionFn = symbol(&library, sys::symbols::ABI_VERSION)?;
        let found = version();
        if found != sys::ABI_VERSION {
            return Err(format!(
                "it implements version {found} of the shim's interface, this spar needs \
                 version {} (a library from another build of spar?)",
                sys::ABI_VERSION
            ));
        }
        let layout: sys::AbiLayoutFn = symbol(&library, sys::symbols::ABI_LAYOUT)?;
        check_layouts(|item| {
            let item = CString::new(item).expect("layout items have no NUL");
            layout(item.as_ptr())
        })?;
        Ok(Shim {
            path: path.to_path_buf(),
            write: symbol(&library, sys::symbols::WRITE)?,
            read: symbol(&library, sys::symbols::READ)?,
            image_view: symbol(&library, sys::symbols::IMAGE_VIEW)?,
            image_free: symbol(&library, sys::symbols::IMAGE_FREE)?,
            string_free: symbol(&library, sys::symbols::STRING_FREE)?,
            render_text: symbol(&library, sys::symbols::RENDER_TEXT)?,
            _library: library,
        })
    }
}

/// The function `name` of `library`, as a `T`.
///
/// # Safety
/// `T` is the function-pointer type of the symbol `name` (NUL-terminated),
/// and the result is not used after `library` is unloaded.
unsafe fn symbol<T: Copy>(library: &Library, name: &[u8]) -> Result<T, String> {
    // SAFETY: guaranteed by the caller (see above).
    unsafe { library.get::<T>(name) }
        .map(|s| *s)
        .map_err(|e| e.to_string())
}

/// Compares the layout of the `#[repr(C)]` structs of `spar_sys::oiio`
/// with the C compiler's, as `c_layout` ("Struct.size", "Struct.align",
/// "Struct.field") reports it.
fn check_layouts(c_layout: impl Fn(&str) -> i64) -> Result<(), String> {
    use std::mem::{align_of, offset_of, size_of};
    use sys::{SparOiioImageView, SparOiioKeyValue, SparOiioWriteRequest};
    let mut mismatches = Vec::new();
    let mut check = |item: String, rust: usize| {
        let c = c_layout(&item);
        if c != rust as i64 {
            mismatches.push(format!("{item} is {c} in the library, {rust} in spar"));
        }
    };
    macro_rules! layout {
        ($ty:ident { $($field:ident),* $(,)? }) => {{
            let name = stringify!($ty);
            check(format!("{name}.size"), size_of::<$ty>());
            check(format!("{name}.align"), align_of::<$ty>());
            $( check(format!("{name}.{}", stringify!($field)), offset_of!($ty, $field)); )*
        }};
    }
    layout!(SparOiioKeyValue { key, value });
    layout!(SparOiioWriteRequest {
        path,
        width,
        height,
        nchannels,
        pixels,
        channel_names,
        pixel_type,
        alpha_channel,
        unassociated_alpha,
        color_space,
        metadata,
        metadata_len,
    });
    layout!(SparOiioImageView {
        width,
        height,
        nchannels,
        pixels,
        channel_names,
        alpha_channel,
        unassociated_alpha,
        metadata,
        metadata_len,
    });
    if mismatches.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "its structs do not match this spar's: {}",
            mismatches.join(", ")
        ))
    }
}

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
        return Err(OiioError::Failed(format!(
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
            return Err(OiioError::Failed(format!(
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
    let shim = shim()?;
    // SAFETY: `shim.write` is the library's `spar_oiio_write` (checked when
    // it loaded). Every pointer in `c_request` points into a live Rust value of
    // this frame (`path`, `names`/`name_ptrs`, `request.pixels` whose length
    // was checked against width * height * nchannels, `metadata`/
    // `metadata_c`, a static C string), all NUL-terminated where the header
    // asks for strings. The shim only reads them during the call and
    // catches every C++ exception.
    let message = unsafe { (shim.write)(&c_request) };
    match take_message(shim, message) {
        None => Ok(()),
        Some(m) => Err(OiioError::Failed(m)),
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
        return Err(OiioError::Failed(format!(
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
        return Err(OiioError::Failed(
            "render_text: image or text too large".into(),
        ));
    };
    let text = CString::new(text)
        .map_err(|_| OiioError::Failed("render_text: text contains NUL".into()))?;
    let font = CString::new(font)
        .map_err(|_| OiioError::Failed("render_text: font name contains NUL".into()))?;
    let shim = shim()?;
    // SAFETY: `shim.render_text` is the library's `spar_oiio_render_text`.
    // `pixels` holds exactly w·h·c floats (checked above) and is
    // borrowed mutably for the call; `colour` holds c floats; both strings
    // are NUL-terminated and live across the call; the shim writes only
    // inside the buffer it was given and catches every C++ exception.
    let message = unsafe {
        (shim.render_text)(
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
    match take_message(shim, message) {
        None => Ok(()),
        Some(m) => Err(OiioError::Failed(m)),
    }
}

/// Reads the first subimage of `path` as linear floats.
pub fn read(path: &Path) -> Result<ReadImage, OiioError> {
    let c_path = path_to_cstring(path)?;
    let shim = shim()?;
    let mut message: *mut c_char = ptr::null_mut();
    // SAFETY: `shim.read` is the library's `spar_oiio_read`; `c_path` is
    // NUL-terminated and lives across the call; `message` is a valid place
    // for the shim to store an owned string.
    let raw = unsafe { (shim.read)(c_path.as_ptr(), &mut message) };
    let error = take_message(shim, message);
    let Some(raw) = NonNull::new(raw) else {
        return Err(OiioError::Failed(error.unwrap_or_else(|| {
            "the shim returned no image and no error".into()
        })));
    };
    let image = OwnedImage { image: raw, shim };
    image.to_read_image()
}

/// A `SparOiioImage` owned by Rust, freed on drop.
struct OwnedImage {
    image: NonNull<sys::SparOiioImage>,
    /// The library that made it, and frees it.
    shim: &'static Shim,
}

impl Drop for OwnedImage {
    fn drop(&mut self) {
        // SAFETY: the pointer came from this library's `spar_oiio_read`, is
        // owned by this value alone and is freed exactly once, here, by the
        // same library's `spar_oiio_image_free`.
        unsafe { (self.shim.image_free)(self.image.as_ptr()) }
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
        // SAFETY: `self.image` is a live image from the shim, passed to the
        // same library's `spar_oiio_image_view`; `view` is a valid place to
        // write a `SparOiioImageView`.
        unsafe { (self.shim.image_view)(self.image.as_ptr(), &mut view) };

        let width = from_i32(view.width, "width")?;
        let height = from_i32(view.height, "height")?;
        let nchannels = from_i32(view.nchannels, "channel count")?;
        let count = width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(nchannels))
            .ok_or_else(|| OiioError::Failed("image too large".into()))?;
        if view.pixels.is_null() || view.channel_names.is_null() {
            return Err(OiioError::Failed("the shim returned an empty image".into()));
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
fn take_message(shim: &Shim, message: *mut c_char) -> Option<String> {
    if message.is_null() {
        return None;
    }
    // SAFETY: a non-null message from the shim is a NUL-terminated string
    // that the caller owns; it is copied, then freed exactly once with the
    // shim's own deallocator (`spar_oiio_string_free` of the same library).
    unsafe {
        let text = CStr::from_ptr(message).to_string_lossy().into_owned();
        (shim.string_free)(message);
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
    CString::new(s).map_err(|_| OiioError::Failed(format!("{what} {s:?} contains a NUL byte")))
}

#[cfg(unix)]
fn path_to_cstring(path: &Path) -> Result<CString, OiioError> {
    use std::os::unix::ffi::OsStrExt;
    CString::new(path.as_os_str().as_bytes())
        .map_err(|_| OiioError::Failed("the file name contains a NUL byte".into()))
}

#[cfg(not(unix))]
fn path_to_cstring(path: &Path) -> Result<CString, OiioError> {
    // OpenImageIO takes UTF-8 file names.
    let s = path
        .to_str()
        .ok_or_else(|| OiioError::Failed("the file name is not valid UTF-8".into()))?;
    c_string(s, "file name")
}

fn to_i32(n: usize, what: &str) -> Result<i32, OiioError> {
    i32::try_from(n).map_err(|_| OiioError::Failed(format!("{what} {n} is too large")))
}

fn from_i32(n: i32, what: &str) -> Result<usize, OiioError> {
    usize::try_from(n).map_err(|_| OiioError::Failed(format!("negative {what} {n}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_library_loads_and_matches_this_build() {
        // Unless the environment names another library, the one this
        // build wrote is found (beside the test binary there is none).
        if std::env::var_os(LIBRARY_ENV).is_some_and(|p| !p.is_empty()) {
            eprintln!("SKIPPED: {LIBRARY_ENV} is set");
            return;
        }
        let path = library().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(path, Path::new(sys::BUILT_LIBRARY));
    }

    #[test]
    fn a_library_that_cannot_be_loaded_is_an_error_naming_every_place() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("absent").join(sys::LIBRARY_FILE);
        let not_elf = dir.path().join("not_elf.so");
        std::fs::write(&not_elf, b"not a shared object").unwrap();
        let candidates = [
            Ok(missing.clone()),
            Err(Attempt {
                place: "the executable's directory".into(),
                reason: "unknown".into(),
            }),
            Ok(not_elf.clone()),
            Ok(PathBuf::from("libspar_oiio_does_not_exist.so")),
        ];
        let Err(error) = load_first(&candidates) else {
            panic!("loaded a library that does not exist")
        };
        assert_eq!(error.attempts.len(), 4);
        let message = error.to_string();
        for needle in [
            &format!("{}: no such file", missing.display()),
            "the executable's directory: unknown",
            &not_elf.display().to_string(),
            "libspar_oiio_does_not_exist.so on the dynamic linker's search path",
            LIBRARY_ENV,
        ] {
            assert!(message.contains(needle), "{needle:?} not in: {message}");
        }
    }

    #[test]
    fn a_library_with_other_struct_layouts_is_refused() {
        // What the compiler of the real library says passes ...
        assert_eq!(check_layouts(real_layout), Ok(()));
        // ... one field moved does not.
        let moved = |item: &str| match item {
            "SparOiioWriteRequest.pixels" => 1000,
            other => real_layout(other),
        };
        let err = check_layouts(moved).unwrap_err();
        assert!(
            err.contains("SparOiioWriteRequest.pixels is 1000 in the library"),
            "{err}"
        );
    }

    /// `spar_oiio_abi_layout` of the built library.
    fn real_layout(item: &str) -> i64 {
        let library = Path::new(sys::BUILT_LIBRARY);
        // SAFETY: the library this build wrote, loaded for the test; the
        // symbol has the type spar-sys declares and is used while `lib`
        // lives.
        unsafe {
            let lib = Library::new(library).unwrap();
            let layout: sys::AbiLayoutFn = symbol(&lib, sys::symbols::ABI_LAYOUT).unwrap();
            let item = CString::new(item).unwrap();
            layout(item.as_ptr())
        }
    }
}
