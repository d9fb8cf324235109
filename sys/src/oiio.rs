//! C ABI of the OpenImageIO shim (`shim/oiio_shim.h`), declared by hand.
//!
//! The shim is not linked: the build script makes it a shared library of
//! its own, [`LIBRARY_FILE`] in `OUT_DIR` ([`BUILT_LIBRARY`]), linked against
//! OpenImageIO, and `spar::native::oiio` loads it with `dlopen` the first
//! time it is needed and resolves each function by its symbol name below.
//! So the functions are declared as function-pointer types, one per symbol.
//!
//! The header is the reference: its comments give the contract of each
//! function (ownership, lifetimes, error messages). The layout of the
//! `#[repr(C)]` structs is checked against the C compiler's
//! (`spar_oiio_abi_layout`) each time spar loads the library, and
//! [`ABI_VERSION`] against `spar_oiio_abi_version`. The safe wrapper is
//! `spar::native::oiio`.

use std::ffi::c_char;

/// File name of the shim library.
pub const LIBRARY_FILE: &str = "libspar_oiio.so";

/// Where the build script wrote the shim library (an absolute path inside
/// this build's `target/` directory).
pub const BUILT_LIBRARY: &str = env!("SPAR_OIIO_SHIM_BUILT");

/// `SPAR_OIIO_ABI_VERSION`: what `spar_oiio_abi_version` returns for a
/// library that matches these declarations.
pub const ABI_VERSION: i32 = 1;

/// `SPAR_OIIO_PIXEL_U8`: 8-bit unsigned integer pixels.
pub const SPAR_OIIO_PIXEL_U8: i32 = 0;
/// `SPAR_OIIO_PIXEL_U16`: 16-bit unsigned integer pixels.
pub const SPAR_OIIO_PIXEL_U16: i32 = 1;
/// `SPAR_OIIO_PIXEL_HALF`: 16-bit float pixels.
pub const SPAR_OIIO_PIXEL_HALF: i32 = 2;
/// `SPAR_OIIO_PIXEL_F32`: 32-bit float pixels.
pub const SPAR_OIIO_PIXEL_F32: i32 = 3;

/// `SparOiioKeyValue`: one string metadata entry.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SparOiioKeyValue {
    pub key: *const c_char,
    pub value: *const c_char,
}

/// `SparOiioWriteRequest`: everything `spar_oiio_write` needs.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SparOiioWriteRequest {
    pub path: *const c_char,
    pub width: i32,
    pub height: i32,
    pub nchannels: i32,
    pub pixels: *const f32,
    pub channel_names: *const *const c_char,
    pub pixel_type: i32,
    pub alpha_channel: i32,
    pub unassociated_alpha: i32,
    pub color_space: *const c_char,
    pub metadata: *const SparOiioKeyValue,
    pub metadata_len: usize,
}

/// `SparOiioImage`: opaque image owned by the caller of `spar_oiio_read`.
#[repr(C)]
pub struct SparOiioImage {
    _private: [u8; 0],
    // Not Send/Sync/Unpin by default: the safe layer decides.
    _marker: core::marker::PhantomData<(*mut u8, core::marker::PhantomPinned)>,
}

/// `SparOiioImageView`: borrowed view of a `SparOiioImage`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SparOiioImageView {
    pub width: i32,
    pub height: i32,
    pub nchannels: i32,
    pub pixels: *const f32,
    pub channel_names: *const *const c_char,
    pub alpha_channel: i32,
    pub unassociated_alpha: i32,
    pub metadata: *const SparOiioKeyValue,
    pub metadata_len: usize,
}

/// `spar_oiio_abi_version`: the library's `SPAR_OIIO_ABI_VERSION`.
pub type AbiVersionFn = unsafe extern "C" fn() -> i32;
/// `spar_oiio_write`: writes one image; NULL on success, else an owned
/// message.
pub type WriteFn = unsafe extern "C" fn(request: *const SparOiioWriteRequest) -> *mut c_char;
/// `spar_oiio_read`: reads one image; NULL and an owned message in `*error`
/// on failure.
pub type ReadFn =
    unsafe extern "C" fn(path: *const c_char, error: *mut *mut c_char) -> *mut SparOiioImage;
/// `spar_oiio_image_view`: fills `*view` from `image`.
pub type ImageViewFn =
    unsafe extern "C" fn(image: *const SparOiioImage, view: *mut SparOiioImageView);
/// `spar_oiio_image_free`: releases an image (NULL allowed).
pub type ImageFreeFn = unsafe extern "C" fn(image: *mut SparOiioImage);
/// `spar_oiio_string_free`: releases an error message (NULL allowed).
pub type StringFreeFn = unsafe extern "C" fn(message: *mut c_char);
/// `spar_oiio_render_text`: draws text into a float image in place; NULL
/// on success, else an owned message.
pub type RenderTextFn = unsafe extern "C" fn(
    pixels: *mut f32,
    width: i32,
    height: i32,
    nchannels: i32,
    x: i32,
    y: i32,
    text: *const c_char,
    font: *const c_char,
    size: i32,
    colour: *const f32,
) -> *mut c_char;
/// `spar_oiio_abi_layout`: size, alignment or field offset of the shim's
/// structs, -1 if unknown.
pub type AbiLayoutFn = unsafe extern "C" fn(item: *const c_char) -> i64;

/// The symbol names, NUL-terminated, for `dlsym`.
pub mod symbols {
    pub const ABI_VERSION: &[u8] = b"spar_oiio_abi_version\0";
    pub const WRITE: &[u8] = b"spar_oiio_write\0";
    pub const READ: &[u8] = b"spar_oiio_read\0";
    pub const IMAGE_VIEW: &[u8] = b"spar_oiio_image_view\0";
    pub const IMAGE_FREE: &[u8] = b"spar_oiio_image_free\0";
    pub const STRING_FREE: &[u8] = b"spar_oiio_string_free\0";
    pub const RENDER_TEXT: &[u8] = b"spar_oiio_render_text\0";
    pub const ABI_LAYOUT: &[u8] = b"spar_oiio_abi_layout\0";
}
