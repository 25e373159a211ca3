// Textures and vertex colours as the flat colours of rtt's materials (docs/robustness.md,
// "Reading policy": a texture counts as its mean colour, vertex colours as each triangle's
// mean). Decoding uses Debian's stb_image (PNG, JPEG, BMP, TGA, ...).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "rtt/math.h"

namespace rtt::detail {

/// The mean linear colour of the image file at `path`, or nothing when it cannot be decoded.
std::optional<Vec3f> mean_image_colour(const std::string& path);

/// The same for an image file's bytes in memory (a texture embedded in a glTF binary).
std::optional<Vec3f> mean_encoded_colour(std::span<const uint8_t> bytes);

/// The mean linear colour of `count` 8-bit sRGB RGBA texels (an uncompressed embedded texture).
Vec3f mean_texel_colour(const uint8_t* rgba, size_t count);

}  // namespace rtt::detail
