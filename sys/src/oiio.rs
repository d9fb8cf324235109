//! C ABI of the OpenImageIO shim (`shim/oiio_shim.h`), declared by hand.
//!
//! The header is the reference: its comments give the contract of each
//! function (ownership, lifetimes, error messages). The layout of the
//! `#[repr(C)]` structs is checked against the C compiler's in the test at
//! the bottom. The safe wrapper is `spar::native::oiio`.

use std::ffi::c_char;

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

extern "C" {
    /// Writes one image; NULL on success, else an owned message.
    pub fn spar_oiio_write(request: *const SparOiioWriteRequest) -> *mut c_char;
    /// Reads one image; NULL and an owned message in `*error` on failure.
    pub fn spar_oiio_read(path: *const c_char, error: *mut *mut c_char) -> *mut SparOiioImage;
    /// Fills `*view` from `image`.
    pub fn spar_oiio_image_view(image: *const SparOiioImage, view: *mut SparOiioImageView);
    /// Releases an image (NULL allowed).
    pub fn spar_oiio_image_free(image: *mut SparOiioImage);
    /// Releases an error message (NULL allowed).
    pub fn spar_oiio_string_free(message: *mut c_char);
    /// Draws text into a float image in place; NULL on success, else an
    /// owned message.
    pub fn spar_oiio_render_text(
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
    /// Size, alignment or field offset of the shim's structs, -1 if unknown.
    pub fn spar_oiio_abi_layout(item: *const c_char) -> i64;
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CString;
    use std::mem::{align_of, offset_of, size_of};

    fn c_layout(item: &str) -> i64 {
        let item = CString::new(item).unwrap();
        // SAFETY: `item` is a valid NUL-terminated string for the call.
        unsafe { spar_oiio_abi_layout(item.as_ptr()) }
    }

    macro_rules! check_layout {
        ($ty:ident { $($field:ident),* $(,)? }) => {{
            let name = stringify!($ty);
            assert_eq!(c_layout(&format!("{name}.size")), size_of::<$ty>() as i64, "{name} size");
            assert_eq!(c_layout(&format!("{name}.align")), align_of::<$ty>() as i64, "{name} align");
            $(
                assert_eq!(
                    c_layout(&format!("{name}.{}", stringify!($field))),
                    offset_of!($ty, $field) as i64,
                    "{name}.{}", stringify!($field)
                );
            )*
        }};
    }

    #[test]
    fn struct_layouts_match_the_header() {
        check_layout!(SparOiioKeyValue { key, value });
        check_layout!(SparOiioWriteRequest {
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
        check_layout!(SparOiioImageView {
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
        assert_eq!(c_layout("NoSuchStruct.size"), -1);
    }
}
