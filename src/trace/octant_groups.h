// Lanes of a packet grouped by the octant of their directions: the kd-tree and BVH packet
// traversals take one child order per axis, so lanes whose direction signs differ go in
// separate traversals.
#pragma once

#include <bit>
#include <cstdint>

#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Calls group(lanes, octant) once for each direction octant among the lanes `active`, in the
/// order of each octant's first lane. sx, sy, sz: the lanes' direction sign bits per axis (the
/// octant has bit a set when axis a's sign bit is, -0 included).
template <typename Group>
RTT_FORCEINLINE void for_each_octant_group(uint32_t sx, uint32_t sy, uint32_t sz, uint32_t active,
                                           Group&& group) {
    while (active) {
        const int lane = std::countr_zero(active);
        // all-ones where a lane's sign bit equals the first lane's
        const auto same = [&](uint32_t s) { return ~(s ^ (0u - ((s >> lane) & 1u))); };
        const uint32_t lanes = same(sx) & same(sy) & same(sz) & active;
        active &= ~lanes;
        group(lanes, ((sx >> lane) & 1u) | ((sy >> lane) & 1u) << 1 | ((sz >> lane) & 1u) << 2);
    }
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
