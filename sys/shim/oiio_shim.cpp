// spar's OpenImageIO shim: the C ABI of oiio_shim.h over OpenImageIO 2.x.
//
// Each entry point catches every exception and returns it as a message, so
// no C++ exception crosses into Rust. OpenImageIO reports failures of
// `ImageOutput::create` / `ImageInput::open` through the per-thread global
// `OIIO::geterror()`, and everything else through the object's own
// `geterror()`; both are drained into the returned message.

#include "oiio_shim.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace OIIO;

// The opaque image handed to C. The view pointers point into the vectors.
struct SparOiioImage {
    int32_t width = 0;
    int32_t height = 0;
    int32_t nchannels = 0;
    std::vector<float> pixels;
    std::vector<std::string> names;
    std::vector<const char*> name_ptrs;
    std::vector<std::pair<std::string, std::string>> metadata;
    std::vector<SparOiioKeyValue> metadata_view;
    int32_t alpha_channel = -1;
    int32_t unassociated_alpha = 0;
};

namespace {

// A malloc'd copy of `message` for the caller to free, never NULL.
char* owned_message(const std::string& message)
{
    std::string text = Strutil::strip(message).empty()
                           ? std::string("unknown OpenImageIO error")
                           : std::string(Strutil::strip(message));
    char* out = static_cast<char*>(std::malloc(text.size() + 1));
    if (out)
        std::memcpy(out, text.c_str(), text.size() + 1);
    // If even this allocation fails, NULL would read as success; abort is
    // the only honest answer left.
    if (!out)
        std::abort();
    return out;
}

// Message for a failed step, with whatever OpenImageIO recorded.
std::string with_detail(const std::string& what, const std::string& detail)
{
    std::string d(Strutil::strip(detail));
    return d.empty() ? what : what + ": " + d;
}

TypeDesc pixel_type_desc(int32_t pixel_type, bool* ok)
{
    *ok = true;
    switch (pixel_type) {
    case SPAR_OIIO_PIXEL_U8: return TypeDesc::UINT8;
    case SPAR_OIIO_PIXEL_U16: return TypeDesc::UINT16;
    case SPAR_OIIO_PIXEL_HALF: return TypeDesc::HALF;
    case SPAR_OIIO_PIXEL_F32: return TypeDesc::FLOAT;
    default: *ok = false; return TypeDesc::UNKNOWN;
    }
}

// Product of image dimensions, or 0 if it does not fit a size_t.
size_t checked_count(int64_t a, int64_t b, int64_t c)
{
    if (a <= 0 || b <= 0 || c <= 0)
        return 0;
    const size_t limit = std::numeric_limits<size_t>::max() / sizeof(float);
    size_t n = static_cast<size_t>(a);
    if (static_cast<size_t>(b) > limit / n)
        return 0;
    n *= static_cast<size_t>(b);
    if (static_cast<size_t>(c) > limit / n)
        return 0;
    return n * static_cast<size_t>(c);
}

// OpenImageIO's colour configuration ($OCIO, else its built-in one). Built
// once: it is read-only afterwards and its const methods are thread-safe.
const ColorConfig& colour_config()
{
    static const ColorConfig config;
    return config;
}

std::string write_image(const SparOiioWriteRequest& rq)
{
    if (!rq.path || !rq.pixels || !rq.channel_names || !rq.color_space
        || (rq.metadata_len > 0 && !rq.metadata))
        return "invalid request (null pointer)";
    if (checked_count(rq.width, rq.height, rq.nchannels) == 0)
        return "invalid image size";
    if (rq.alpha_channel < -1 || rq.alpha_channel >= rq.nchannels)
        return "alpha channel index out of range";
    bool ok;
    TypeDesc format = pixel_type_desc(rq.pixel_type, &ok);
    if (!ok)
        return "unknown pixel type";

    OIIO::geterror();  // drop any stale message left on this thread
    std::unique_ptr<ImageOutput> out = ImageOutput::create(rq.path);
    if (!out)
        return with_detail("no image writer for this file name",
                           OIIO::geterror());
    std::string format_name = out->format_name();

    // Refuse what a writer would silently drop or misrecord.
    if (rq.alpha_channel >= 0 && !out->supports("alpha"))
        return Strutil::fmt::format("the {} format cannot store alpha",
                                    format_name);
    if (format_name == "jpeg") {
        // The JPEG writer keeps the first three channels of any other count.
        if (rq.nchannels != 1 && rq.nchannels != 3)
            return "JPEG stores 1 or 3 channels only";
        // JPEG readers assume sRGB whatever the writer says.
        if (!Strutil::iequals(rq.color_space, "sRGB"))
            return "JPEG can only record sRGB-encoded values";
    }

    ImageSpec spec(rq.width, rq.height, rq.nchannels, format);
    for (int c = 0; c < rq.nchannels; ++c) {
        if (!rq.channel_names[c])
            return "invalid request (null channel name)";
        spec.channelnames[c] = rq.channel_names[c];
    }
    // The constructor guesses alpha from the channel count (4 channels:
    // the last is alpha); the caller knows better.
    spec.alpha_channel = rq.alpha_channel;
    for (size_t i = 0; i < rq.metadata_len; ++i) {
        const SparOiioKeyValue& kv = rq.metadata[i];
        if (!kv.key || !kv.value)
            return "invalid request (null metadata)";
        spec.attribute(kv.key, kv.value);
    }
    // The shim's own settings come last so that metadata cannot undo them.
    if (format_name == "openexr" || format_name == "tiff")
        spec.attribute("compression", "zip");
    spec.attribute("oiio:ColorSpace", rq.color_space);
    // Colours are premultiplied only if there is an alpha channel and the
    // caller says so. Without this hint a writer may treat a fourth channel
    // as premultiplying alpha even when alpha_channel is -1 (PNG does), and
    // divide the colours by it.
    if (rq.alpha_channel < 0 || rq.unassociated_alpha)
        spec.attribute("oiio:UnassociatedAlpha", 1);

    if (!out->open(rq.path, spec))
        return with_detail("cannot open for writing", out->geterror());
    // Writers silently substitute what their format cannot store (PNG
    // writes 8 bits for float, JPEG drops a fourth channel). Refuse instead.
    const ImageSpec& used = out->spec();
    if (used.format != format || used.nchannels != rq.nchannels) {
        std::string msg = Strutil::fmt::format(
            "the {} format cannot store {} channel(s) of {} pixels",
            format_name, rq.nchannels, format.c_str());
        // Finish the file anyway (the caller deletes it): closing a PNG
        // with no pixels makes libpng complain on stderr.
        out->write_image(TypeDesc::FLOAT, rq.pixels);
        out->close();
        return msg;
    }
    if (!out->write_image(TypeDesc::FLOAT, rq.pixels)) {
        std::string msg = with_detail("cannot write pixels", out->geterror());
        out->close();
        return msg;
    }
    if (!out->close())
        return with_detail("cannot finish the file", out->geterror());
    return std::string();
}

std::unique_ptr<SparOiioImage> read_image(const char* path, std::string* error)
{
    if (!path) {
        *error = "invalid request (null path)";
        return nullptr;
    }
    // Ask for alpha as stored: unassociated formats (PNG) are then not
    // premultiplied in their encoded domain by the reader.
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);

