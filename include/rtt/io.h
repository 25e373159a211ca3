// Output files: CONVENTIONS' hit (RTTH) and shadow (RTTS) buffers and PNG images, each written
// whole or not at all (temporary file in the destination folder, then rename).
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rtt/math.h"

namespace rtt {

/// Version written into, and required in, RTTH and RTTS headers.
inline constexpr uint32_t buffer_version = 1;

/// RTTH: the closest hit of every sample.
struct HitBuffer {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t spp = 0;            ///< Samples per pixel, K * K.
    std::vector<uint32_t> hits;  ///< width*height*spp triangle indices (y, x, j, i order).
};

/// RTTS: per sample, bit l set when light l is visible from the hit point.
struct ShadowBuffer {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t spp = 0;
    uint32_t nlights = 0;
    std::vector<uint32_t> bits;  ///< width*height*spp light masks; 0 for a miss.
};

/// Writes a file whole or not at all. `write` fills a temporary file created next to `path`
/// (same folder, so the final rename is atomic); the file is flushed, synced and renamed over
/// `path` only after `write` returns and every write succeeded. On any failure the temporary
/// is removed and nothing is left at `path` (an existing file there is kept unchanged).
/// I/O failures throw rtt::Error naming `path`; exceptions from `write` propagate.
void write_file_atomically(const std::string& path, const std::function<void(std::FILE*)>& write);

/// Writes CONVENTIONS' RTTH layout (little-endian). Throws rtt::Error when the payload size
/// does not match the header or the file cannot be written.
void write_hit_buffer(const std::string& path, const HitBuffer& buffer);
/// Reads an RTTH file; throws rtt::Error on a wrong magic or version, or a truncated file.
HitBuffer read_hit_buffer(const std::string& path);

/// Writes CONVENTIONS' RTTS layout (little-endian); nlights must be at most 32.
void write_shadow_buffer(const std::string& path, const ShadowBuffer& buffer);
/// Reads an RTTS file; throws rtt::Error on a wrong magic or version, or a truncated file.
ShadowBuffer read_shadow_buffer(const std::string& path);

/// Writes an 8-bit PNG, `channels` = 1 (grey) or 3 (RGB), rows top to bottom.
void write_png(const std::string& path, int width, int height, int channels,
               std::span<const uint8_t> pixels);

/// Writes an 8-bit binary PPM (P6, RGB) or PGM (P5, `channels` = 1), rows top to bottom.
void write_pnm(const std::string& path, int width, int height, int channels,
               std::span<const uint8_t> pixels);

/// Writes a PFM: linear float RGB, little-endian, rows stored bottom to top as the format says.
void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> pixels);

/// One channel of an EXR image: `name` ("R", "depth.Z", "N.X", ...) and one value per pixel,
/// rows top to bottom. Float channels are stored as 32-bit floats, uint ones as 32-bit uints.
struct ExrChannel {
    std::string name;
    std::span<const float> floats;    ///< Either floats ...
    std::span<const uint32_t> uints;  ///< ... or uints, width * height values.
};

/// Writes an OpenEXR scanline image (ZIP compression) with the given channels; layers are
/// channel-name prefixes ("depth.Z"). Whole or not at all, as write_file_atomically.
void write_exr(const std::string& path, int width, int height,
               std::span<const ExrChannel> channels);

}  // namespace rtt
