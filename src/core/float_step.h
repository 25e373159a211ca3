// The neighbouring floats of a float, without branches or a libm call (std::nextafter is a
// call; the kd-tree build steps floats in its inner loops).
#pragma once

#include <bit>
#include <cstdint>

namespace rtt {

/// The largest float below x (x finite; -0 and +0 are one value, so both give -denorm_min).
inline float next_float_down(float x) {
    const int32_t bits = std::bit_cast<int32_t>(x + 0.f);
    const int32_t below = bits > 0 ? bits - 1 : bits < 0 ? bits + 1 : int32_t(0x80000001u);
    return std::bit_cast<float>(below);
}

/// The smallest float above x (x finite).
inline float next_float_up(float x) { return -next_float_down(-x); }

}  // namespace rtt
