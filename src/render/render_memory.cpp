// The memory one render needs, estimated before anything is allocated (core/memory_budget.cpp
// says why).
#include <algorithm>

#include "rtt/memory_budget.h"
#include "rtt/render.h"

namespace rtt {

uint64_t render_memory_bytes(const RenderOptions& o, const AnswerMaps& maps) {
    const uint64_t w = uint64_t(std::max(o.width, 0)), h = uint64_t(std::max(o.height, 0));
    const uint64_t k = uint64_t(std::max(o.aa, 0));
    // Sides below 2^31: w * h and k * k fit; their product saturates.
    const uint64_t pixels = w * h, samples = saturating_mul_add(pixels, k * k, 0);
    // Linear RGB (12) and the 8-bit sRGB copy written to PNG (3), one byte per map, and depth
    // and triangle (8) with a copy of each as EXR layers (another 8, and 12 for normals).
    const uint64_t per_pixel =
        15 + (maps.primary ? 1 : 0) + (maps.shadow_light >= 0 ? 1 : 0) + (o.pixel_hits ? 28 : 0);
    // Each buffer holds 4 bytes per sample, and the buffer writer's HitBuffer / ShadowBuffer
    // copies it once more.
    const uint64_t per_sample = 8 * ((o.hits_buffer ? 1 : 0) + (o.shadow_buffer ? 1 : 0));
    return saturating_mul_add(samples, per_sample, saturating_mul_add(pixels, per_pixel, 0));
}

}  // namespace rtt