    OIIO::geterror();  // drop any stale message left on this thread
    std::unique_ptr<ImageInput> in = ImageInput::open(path, &config);
    if (!in) {
        *error = with_detail("cannot open as an image", OIIO::geterror());
        return nullptr;
    }
    const ImageSpec spec = in->spec();
    if (spec.deep) {
        *error = "deep images are not supported";
        return nullptr;
    }
    if (spec.depth > 1) {
        *error = "volume images are not supported";
        return nullptr;
    }
    size_t count = checked_count(spec.width, spec.height, spec.nchannels);
    if (count == 0) {
        *error = "invalid image size in file";
        return nullptr;
    }

    auto image        = std::make_unique<SparOiioImage>();
    image->width      = spec.width;
    image->height     = spec.height;
    image->nchannels  = spec.nchannels;
    image->pixels.resize(count);
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT,
                        image->pixels.data())) {
        *error = with_detail("cannot read pixels", in->geterror());
        return nullptr;
    }
    image->alpha_channel      = spec.alpha_channel;
    image->unassociated_alpha = spec.get_int_attribute("oiio:UnassociatedAlpha",
                                                       0)
                                        != 0
                                    ? 1
                                    : 0;
    in->close();

    // Decode integer samples to linear when the file declares a non-linear
    // encoding. Half and float samples are linear by convention (EXR, float
    // TIFF), whatever name a file gives its colour space.
    std::string colour_space = spec.get_string_attribute("oiio:ColorSpace");
    if (!spec.format.is_floating_point() && !colour_space.empty()
        && !colour_config().isColorSpaceLinear(colour_space)) {
        ImageSpec float_spec = spec;
        float_spec.set_format(TypeDesc::FLOAT);
        // Wraps image->pixels without copying; converted in place.
        ImageBuf buf(float_spec, image->pixels.data());
        bool premultiplied = spec.alpha_channel >= 0
                             && !image->unassociated_alpha;
        if (!ImageBufAlgo::colorconvert(buf, buf, colour_space, "linear",
                                        premultiplied, "", "",
                                        const_cast<ColorConfig*>(
                                            &colour_config()))) {
            *error = with_detail("cannot decode colour space \"" + colour_space
                                     + "\" to linear",
                                 buf.geterror());
            return nullptr;
        }
    }

    for (int c = 0; c < spec.nchannels; ++c)
        image->names.emplace_back(spec.channel_name(c));
    for (const std::string& name : image->names)
        image->name_ptrs.push_back(name.c_str());
    for (const ParamValue& p : spec.extra_attribs) {
        if (p.type() != TypeString || p.nvalues() != 1)
            continue;
        std::string key = p.name().string();
        if (Strutil::istarts_with(key, "oiio:"))
            continue;
        image->metadata.emplace_back(key, p.get_string());
    }
    for (const auto& kv : image->metadata)
        image->metadata_view.push_back({ kv.first.c_str(), kv.second.c_str() });
    return image;
}

}  // namespace

