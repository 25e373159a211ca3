// The "bvh" tracer: single rays through a W-wide BVH (bvh/bvh.h), a node's children tested in
// one W-lane vector, nearest first. Exact: a node is skipped only when the ray's interval in its
// box, widened by the kd-tree's split margin, starts after the closest hit so far (docs/design.md,
// "The BVH for arbitrary rays"); triangles are tested with the one watertight test and ties go to
// the smaller index, so hits equal trace_ray's bit for bit.
#include "trace/trace_bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "simd/simd.h"
#include "trace/kernels.h"
#include "trace/trace_ray.h"
#include "trace/traced_tile.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

/// What the node test needs of a ray, broadcast to W lanes.
template <int W>
struct BoxRay {
    using vf = vfloat<W>;
    vf inv[3], org_inv[3];
    vf org[3];  ///< Only for rays that are not plain (below).
    /// The widening of a box's interval beyond its |t| part: 2 kd_margin times the scene's t
    /// scale, grown to cover the rounding of face * inv - org * inv (docs/design.md, "The BVH
    /// for arbitrary rays").
    vf t_margin;
    /// Byte offsets in a node of the faces a ray enters and leaves by on each axis (hi when
    /// dir < 0): fixed per ray, so a node's test picks no faces.
    uint32_t enter[3], leave[3];
    // Set only when the ray is not plain (an axis flat or free), for the test's slow path:
    bool flat[3];  ///< dir[a] == 0: a face distance is NaN when the ray lies in the face's plane.
    bool free[3];  ///< |1 / dir[a]| beyond 2^40: the axis is left unbounded (never culls).
    bool plain;    ///< No axis flat or free.
    bool nonneg_tmin;  ///< tmin >= 0 (widen_interval).

    BoxRay(const Ray& ray, const Bbox3f& bounds) {
        // The three axes at once in lanes 0-2 (lane 3 a copy of z): one division, no branches.
        const auto xyz = [](const Vec3f& v) { return vfloat4::setr(v.x, v.y, v.z, v.z); };
        const vfloat4 o = xyz(ray.org), d = xyz(ray.dir), i = vfloat4(1.f) / d, oi = o * i;
        const vbool4 zero = d == vfloat4(0.f), huge = !(abs(i) <= vfloat4(0x1p40f));
        // The t scale of trace_ray.h's scene_t_scale, and the largest |org * inv| of the axes
        // the fast test uses.
        const vfloat4 dist = max(abs(xyz(bounds.lo) - o), abs(xyz(bounds.hi) - o));
        const float scale = std::min(reduce_max(dist)[0] / reduce_max(abs(d))[0], FLT_MAX);
        const float org_t = reduce_max(select(zero | huge, vfloat4(0.f), abs(oi)))[0];
        t_margin = vf(2.f * kd_margin * std::min(scale + org_t * 0x1p-6f, FLT_MAX));
        const uint32_t flat_bits = movemask(zero), free_bits = movemask(andnot(huge, zero));
        const uint32_t negative = movemask(d < vfloat4(0.f));
        plain = ((flat_bits | free_bits) & 7u) == 0;
        nonneg_tmin = ray.tmin >= 0.f;
        for (int a = 0; a < 3; ++a) {
            inv[a] = vf(i[a]);
            org_inv[a] = vf(oi[a]);
        }
        box_faces<W>(negative, enter, leave);
        if (!plain) [[unlikely]] {
            for (int a = 0; a < 3; ++a) {
                org[a] = vf(o[a]);
                flat[a] = (flat_bits >> a) & 1u;
                free[a] = (free_bits >> a) & 1u;
            }
        }
    }

