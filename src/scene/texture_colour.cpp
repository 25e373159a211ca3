#include "scene/texture_colour.h"

#include <array>
#include <cmath>
#include <limits>
#include <memory>

// stb_image is compiled into this file alone (static functions), so it is no link dependency.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO_WARNINGS
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace rtt::detail {
namespace {

const std::array<float, 256>& srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}

/// Mean of stb_image's decoded RGBA texels; nothing when decoding failed or the image is empty.
std::optional<Vec3f> mean_of(stbi_uc* pixels, int width, int height) {
    const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> owned(pixels, stbi_image_free);
    if (!pixels || width <= 0 || height <= 0) return std::nullopt;
    return mean_texel_colour(pixels, size_t(width) * size_t(height));
}

/// Textures beyond this many texels are not decoded (4 bytes each in memory).
constexpr long long max_texels = 1ll << 26;

bool too_large(int ok, int width, int height) {
    return !ok || (long long)width * (long long)height > max_texels;
}

}  // namespace

Vec3f mean_texel_colour(const uint8_t* rgba, size_t count) {
    if (count == 0) return Vec3f{0.f};
    const std::array<float, 256>& lin = srgb_table();
    double sum[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c) sum[c] += lin[rgba[4 * i + size_t(c)]];
    const double n = double(count);
    return Vec3f{float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}

std::optional<Vec3f> mean_image_colour(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    if (too_large(stbi_info(path.c_str(), &w, &h, &channels), w, h)) return std::nullopt;
    return mean_of(stbi_load(path.c_str(), &w, &h, &channels, 4), w, h);
}

std::optional<Vec3f> mean_encoded_colour(std::span<const uint8_t> bytes) {
    if (bytes.empty() || bytes.size() > size_t(std::numeric_limits<int>::max()))
        return std::nullopt;
    int w = 0, h = 0, channels = 0;
    const int n = int(bytes.size());
    if (too_large(stbi_info_from_memory(bytes.data(), n, &w, &h, &channels), w, h))
        return std::nullopt;
    return mean_of(stbi_load_from_memory(bytes.data(), n, &w, &h, &channels, 4), w, h);
}

}  // namespace rtt::detail
