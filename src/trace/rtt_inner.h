// RTT's inner rays: K at a time (8 with AVX2, 16 with AVX-512) against the tile's relevant
// list, with the watertight test of triangle_simd.h (lane for lane the scalar test), after a
// per-ray check that the ray is one the shaft's tests speak for (shaft_accepts, K-wide).
// A ray that fails the check, or whose answer is not provably complete, is handed back to the
// caller for ordinary tracing: exactness first.
#pragma once

#include <bit>
#include <cstdint>

#include "geom/shaft.h"
#include "geom/triangle_simd.h"
#include "trace/rtt_corners.h"

namespace rtt {

/// Structure-of-arrays staging of up to K rays; lanes past `count` repeat lane 0 (finite).
template <int K>
struct alignas(64) InnerBatch {
    alignas(64) float org[3][K];
    alignas(64) float dir[3][K];
    alignas(64) float tmin[K];
    alignas(64) float tmax[K];
    int sample[K];
    int count = 0;

    void add(int s, const Ray& r) {
        for (int a = 0; a < 3; ++a) {
            org[a][count] = r.org[a];
            dir[a][count] = r.dir[a];
        }
        tmin[count] = r.tmin;
        tmax[count] = r.tmax;
        sample[count++] = s;
    }
    /// Fills the unused lanes; returns the mask of used ones.
    uint32_t seal() {
        for (int l = count; l < K; ++l) {
            for (int a = 0; a < 3; ++a) {
                org[a][l] = org[a][0];
                dir[a][l] = dir[a][0];
            }
            tmin[l] = tmin[0];
            tmax[l] = tmax[0];
            sample[l] = -1;
        }
        return count == 32 ? ~0u : (1u << count) - 1u;
    }
    Vec3v<K> origin() const {
        return {vfloat<K>::load(org[0]), vfloat<K>::load(org[1]), vfloat<K>::load(org[2])};
    }
    Vec3v<K> direction() const {
        return {vfloat<K>::load(dir[0]), vfloat<K>::load(dir[1]), vfloat<K>::load(dir[2])};
    }
};

/// shaft_accepts() for K rays at once, on the constants of `wp` (built from the same rays):
/// the same comparisons on the same float values, lane by lane.
template <int K>
RTT_FORCEINLINE vbool<K> shaft_accepts(const Shaft& s, const InnerBatch<K>& b,
                                       const WatertightPacket<K>& wp) {
    using vf = vfloat<K>;
    using vi = vint<K>;
    const Vec3v<K> org = b.origin();
    vbool<K> ok = (as_int(org.x) == vi(std::bit_cast<int32_t>(s.org.x))) &
                  (as_int(org.y) == vi(std::bit_cast<int32_t>(s.org.y))) &
                  (as_int(org.z) == vi(std::bit_cast<int32_t>(s.org.z)));
    ok &= (wp.kx == vi(s.kx)) & (wp.ky == vi(s.ky)) & (wp.kz == vi(s.kz));
    for (int m = 0; m < 4; ++m)
        ok &= vf(s.edge_nx[m]) * wp.sx + vf(s.edge_ny[m]) * wp.sy >= vf(s.edge_c[m]);
    const vf dz = abs(vf::load(b.dir[s.kz]));
    const vf so = vf::load(b.tmin) * dz, eo = vf::load(b.tmax) * dz;
    ok &= (so >= vf(s.start_lo)) & (so <= vf(s.start_hi)) & (eo >= vf(s.end_lo)) &
          (eo <= vf(s.end_hi));
    return ok;
}

/// Watertight constants of a batch (see WatertightPacket).
template <int K>
RTT_FORCEINLINE WatertightPacket<K> watertight(const InnerBatch<K>& b, uint32_t used) {
    using vf = vfloat<K>;
    return WatertightPacket<K>(b.origin(), b.direction(), vf::load(b.tmin), vf::load(b.tmax),
                               vbool<K>::from_bits(used));
}

/// Closest hits of the lanes `ok` over the list (closer(): smaller t, then smaller index).
template <int K>
RTT_FORCEINLINE PacketHit<K> closest_in_list(const WatertightPacket<K>& wp, vbool<K> ok,
                                             const RelevantList& list,
                                             std::span<const TriangleVerts> triangles) {
    PacketHit<K> best;
    for (int j = 0; j < list.count; ++j) {
        const uint32_t id = list.tri[j];
        vfloat<K> t;
        const vbool<K> hit = intersect_watertight<K>(wp, ok, triangles[id], t);
        if (any(hit)) best.update(hit, t, id);
    }
    return best;
}

/// Lanes of `ok` that some triangle of the list blocks.
template <int K>
RTT_FORCEINLINE vbool<K> occluded_by_list(const WatertightPacket<K>& wp, vbool<K> ok,
                                          const RelevantList& list,
                                          std::span<const TriangleVerts> triangles) {
    vbool<K> blocked(false);
    for (int j = 0; j < list.count && any(ok); ++j) {
        vfloat<K> t;
        const vbool<K> hit = intersect_watertight<K>(wp, ok, triangles[list.tri[j]], t);
        blocked |= hit;
        ok = andnot(ok, hit);
    }
    return blocked;
}

}  // namespace rtt
