// Camera directions K at a time, bit for bit CameraFrame::direction (CONVENTIONS' formula): the
// renderer's ray generation and RTT's answers, which remake a tile's directions in registers
// instead of loading them.
#pragma once

#include <span>

#include "rtt/camera.h"
#include "simd/isa.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// normalize(forward + a right - b up2) for K samples of one sample row (per-lane a, one b):
/// the scalar code's float operations in its order (rtt compiles without FMA contraction), and
/// IEEE sqrt and division, so lane l equals CameraFrame::direction(a[l], b) bit for bit.
template <int K>
RTT_FORCEINLINE Vec3v<K> camera_directions(const CameraFrame& f, vfloat<K> a, float b) {
    using vf = vfloat<K>;
    const vf bv(b);
    const vf x = (vf(f.forward.x) + a * vf(f.right.x)) - bv * vf(f.up2.x);
    const vf y = (vf(f.forward.y) + a * vf(f.right.y)) - bv * vf(f.up2.y);
    const vf z = (vf(f.forward.z) + a * vf(f.right.z)) - bv * vf(f.up2.z);
    const vf len = sqrt((x * x + y * y) + z * z);
    return {x / len, y / len, z / len};
}

/// CameraFrame::a of the first `width` sample columns of a camera tile, into out[0, width).
inline void column_factors(const CameraTile& tile, int width, float* out) {
    const int k = tile.frame->aa;
    for (int sc = 0; sc < width; ++sc) out[sc] = tile.frame->a(tile.x0 + sc / k, sc % k);
}

/// CameraFrame::b of sample row sr of a camera tile.
inline float row_factor(const CameraTile& tile, int sr) {
    const int k = tile.frame->aa;
    return tile.frame->b(tile.y0 + sr / k, sr % k);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