extern "C" {

int32_t spar_oiio_abi_version(void) { return SPAR_OIIO_ABI_VERSION; }

char* spar_oiio_write(const SparOiioWriteRequest* request)
{
    try {
        if (!request)
            return owned_message("invalid request (null)");
        std::string error = write_image(*request);
        return error.empty() ? nullptr : owned_message(error);
    } catch (const std::exception& e) {
        return owned_message(std::string("OpenImageIO threw: ") + e.what());
    } catch (...) {
        return owned_message("OpenImageIO threw an unknown exception");
    }
}

SparOiioImage* spar_oiio_read(const char* path, char** error)
{
    if (error)
        *error = nullptr;
    try {
        std::string message;
        std::unique_ptr<SparOiioImage> image = read_image(path, &message);
        if (!image) {
            if (error)
                *error = owned_message(message);
            return nullptr;
        }
        return image.release();
    } catch (const std::exception& e) {
        if (error)
            *error = owned_message(std::string("OpenImageIO threw: ")
                                   + e.what());
    } catch (...) {
        if (error)
            *error = owned_message("OpenImageIO threw an unknown exception");
    }
    return nullptr;
}

void spar_oiio_image_view(const SparOiioImage* image, SparOiioImageView* view)
{
    if (!view)
        return;
    *view = SparOiioImageView {};
    view->alpha_channel = -1;
    if (!image)
        return;
    view->width              = image->width;
    view->height             = image->height;
    view->nchannels          = image->nchannels;
    view->pixels             = image->pixels.data();
    view->channel_names      = image->name_ptrs.data();
    view->alpha_channel      = image->alpha_channel;
    view->unassociated_alpha = image->unassociated_alpha;
    view->metadata           = image->metadata_view.data();
    view->metadata_len       = image->metadata_view.size();
}

char* spar_oiio_render_text(float* pixels, int32_t width, int32_t height,
                            int32_t nchannels, int32_t x, int32_t y,
                            const char* text, const char* font, int32_t size,
                            const float* colour)
{
    try {
        if (!pixels || !text || !font || !colour || width <= 0 || height <= 0
            || nchannels <= 0 || size <= 0)
            return owned_message("render_text: invalid arguments");
        // Wrap the caller's buffer: ImageBuf writes straight into it.
        ImageSpec spec(width, height, nchannels, TypeDesc::FLOAT);
        ImageBuf buf(spec, pixels);
        std::vector<float> c(colour, colour + nchannels);
        if (!ImageBufAlgo::render_text(buf, x, y, text, size, font, c)) {
            std::string detail = buf.geterror();
            return owned_message(with_detail("cannot draw text", detail));
        }
        return nullptr;
    } catch (const std::exception& e) {
        return owned_message(std::string("OpenImageIO threw: ") + e.what());
    } catch (...) {
        return owned_message("OpenImageIO threw an unknown exception");
    }
}

void spar_oiio_image_free(SparOiioImage* image) { delete image; }

void spar_oiio_string_free(char* message) { std::free(message); }

int64_t spar_oiio_abi_layout(const char* item)
{
    if (!item)
        return -1;
#define SPAR_LAYOUT(S)                                                   \
    if (std::strcmp(item, #S ".size") == 0)                              \
        return static_cast<int64_t>(sizeof(S));                          \
    if (std::strcmp(item, #S ".align") == 0)                             \
        return static_cast<int64_t>(alignof(S));
#define SPAR_OFFSET(S, F)                                                \
    if (std::strcmp(item, #S "." #F) == 0)                               \
        return static_cast<int64_t>(offsetof(S, F));
    SPAR_LAYOUT(SparOiioKeyValue)
    SPAR_OFFSET(SparOiioKeyValue, key)
    SPAR_OFFSET(SparOiioKeyValue, value)
    SPAR_LAYOUT(SparOiioWriteRequest)
    SPAR_OFFSET(SparOiioWriteRequest, path)
    SPAR_OFFSET(SparOiioWriteRequest, width)
    SPAR_OFFSET(SparOiioWriteRequest, height)
    SPAR_OFFSET(SparOiioWriteRequest, nchannels)
    SPAR_OFFSET(SparOiioWriteRequest, pixels)
    SPAR_OFFSET(SparOiioWriteRequest, channel_names)
    SPAR_OFFSET(SparOiioWriteRequest, pixel_type)
    SPAR_OFFSET(SparOiioWriteRequest, alpha_channel)
    SPAR_OFFSET(SparOiioWriteRequest, unassociated_alpha)
    SPAR_OFFSET(SparOiioWriteRequest, color_space)
    SPAR_OFFSET(SparOiioWriteRequest, metadata)
    SPAR_OFFSET(SparOiioWriteRequest, metadata_len)
    SPAR_LAYOUT(SparOiioImageView)
    SPAR_OFFSET(SparOiioImageView, width)
    SPAR_OFFSET(SparOiioImageView, height)
    SPAR_OFFSET(SparOiioImageView, nchannels)
    SPAR_OFFSET(SparOiioImageView, pixels)
    SPAR_OFFSET(SparOiioImageView, channel_names)
    SPAR_OFFSET(SparOiioImageView, alpha_channel)
    SPAR_OFFSET(SparOiioImageView, unassociated_alpha)
    SPAR_OFFSET(SparOiioImageView, metadata)
    SPAR_OFFSET(SparOiioImageView, metadata_len)
#undef SPAR_LAYOUT
#undef SPAR_OFFSET
    return -1;
}

}  // extern "C"
