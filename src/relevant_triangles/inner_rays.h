// RTT's inner rays: K at a time (8 with AVX2, 16 with AVX-512) against the tile's relevant
// list, with the watertight test of triangle_simd.h (lane for lane the scalar test), after a
// per-ray check that the ray is one the shaft's tests speak for (shaft_accepts, K-wide).
// A ray that fails the check, or whose answer is not provably complete, is handed back to the
// caller for ordinary tracing: exactness first.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <type_traits>

#include "geom/triangle_simd.h"
#include "relevant_triangles/relevant_list.h"
#include "relevant_triangles/shaft.h"
#include "rtt/tracer.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// K consecutive samples of a tile, [base, base + K), as structure of arrays. Lanes past the
/// tile's end repeat its last ray (finite values, no slow denormals); `lanes` marks the
/// samples the block holds.
template <int K>
struct InnerRays {
    Vec3v<K> org, dir;
    vfloat<K> tmin, tmax;
    int base = 0;
    uint32_t lanes = 0;
};

/// Records base .. base + K - 1 of `records` (each `Floats` floats), read in registers
/// (load_records8/3: staging them through memory with scalar stores made every vector load
/// wait on store forwarding); a block past the end is padded with the last record.
template <int K, int Floats, typename Record>
RTT_FORCEINLINE void load_block(std::span<const Record> records, int base, vfloat<K> (&out)[Floats],
                                uint32_t& lanes) {
    static_assert(sizeof(Record) == Floats * sizeof(float) && std::is_standard_layout_v<Record>);
    const int n = int(records.size());
    const auto load = [&](const float* p) {
        if constexpr (Floats == 8)
            load_records8(p, out);
        else
            load_records3(p, out);
    };
    if (n - base >= K) [[likely]] {
        lanes = all_lanes<K>;
        load(reinterpret_cast<const float*>(records.data() + base));
        return;
    }
    lanes = (1u << (n - base)) - 1u;
    Record padded[K];
    for (int l = 0; l < K; ++l) padded[l] = records[size_t(std::min(base + l, n - 1))];
    load(reinterpret_cast<const float*>(padded));
}

/// Rays base .. base + K - 1 of `rays`.
template <int K>
RTT_FORCEINLINE InnerRays<K> load_inner_rays(std::span<const Ray> rays, int base) {
    InnerRays<K> r;
    r.base = base;
    vfloat<K> f[8];
    load_block<K, 8>(rays, base, f, r.lanes);
    r.org = {f[0], f[1], f[2]};
    r.dir = {f[3], f[4], f[5]};
    r.tmin = f[6];
    r.tmax = f[7];
    return r;
}

/// Shadow segments base .. base + K - 1 of a tile: shadow_ray(light, points[s]), the same
/// float operations (dir = p - L per component, the constant interval).
template <int K>
RTT_FORCEINLINE InnerRays<K> load_inner_segments(const Vec3f& light, std::span<const Vec3f> points,
                                                 int base) {
    using vf = vfloat<K>;
    InnerRays<K> r;
    r.base = base;
    vf p[3];
    load_block<K, 3>(points, base, p, r.lanes);
    r.org = Vec3v<K>(light);
    r.dir = {p[0] - vf(light.x), p[1] - vf(light.y), p[2] - vf(light.z)};
    r.tmin = vf(shadow_epsilon);
    r.tmax = vf(1.f - shadow_epsilon);
    return r;
}

/// Bits of the samples of the block that are not the tile's corners.
template <int K>
RTT_FORCEINLINE uint32_t without_corners(const InnerRays<K>& r, int width, int height) {
    uint32_t lanes = r.lanes;
    for (int c = 0; c < 4; ++c) {
        const int at = corner_sample(width, height, c) - r.base;
        if (at >= 0 && at < K) lanes &= ~(1u << at);
    }
    return lanes;
}

