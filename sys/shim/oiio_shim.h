/* C ABI of spar's OpenImageIO shim.
 *
 * OpenImageIO is C++; this header is the small C surface that spar-sys
 * declares in `src/oiio.rs` and that `spar::native::oiio` wraps safely.
 * The shim is built as its own shared library, `libspar_oiio.so`, linked
 * against OpenImageIO; spar loads it with dlopen when it first needs it and
 * looks each function up by name, so spar itself never links OpenImageIO.
 *
 * Conventions
 * - Pixels are 32-bit floats, interleaved (all channels of a pixel are
 *   adjacent), row-major, top row first: width * height * nchannels values.
 * - Strings are NUL-terminated UTF-8 (file names are passed to OpenImageIO
 *   as bytes).
 * - Errors: a function that can fail returns (or stores through `error`) a
 *   message allocated by the shim, or NULL on success. The caller owns the
 *   message and releases it with `spar_oiio_string_free`. No C++ exception
 *   leaves the shim: each one is caught and turned into such a message.
 * - Thread safety: the shim has no global state. OpenImageIO's global error
 *   message is per thread, so independent files can be read and written
 *   from several threads at once.
 */
#pragma once

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The library is compiled with hidden visibility: only these functions are
 * exported. */
#if defined(__GNUC__)
#define SPAR_OIIO_API __attribute__((visibility("default")))
#else
#define SPAR_OIIO_API
#endif

/* Version of this C ABI: raised whenever a function's signature or meaning
 * changes, so that spar refuses a stale library found at run time (struct
 * layouts are checked separately, through spar_oiio_abi_layout). */
#define SPAR_OIIO_ABI_VERSION 1

/* Returns SPAR_OIIO_ABI_VERSION as the library was compiled. */
SPAR_OIIO_API int32_t spar_oiio_abi_version(void);

/* Pixel types stored in the file (values of `SparOiioWriteRequest.pixel_type`).
 * The caller always passes floats; OpenImageIO converts them. For the
 * integer types [0, 1] maps to the full integer range and values outside
 * it are clamped; NaN is not handled by OpenImageIO (the caller must
 * replace it). HALF turns values above 65504 into infinity. */
#define SPAR_OIIO_PIXEL_U8 0
#define SPAR_OIIO_PIXEL_U16 1
#define SPAR_OIIO_PIXEL_HALF 2
#define SPAR_OIIO_PIXEL_F32 3

/* One string metadata entry. */
typedef struct SparOiioKeyValue {
    const char* key;
    const char* value;
} SparOiioKeyValue;

/* Everything `spar_oiio_write` needs. All pointers are borrowed for the
 * duration of the call. */
typedef struct SparOiioWriteRequest {
    /* File to write; its extension selects the format (.exr, .png, .tif,
     * .jpg, ...). An existing file is overwritten. */
    const char* path;
    int32_t width;
    int32_t height;
    int32_t nchannels;
    /* width * height * nchannels floats. */
    const float* pixels;
    /* nchannels names. PNG, JPEG and TIFF do not store names. */
    const char* const* channel_names;
    /* SPAR_OIIO_PIXEL_*. If the format cannot store this type the write
     * fails (OpenImageIO would otherwise silently substitute another). */
    int32_t pixel_type;
    /* Index of the alpha channel, or -1 for none. */
    int32_t alpha_channel;
    /* Nonzero if colours are not premultiplied by alpha: sets
     * `oiio:UnassociatedAlpha`, so PNG output is not un-premultiplied a
     * second time. Without an alpha channel it is set whatever this says
     * (PNG would otherwise divide three channels by a fourth). */
    int32_t unassociated_alpha;
    /* How the values are already encoded, recorded as `oiio:ColorSpace`:
     * "linear" or "sRGB". Nothing is converted on write. JPEG can only
     * record sRGB; anything else is an error for it. Half and float files
     * are read back as linear whatever they record. */
    const char* color_space;
    /* String metadata, written as file attributes where the format allows
     * (EXR keeps every key; PNG, TIFF and JPEG keep fewer). Applied before
     * the shim's own settings (compression, colour space, alpha), which
     * therefore win. */
    const SparOiioKeyValue* metadata;
    size_t metadata_len;
} SparOiioWriteRequest;

/* Writes one image. EXR and TIFF are written with lossless "zip"
 * compression. Returns NULL on success, else an owned error message. */
SPAR_OIIO_API char* spar_oiio_write(const SparOiioWriteRequest* request);

/* An image read by `spar_oiio_read`; owned by the caller, released with
 * `spar_oiio_image_free`. */
typedef struct SparOiioImage SparOiioImage;

/* Borrowed view of a `SparOiioImage`: every pointer stays valid until the
 * image is freed. */
typedef struct SparOiioImageView {
    int32_t width;
    int32_t height;
    int32_t nchannels;
    /* width * height * nchannels floats, linear (see spar_oiio_read). */
    const float* pixels;
    /* nchannels names, in the file's order (EXR: sorted by name). */
    const char* const* channel_names;
    /* Index of the alpha channel, or -1. */
    int32_t alpha_channel;
    /* Nonzero if colours are not premultiplied by alpha. */
    int32_t unassociated_alpha;
    /* The file's string metadata, without OpenImageIO's own hints
     * (keys starting with "oiio:"). */
    const SparOiioKeyValue* metadata;
    size_t metadata_len;
} SparOiioImageView;

/* Reads the first subimage of a file (the top MIP level, the data window)
 * as float. Integer samples whose file declares a non-linear colour space
 * (8- and 16-bit PNG and JPEG unless they say otherwise, TIFF tagged sRGB,
 * PNG with a gamma) are decoded to linear by OpenImageIO; alpha is left as
 * it is; an encoding OpenImageIO cannot decode is an error. Half and float
 * samples (EXR, float TIFF) and files that declare nothing (untagged TIFF)
 * are returned as stored. Returns NULL and stores an owned message in
 * *error on failure; *error is set to NULL on success. */
SPAR_OIIO_API SparOiioImage* spar_oiio_read(const char* path, char** error);

/* Fills *view from an image. */
SPAR_OIIO_API void spar_oiio_image_view(const SparOiioImage* image,
                                        SparOiioImageView* view);

/* Releases an image (NULL is allowed). */
SPAR_OIIO_API void spar_oiio_image_free(SparOiioImage* image);

/* Releases an error message (NULL is allowed). */
SPAR_OIIO_API void spar_oiio_string_free(char* message);

/* Draws `text` into a float image in place (width * height * nchannels
 * values, interleaved, top row first), its baseline starting at pixel
 * (x, y), `size` pixels high, in `font` (a font name such as "DejaVuSans",
 * found through the system's font directories, or a path to a font file)
 * and `colour` (nchannels floats). Returns NULL on success, else an owned
 * message (for example when the font cannot be found). */
SPAR_OIIO_API char* spar_oiio_render_text(float* pixels, int32_t width,
                                          int32_t height, int32_t nchannels,
                                          int32_t x, int32_t y,
                                          const char* text, const char* font,
                                          int32_t size, const float* colour);

/* Layout of the structs above as this compiler sees them, which spar checks
 * against its own declarations when it loads the library: `item` is "<Struct>.size", "<Struct>.align" or
 * "<Struct>.<field>" (the field's offset). Returns -1 for an unknown item. */
SPAR_OIIO_API int64_t spar_oiio_abi_layout(const char* item);

#ifdef __cplusplus
}
#endif
