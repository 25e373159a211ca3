// Triangles that blocked recent shadow rays, tried first on their neighbours.
#pragma once

#include <cstdint>

#include "geom/triangle.h"
#include "geom/triangle_simd.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Triangles that blocked the last shadow packets of a tile (one light), tested on the next
/// packet's lanes before its traversal: neighbouring segments are often blocked by the same
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

/// The lanes of `lanes` that a triangle of `blockers` blocks, by the traversals' own test.
template <int K>
RTT_FORCEINLINE vbool<K> blocked_by(const BlockerCache& blockers, const WatertightPacket<K>& wp,
                                    vbool<K> lanes) {
    vbool<K> blocked(false);
    for (int c = 0; c < blockers.count; ++c) {
        vfloat<K> t;
        blocked |= intersect_watertight<K>(wp, andnot(lanes, blocked), blockers.tri[c], t);
    }
    return blocked;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
