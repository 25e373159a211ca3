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
inline float next_float_up(float x) {
    return -next_float_down(-x);
}

/// An unsigned key in the order of the floats (x finite; -0 and +0 are one key), so that the
/// floats between two can be bisected; float_from_order_key inverts it.
inline uint32_t float_order_key(float x) {
    const uint32_t bits = std::bit_cast<uint32_t>(x + 0.f);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}
inline float float_from_order_key(uint32_t key) {
    return std::bit_cast<float>(key & 0x80000000u ? key & 0x7fffffffu : ~key);
}

}  // namespace rtt
