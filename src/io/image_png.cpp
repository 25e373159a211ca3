// PNG output through libpng. libpng reports errors with longjmp, so the libpng calls live in one
// function that owns no C++ objects; its failure becomes an rtt::Error outside it.
#include <png.h>

#include <string>

#include "rtt/error.h"
#include "rtt/io.h"

namespace rtt {
namespace {

struct PngError {
    char message[256] = "unknown libpng error";
};

void on_png_error(png_structp png, png_const_charp message) {
    auto* err = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(err->message, sizeof err->message, "%s", message);
    png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

/// Returns false (with err->message) when libpng fails. No C++ object may live in this frame.
bool write_png_stream(std::FILE* f, int width, int height, int channels, const uint8_t* pixels,
                      PngError* err) {
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, err, on_png_error, on_png_warning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const size_t stride = size_t(width) * size_t(channels);
    for (int y = 0; y < height; ++y) png_write_row(png, pixels + size_t(y) * stride);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

void write_png(const std::string& path, int width, int height, int channels,
               std::span<const uint8_t> pixels) {
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3))
        throw Error(path + ": invalid PNG dimensions or channel count");
    if (pixels.size() != size_t(width) * size_t(height) * size_t(channels))
        throw Error(path + ": PNG pixel count does not match its size");
    write_file_atomically(path, [&](std::FILE* f) {
        PngError err;
        if (!write_png_stream(f, width, height, channels, pixels.data(), &err))
            throw Error(path + ": cannot write PNG: " + err.message);
    });
}

}  // namespace rtt