    /// Lanes of the node's children whose box the ray may meet in [tmin, tmax]; their entry
    /// distances (widened) in `near`.
    RTT_FORCEINLINE uint32_t test(const BvhNode<W>& n, float tmin, float tmax, vf& near) const {
        vf tn(neg_inf), tf(pos_inf);
        if (plain) [[likely]] {
            // dir[a] != 0: the entry face gives the smaller distance (a padding slot's +-inf
            // box gives tn = +inf, and the slot is masked anyway).
            const char* base = reinterpret_cast<const char*>(&n);
            const auto face = [&](uint32_t offset, int a) {
                return mul_sub(vf::load(reinterpret_cast<const float*>(base + offset)), inv[a],
                               org_inv[a]);
            };
            tn = max(max(face(enter[0], 0), face(enter[1], 1)), face(enter[2], 2));
            tf = min(min(face(leave[0], 0), face(leave[1], 1)), face(leave[2], 2));
        } else {
            for (int a = 0; a < 3; ++a) {
                if (free[a]) continue;
                const vf dlo = (vf::load(n.lo[a]) - org[a]) * inv[a];
                const vf dhi = (vf::load(n.hi[a]) - org[a]) * inv[a];
                vf na = min(dlo, dhi), fa = max(dlo, dhi);
                if (flat[a]) {  // in a face's plane: inside the closed slab
                    const auto in_plane = isnan(dlo) | isnan(dhi);
                    na = select(in_plane, vf(neg_inf), na);
                    fa = select(in_plane, vf(pos_inf), fa);
                }
                tn = max(tn, na);
                tf = min(tf, fa);
            }
        }
        // Widened by twice the margin of trace_ray's split distances: (1 -+ 2 kd_margin) scales
        // |t| down or up whatever its sign; infinities stay infinite.
        vf far;
        if (nonneg_tmin)
            widen_interval<true>(tn, tf, 2.f * kd_margin, t_margin, near, far);
        else
            widen_interval(tn, tf, 2.f * kd_margin, t_margin, near, far);
        const uint32_t used = (1u << n.count) - 1u;
        return movemask(max(near, vf(tmin)) <= min(far, vf(tmax))) & used;
    }
};

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
        const vfloat4 u = cx * by - cy * bx;
        const vfloat4 v = ax * cy - ay * cx;
        const vfloat4 w = bx * ay - by * ax;
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

struct StackEntry {
    uint32_t child;
    float near;
};

#ifdef RTT_HAVE_SIMD8
/// For each 8-bit mask, its set lanes from the highest down, one byte each.
constexpr auto descending_lanes = [] {
    std::array<uint64_t, 256> table{};
    for (uint32_t m = 0; m < 256; ++m)
        for (int lane = 7, n = 0; lane >= 0; --lane)
            if ((m >> lane) & 1u) table[m] |= uint64_t(lane) << (8 * n++);
    return table;
}();
#endif

/// Pushes the children of `mask` so that they pop in slot order, the lowest first; returns how
/// many. An any-hit ray takes the builder's order (order_for_any_hit) and needs no distances.
/// Wide nodes push without a loop, whose exit mispredicts about once a node; the full-width
/// store needs W spare slots above the stack's top.
template <int W>
RTT_FORCEINLINE int push_in_slot_order(const BvhNode<W>& node, uint32_t mask, uint32_t* top) {
    const int n = std::popcount(mask);
#ifdef RTT_HAVE_SIMD16
    if constexpr (W == 16) {
        // The lanes in use packed from lane 0, then reversed.
        const vint16 packed = compress(vbool16::from_bits(mask),
                                       vint16::load(reinterpret_cast<const int32_t*>(node.child)));
        storeu(reinterpret_cast<int32_t*>(top), permute(packed, vint16(n - 1) - vint16::step()));
        return n;
    }
#endif
#ifdef RTT_HAVE_SIMD8
    if constexpr (W == 8) {
        const vint8 child = vint8::load(reinterpret_cast<const int32_t*>(node.child));
        storeu(reinterpret_cast<int32_t*>(top),
               permute(child, widen_bytes(descending_lanes[mask])));
        return n;
    }
#endif
    for (int k = 0; mask; ++k) {
        const int last = 31 - std::countl_zero(mask);
        top[k] = node.child[last];
        mask &= ~(1u << last);
    }
    return n;
}

