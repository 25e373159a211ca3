// Single rays through a BVH (bvh/bvh.h): the "bvh" tracer's kernel (trace_bvh.cpp), for tests
// and callers holding a Bvh.
#pragma once

#include <array>
#include <bit>
#include <cfloat>
#include <cstddef>
#include <cstdint>
#include <span>

#include "bvh/bvh.h"
#include "geom/triangle.h"
#include "rtt/tracer.h"
#include "simd/isa.h"
#include "simd/simd.h"
#include "simd/vec3v.h"
#include "trace/blocker_cache.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Children per node of this ISA's kernel: one node test is one vector of the ISA's widest (16
/// children against 8 on AVX-512: docs/benchmarks.md, "Arbitrary rays", the BVH's choices).
inline constexpr int bvh_width = simd_max_width;

/// Byte offsets in a BvhNode<W> of the faces rays enter and leave by on each axis: lo then hi,
/// or hi then lo where the rays' direction is negative (bit a of `negative`). From a table of
/// the eight sign patterns: computed per ray they cost 2 % of a closest-hit ray's instructions.
template <int W>
RTT_FORCEINLINE void box_faces(uint32_t negative, uint32_t (&enter)[3], uint32_t (&leave)[3]) {
    struct Faces {
        uint32_t enter[3], leave[3];
    };
    static constexpr auto table = [] {
        std::array<Faces, 8> t{};
        for (uint32_t signs = 0; signs < 8; ++signs)
            for (int a = 0; a < 3; ++a) {
                const auto lo = uint32_t(offsetof(BvhNode<W>, lo) + sizeof(float) * W * size_t(a));
                const auto hi = uint32_t(offsetof(BvhNode<W>, hi) + sizeof(float) * W * size_t(a));
                const bool down = (signs >> a) & 1u;
                t[signs].enter[a] = down ? hi : lo;
                t[signs].leave[a] = down ? lo : hi;
            }
        return t;
    }();
    const Faces& f = table[negative & 7u];
    for (int a = 0; a < 3; ++a) {
        enter[a] = f.enter[a];
        leave[a] = f.leave[a];
    }
}

/// The margin a caller with tmin >= 0 adds to far distances instead of `t_margin`
/// (widen_interval<true>), so that one fused operation widens them. leave (1 + relative) +
/// far_margin is at least the two-sided widening max(leave (1 - relative), leave (1 + relative))
/// + t_margin wherever that can reach tmin: for leave >= 0 it is; a negative leave reaches
/// tmin >= 0 only when |leave| (1 - relative) <= t_margin, and the two then differ by
/// 2 relative |leave| <= 2 relative t_margin / (1 - relative), less than the 4 relative
/// t_margin added (rounding, being monotonic, keeps the order). Elsewhere a far distance only
/// grows, and a box is only entered more often.
template <typename V>
RTT_FORCEINLINE V far_margin(V t_margin, float relative) {
    return t_margin * V(1.f + 4.f * relative);
}

/// The node tests' constants of K rays, lane by lane (docs/design.md, "The BVH for arbitrary
/// rays"): the inverse directions, the origins times them, and `t_margin`, the widening of a
/// box's interval beyond its |t| part: 2 kd_margin times the scene's t scale (trace_ray.h's
/// scene_t_scale), grown to cover the rounding of face * inv - org * inv. An axis whose
/// direction is 0 (`flat`: a face distance is NaN when the ray lies in the face's plane) or
/// whose inverse exceeds 2^40 (`free`: left unbounded) adds nothing to the origin term; the
/// tests treat such axes apart. Where the origin term would more than double the margin, the
/// lane is `subtract`: its test takes (face - org) * inv, whose margin needs no origin term (as
/// the packets' PacketRays::subtract).
template <int K>
struct BoxLanes {
    using vf = vfloat<K>;
    vf inv[3], org_inv[3], t_margin;
    vf far_t_margin;  ///< far_margin(t_margin, 2 kd_margin): the single rays' box test's.
    /// Per lane, bit a for axis a: the direction is negative, flat, free.
    vint<K> negative{0}, flat{0}, free{0};
    vbool<K> subtract;

