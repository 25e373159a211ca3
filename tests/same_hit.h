// The agreement the differential tests require of two answers for one ray: the same triangle
// and the same t, bit for bit.
#pragma once

#include <bit>
#include <cstdint>

#include "rtt/math.h"

namespace rtt {

inline bool same_hit(const Hit& a, const Hit& b) {
    return a.tri == b.tri && std::bit_cast<uint32_t>(a.t) == std::bit_cast<uint32_t>(b.t);
}

}  // namespace rtt
