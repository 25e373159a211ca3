// Triangles that blocked recent shadow rays, tried first on their neighbours.
#pragma once

#include <atomic>
#include <cstdint>

#include "geom/triangle.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Triangles that blocked the last shadow packets to a light, tested on the next packet's lanes
/// before its traversal: neighbouring segments to one light are often blocked by the same
/// triangle (docs/benchmarks.md, "Shadow rays: blockers first"). Exact because occlusion is
/// "some triangle's watertight test hits in [tmin, tmax]" and the kd-tree and BVH traversals
/// find every such triangle: a lane a cached triangle blocks is occluded, only found sooner.
/// (On a broken tree this can differ from occluded_ray; the `packet` kinds, which the tests
/// hold to trace_ray's node order even there, do not use it.)
struct BlockerCache {
    static constexpr int size = 4;
    uint32_t id[size] = {};
    TriangleVerts tri[size] = {};  ///< Copies: tested without the structure's triangle arrays.
    int count = 0;
    /// Puts triangle `i` first, dropping the oldest entry when full.
    void note(uint32_t i, const TriangleVerts& t) {
        if (count > 0 && id[0] == i) return;
        int slot = count < size ? count : size - 1;  // the entry `i` replaces
        for (int k = 0; k < count; ++k)
            if (id[k] == i) slot = k;
        if (slot == count) ++count;
        for (int k = slot; k > 0; --k) {
            id[k] = id[k - 1];
            tri[k] = tri[k - 1];
        }
        id[0] = i;
        tri[0] = t;
    }
};

/// A number for each structure whose blockers tile_blockers() keeps (never 0).
inline uint64_t new_blocker_owner() {
    static std::atomic<uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

/// The BlockerCache of `light` for `owner`, kept by this thread from one shadow tile to the
/// next: the tiles of a light are neighbours too. A few lights per thread; others recycle.
inline BlockerCache& tile_blockers(uint64_t owner, const Vec3f& light) {
    struct Slot {
        uint64_t owner = 0;
        Vec3f light;
        BlockerCache cache;
    };
    constexpr int slots = 8;
    static thread_local Slot slot[slots];
    static thread_local int next = 0;
    for (Slot& s : slot)
        if (s.owner == owner && s.light == light) return s.cache;
    Slot& s = slot[next];
    next = (next + 1) % slots;
    s = Slot{owner, light, BlockerCache{}};
    return s.cache;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