    RTT_FORCEINLINE BoxLanes(const Vec3v<K>& org, const Vec3v<K>& dir, const Bbox3f& bounds) {
        const vf* o[3] = {&org.x, &org.y, &org.z};
        const vf* d[3] = {&dir.x, &dir.y, &dir.z};
        const vf flt_max(FLT_MAX);
        // std::min(x, FLT_MAX) lane by lane (a NaN stays).
        const auto min_flt_max = [&](vf x) { return select(flt_max < x, flt_max, x); };
        vf dist(0.f), dir_max(0.f), org_t(0.f);  // maxima: exact in any order
        for (int a = 0; a < 3; ++a) {
            inv[a] = vf(1.f) / *d[a];
            org_inv[a] = *o[a] * inv[a];
            const vbool<K> zero = *d[a] == vf(0.f), huge = !(abs(inv[a]) <= vf(0x1p40f));
            const vint<K> bit(1 << a), none(0);
            negative = negative | select(*d[a] < vf(0.f), bit, none);
            flat = flat | select(zero, bit, none);
            free = free | select(andnot(huge, zero), bit, none);
            dist = max(dist, max(abs(vf(bounds.lo[a]) - *o[a]), abs(vf(bounds.hi[a]) - *o[a])));
            dir_max = max(dir_max, abs(*d[a]));
            org_t = max(org_t, select(zero | huge, vf(0.f), abs(org_inv[a])));
        }
        const vf scale = min_flt_max(dist / dir_max);
        subtract = org_t * vf(0x1p-6f) > scale;
        t_margin =
            vf(2.f * kd_margin) * select(subtract, scale, min_flt_max(scale + org_t * vf(0x1p-6f)));
        far_t_margin = far_margin(t_margin, 2.f * kd_margin);
    }
};

/// A box's slab interval [enter, leave] widened by `relative` * |t| + `t_margin` on each side
/// (docs/design.md, "The BVH for arbitrary rays"): the nodes' tests, single ray and packet.
/// Infinities stay infinite.
/// NonNegTmin: the caller compares `near` with a tmin >= 0 only (max(near, tmin)), so a
/// negative entry distance, however widened, loses to tmin: only the shrink a non-negative one
/// needs is applied, and `far` takes `far_t_margin` (far_margin(t_margin, relative)): one
/// operation each instead of three. Otherwise `far_t_margin` is not read.
template <bool NonNegTmin = false, typename V>
RTT_FORCEINLINE void widen_interval(V enter, V leave, float relative, V t_margin, V far_t_margin,
                                    V& near, V& far) {
    const V shrink(1.f - relative), grow(1.f + relative);
    if constexpr (NonNegTmin) {
        near = mul_sub(enter, shrink, t_margin);
        far = mul_add(leave, grow, far_t_margin);
    } else {
        near = min(mul_sub(enter, shrink, t_margin), mul_sub(enter, grow, t_margin));
        far = max(mul_add(leave, grow, t_margin), mul_add(leave, shrink, t_margin));
    }
}

/// The watertight test of one ray against four triangles: triangle.h's operations, lane by lane
/// in the same order, so each lane's t and verdict are the scalar test's bit for bit.
struct WatertightRay4 {
    int kx, ky, kz;
    vfloat4 org[3], sx, sy, sz;

    explicit WatertightRay4(const WatertightRay& r)
        : kx(r.kx), ky(r.ky), kz(r.kz), sx(r.sx), sy(r.sy), sz(r.sz) {
        for (int a = 0; a < 3; ++a) org[a] = vfloat4(r.org[a]);
    }