template <int W, bool AnyHit>
Hit traverse(const Bvh<W>& bvh, const Ray& ray) {
    Hit best;
    if (bvh.nodes.empty()) return best;
    WatertightRay wr(ray);
    const WatertightRay4 wr4(wr);
    const BoxRay<W> br(ray, bvh.padded_bounds);
    // Each node pushes at most W - 1 children: W - 1 per level, bvh_max_depth levels. Any-hit
    // rays need no distances.
    std::conditional_t<AnyHit, uint32_t, StackEntry> stack[(W - 1) * bvh_max_depth + W];
    int top = 0;
    uint32_t cur = 0;  // the root
    for (;;) {
        if (cur & bvh_leaf_bit) {
            const uint32_t first = (cur & ~bvh_leaf_bit) >> 3, count = cur & 7u;
            for (uint32_t k = first; k < first + count; ++k) {
                const BvhTriangles4& q = bvh.blocks[k];
                vfloat4 t4;
                uint32_t hits = wr4.test(q, ray.tmin, wr.tmax, t4);
                if (!hits) continue;
                alignas(16) float t[4];
                store(t, t4);
                for (; hits; hits &= hits - 1) {
                    const int l = std::countr_zero(hits);
                    if (q.id[l] == invalid_triangle) continue;
                    if constexpr (AnyHit) return Hit{t[l], q.id[l]};
                    if (closer(t[l], q.id[l], best)) {
                        best = {t[l], q.id[l]};
                        wr.tmax = t[l];  // inclusive: equal t still reaches the tie-break
                    }
                }
            }
        } else {
            const BvhNode<W>& node = bvh.nodes[cur];
            vfloat<W> near;
            uint32_t mask = br.test(node, ray.tmin, wr.tmax, near);
            if constexpr (AnyHit) {
                // Any hit ends the ray: no distance to sort by.
                if (mask) {
                    // Children in slot order, the builder's likeliest blocker first
                    // (order_for_any_hit): the first now, the others pushed from the last so
                    // that they pop in that order.
                    cur = node.child[std::countr_zero(mask)];
                    top += push_in_slot_order(node, mask & (mask - 1), stack + top);
                    continue;
                }
            } else if (mask) {
                alignas(4 * W) float d[W];
                store(d, near);
                int i = std::countr_zero(mask);
                mask &= mask - 1;
                if (!mask) {  // one child: down without the stack
                    cur = node.child[i];
                    continue;
                }
                int j = std::countr_zero(mask);
                mask &= mask - 1;
                if (d[j] < d[i]) std::swap(i, j);
                if (!mask) {  // two: the far one waits
                    stack[top++] = {node.child[j], d[j]};
                    cur = node.child[i];
                    continue;
                }
                // Three or more: the rest sorted far to near on the stack, the nearest next.
                int order[W] = {j, i}, n = 2;
                for (; mask; mask &= mask - 1) {
                    const int c = std::countr_zero(mask);
                    int k = n++;
                    for (; k > 0 && d[order[k - 1]] < d[c]; --k) order[k] = order[k - 1];
                    order[k] = c;
                }
                for (int k = 0; k < n - 1; ++k) stack[top++] = {node.child[order[k]], d[order[k]]};
                cur = node.child[order[n - 1]];
                continue;
            }
        }
        // Next: the nearest waiting subtree that may still hold a closer hit.
        if constexpr (AnyHit) {
            if (top == 0) return best;
            cur = stack[--top];
        } else {
            for (;;) {
                if (top == 0) return best;
                const StackEntry& e = stack[--top];
                if (e.near <= wr.tmax) {
                    cur = e.child;
                    break;
                }
            }
        }
    }
}

template <int W>
class BvhTracer final : public Tracer {
public:
    BvhTracer(const Scene& scene, const BvhBuildOptions& options)
        : bvh_(build_bvh<W>(BuildTriangles(scene), options)),
          name_(options.spatial_split_budget > 0.f ? "bvh-high" : "bvh") {}
    std::string_view name() const override { return name_; }

    // A tile's rays travel together: packets (trace_bvh_packets.cpp).
    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        trace_bvh_tile(bvh_, tile, hits);
        record_traced_tile(tile.rays.size(), context);
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        BlockerCache blockers;
        record_traced_tile(visible_bvh_segments(bvh_, tile, visible, blockers), context);
    }

    void intersect_arbitrary(std::span<const Ray> rays, std::span<Hit> hits,
                             TraceStats* stats) const override {
        trace_bvh_rays(bvh_, rays, hits);
        record_traced_tile(rays.size(), stats);
    }

    void visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                           TraceStats* stats) const override {
        visible_bvh_rays(bvh_, rays, visible);
        record_traced_tile(rays.size(), stats);
    }

private:
    Bvh<W> bvh_;
    std::string_view name_;
};

}  // namespace

template <int W>
Hit trace_bvh(const Bvh<W>& bvh, const Ray& ray) {
    return traverse<W, false>(bvh, ray);
}

template <int W>
bool occluded_bvh(const Bvh<W>& bvh, const Ray& ray) {
    return traverse<W, true>(bvh, ray).valid();
}

template <int W>
void trace_bvh_rays(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = traverse<W, false>(bvh, rays[i]);
}

template <int W>
void visible_bvh_rays(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible) {
    for (size_t i = 0; i < rays.size(); ++i) visible[i] = !traverse<W, true>(bvh, rays[i]).valid();
}

#define RTT_INSTANTIATE_BVH(W)                                                            \
    template Hit trace_bvh<W>(const Bvh<W>&, const Ray&);                                 \
    template bool occluded_bvh<W>(const Bvh<W>&, const Ray&);                             \
    template void trace_bvh_rays<W>(const Bvh<W>&, std::span<const Ray>, std::span<Hit>); \
    template void visible_bvh_rays<W>(const Bvh<W>&, std::span<const Ray>, std::span<uint8_t>);
RTT_INSTANTIATE_BVH(4)
#ifdef RTT_HAVE_SIMD8
RTT_INSTANTIATE_BVH(8)
#endif
#ifdef RTT_HAVE_SIMD16
RTT_INSTANTIATE_BVH(16)
#endif

std::unique_ptr<Tracer> make_bvh_tracer(const Scene& scene, const BvhBuildOptions& options) {
    return std::make_unique<BvhTracer<bvh_width>>(scene, options);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