/// shaft_accepts() for K rays at once, on the constants of `wp` (built from the same rays):
/// the same comparisons on the same float values, lane by lane.
template <int K>
RTT_FORCEINLINE vbool<K> shaft_accepts(const Shaft& s, const InnerRays<K>& r,
                                       const WatertightPacket<K>& wp) {
    using vf = vfloat<K>;
    using vi = vint<K>;
    vbool<K> ok = (as_int(r.org.x) == vi(std::bit_cast<int32_t>(s.org.x))) &
                  (as_int(r.org.y) == vi(std::bit_cast<int32_t>(s.org.y))) &
                  (as_int(r.org.z) == vi(std::bit_cast<int32_t>(s.org.z)));
    ok &= (wp.kx == vi(s.kx)) & (wp.ky == vi(s.ky)) & (wp.kz == vi(s.kz));
    for (int m = 0; m < 4; ++m)
        ok &= vf(s.edge_nx[m]) * wp.sx + vf(s.edge_ny[m]) * wp.sy >= vf(s.edge_c[m]);
    const vf dz = abs(r.dir[s.kz]);
    const vf so = r.tmin * dz, eo = r.tmax * dz;
    ok &= (so >= vf(s.start_lo)) & (so <= vf(s.start_hi)) & (eo >= vf(s.end_lo)) &
          (eo <= vf(s.end_hi));
    return ok;
}

/// Watertight constants of the rays of `lanes` (see WatertightPacket).
template <int K>
RTT_FORCEINLINE WatertightPacket<K> watertight(const InnerRays<K>& r, uint32_t lanes) {
    return WatertightPacket<K>(r.org, r.dir, r.tmin, r.tmax, vbool<K>::from_bits(lanes));
}

/// A tile's relevant list with each triangle's vertices taken relative to the shaft's apex, in
/// the shaft's axis order, once per tile: the first step of the watertight test (a[kx] =
/// v0[kx] - org[kx], ...) for every ray shaft_accepts passes (it starts at the apex, with the
/// shaft's permutation), which the blocks of inner rays then skip. The same float
/// subtractions: the lanes' answers are unchanged.
struct ApexList {
    int count = 0;
    uint32_t tri[rtt_max_relevant];
    float rel[rtt_max_relevant][9];

    ApexList(const Shaft& s, const RelevantList& list, std::span<const TriangleVerts> triangles)
        : count(list.count) {
        const int k[3] = {s.kx, s.ky, s.kz};
        for (int j = 0; j < count; ++j) {
            tri[j] = list.tri[j];
            const TriangleVerts& t = triangles[list.tri[j]];
            const Vec3f* v[3] = {&t.v0, &t.v1, &t.v2};
            for (int vi = 0; vi < 3; ++vi)
                for (int a = 0; a < 3; ++a)
                    rel[j][3 * vi + a] = coord(*v[vi], k[a]) - coord(s.org, k[a]);
        }
    }
    template <int K>
    RTT_FORCEINLINE RelativeTriangle<K> get(int j) const {
        const float* r = rel[j];
        return {vfloat<K>(r[0]), vfloat<K>(r[1]), vfloat<K>(r[2]), vfloat<K>(r[3]), vfloat<K>(r[4]),
                vfloat<K>(r[5]), vfloat<K>(r[6]), vfloat<K>(r[7]), vfloat<K>(r[8])};
    }
};

/// Closest hits of the lanes `ok` (accepted by the list's shaft) over the list (closer():
/// smaller t, then smaller index).
template <int K>
RTT_FORCEINLINE PacketHit<K> closest_in_list(const WatertightPacket<K>& wp, vbool<K> ok,
                                             const ApexList& list) {
    PacketHit<K> best;
    for (int j = 0; j < list.count; ++j) {
        vfloat<K> t;
        const vbool<K> hit = intersect_watertight_relative<K>(wp, ok, list.get<K>(j), t);
        if (any(hit)) best.update(hit, t, list.tri[j]);
    }
    return best;
}

/// Lanes of `ok` (accepted by the list's shaft) that some triangle of the list blocks.
template <int K>
RTT_FORCEINLINE vbool<K> occluded_by_list(const WatertightPacket<K>& wp, vbool<K> ok,
                                          const ApexList& list) {
    vbool<K> blocked(false);
    for (int j = 0; j < list.count && any(ok); ++j) {
        vfloat<K> t;
        const vbool<K> hit = intersect_watertight_relative<K>(wp, ok, list.get<K>(j), t);
        blocked |= hit;
        ok = andnot(ok, hit);
    }
    return blocked;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