    /// Lanes that hit in [tmin, tmax], their distances in `t`.
    RTT_FORCEINLINE uint32_t test(const BvhTriangles4& q, float tmin, float tmax,
                                  vfloat4& t) const {
        const auto rel = [&](const float(&v)[3][4], int a) { return vfloat4::load(v[a]) - org[a]; };
        const vfloat4 akz = rel(q.v0, kz), bkz = rel(q.v1, kz), ckz = rel(q.v2, kz);
        const vfloat4 ax = rel(q.v0, kx) - sx * akz, ay = rel(q.v0, ky) - sy * akz;
        const vfloat4 bx = rel(q.v1, kx) - sx * bkz, by = rel(q.v1, ky) - sy * bkz;
        const vfloat4 cx = rel(q.v2, kx) - sx * ckz, cy = rel(q.v2, ky) - sy * ckz;
        const vfloat4 u = difference_of_products(cx, by, cy, bx);
        const vfloat4 v = difference_of_products(ax, cy, ay, cx);
        const vfloat4 w = difference_of_products(bx, ay, by, ax);
        const vfloat4 zero(0.f);
        const vbool4 outside =
            ((u < zero) | (v < zero) | (w < zero)) & ((u > zero) | (v > zero) | (w > zero));
        const vfloat4 det = (u + v) + w;
        const vfloat4 az = sz * akz, bz = sz * bkz, cz = sz * ckz;
        t = ((u * az + v * bz) + w * cz) / det;
        const vbool4 in_range = (t >= vfloat4(tmin)) & (t <= vfloat4(tmax));  // false for NaN
        return movemask(in_range & !outside & !(det == zero));
    }
};

/// Calls on_hit(block, lane, t) for each triangle of the leaf blocks [first, first + count)
/// that `r` hits in [tmin, tmax], `tmax` read again for every block (on_hit may shrink it);
/// stops and returns true as soon as on_hit does (an any-hit ray's end).
template <int W, typename OnHit>
RTT_FORCEINLINE bool for_each_leaf_hit(const Bvh<W>& bvh, uint32_t first, uint32_t count,
                                       const WatertightRay4& r, float tmin, const float& tmax,
                                       OnHit&& on_hit) {
    for (uint32_t k = first; k < first + count; ++k) {
        const BvhTriangles4& q = bvh.blocks[k];
        vfloat4 t4;
        uint32_t hits = r.test(q, tmin, tmax, t4);
        if (!hits) continue;
        alignas(16) float t[4];
        store(t, t4);
        for (; hits; hits &= hits - 1) {
            const int l = std::countr_zero(hits);
            if (q.id[l] != invalid_triangle && on_hit(q, l, t[l])) return true;
        }
    }
    return false;
}

/// The closest hit of `ray` (trace_ray's, bit for bit). W = 4, or bvh_width.
template <int W>
Hit trace_bvh(const Bvh<W>& bvh, const Ray& ray);

/// Whether some triangle meets `ray` in [tmin, tmax] (occluded_ray's answer).
template <int W>
bool occluded_bvh(const Bvh<W>& bvh, const Ray& ray);

/// trace_bvh for each ray: hits[i] for rays[i] (spans of equal size).
template <int W>
void trace_bvh_rays(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<Hit> hits);

/// visible[i] = !occluded_bvh(rays[i]).
template <int W>
void visible_bvh_rays(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible);

/// trace_bvh_rays for rays that travel together (a tile's rows, one mirror's reflections):
/// packets of the ISA's widest vector share each node's fetch and box test
/// (trace_bvh_packets.cpp). Hits equal trace_bvh's. W = bvh_width.
template <int W>
void trace_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<Hit> hits);

/// visible_bvh_rays in packets, as trace_bvh_packets.
template <int W>
void visible_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible);

/// Closest hits of a tile's rays in packets of packet_width x packet_height samples (as the
/// packet tracers cut tiles): hits equal trace_bvh's. hits.size() == tile.rays.size().
template <int W>
void trace_bvh_tile(const Bvh<W>& bvh, const RayTile& tile, std::span<Hit> hits);

/// Whether each active segment of `tile` reaches its light (inactive ones: 0), in packets
/// cut as trace_bvh_tile's, each first tested against `blockers` (which notes the blockers it
/// finds for the next packets); returns the number of active segments.
template <int W>
uint64_t visible_bvh_segments(const Bvh<W>& bvh, const SegmentTile& tile,
                              std::span<uint8_t> visible, BlockerCache& blockers);

}  // namespace RTT_ISA_NS
}  // namespace rtt
