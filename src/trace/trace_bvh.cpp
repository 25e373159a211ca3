// The "bvh" tracer: single rays through a W-wide BVH (bvh/bvh.h), a node's children tested in
// one W-lane vector, nearest first. Exact: a node is skipped only when the ray's interval in its
// box, widened by the kd-tree's split margin, starts after the closest hit so far (docs/design.md,
// "The BVH for arbitrary rays"); triangles are tested with the one watertight test and ties go to
// the smaller index, so hits equal trace_ray's bit for bit.
#include "trace/trace_bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/kernels.h"
#include "trace/trace_ray.h"
#include "trace/traced_tile.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

/// The scalars BoxRay and WatertightRay take from each of K rays, made in K lanes at once
/// (BoxLanes, WatertightPacket: each lane bit for bit WatertightRay's). Arrays of rays make
/// them a vector at a time, where ray by ray the setup was 8 % of the kernel's time
/// (docs/benchmarks.md, "Arbitrary rays").
template <int K>
struct RaySetups {
    using vf = vfloat<K>;
    alignas(64) float inv[3][K], org_inv[3][K], t_margin[K], far_t_margin[K], sx[K], sy[K], sz[K];
    alignas(64) int32_t kx[K], ky[K], kz[K];
    alignas(64) int32_t negative[K], flat[K], free[K];  ///< BoxLanes' axis bits.
    uint32_t subtract;                                  ///< BoxLanes' subtract lanes.

    /// rays[0, n), 1 <= n <= K; the lanes beyond n repeat ray 0.
    RaySetups(const Ray* rays, int n, const Bbox3f& bounds) {
        static_assert(sizeof(Ray) == 8 * sizeof(float) && std::is_standard_layout_v<Ray>);
        vf f[8];
        if (n == K) {
            load_records8(reinterpret_cast<const float*>(rays), f);
        } else {
            alignas(64) Ray padded[K];
            for (int i = 0; i < K; ++i) padded[i] = rays[i < n ? i : 0];
            load_records8(reinterpret_cast<const float*>(padded), f);
        }
        const Vec3v<K> o{f[0], f[1], f[2]}, d{f[3], f[4], f[5]};
        const BoxLanes<K> box(o, d, bounds);
        for (int a = 0; a < 3; ++a) {
            store(inv[a], box.inv[a]);
            store(org_inv[a], box.org_inv[a]);
        }
        store(t_margin, box.t_margin);
        store(negative, box.negative);
        store(flat, box.flat);
        store(free, box.free);
        subtract = movemask(box.subtract);
        store(far_t_margin, box.far_t_margin);
        const WatertightPacket<K> w(o, d, f[6], f[7], vbool<K>(true));
        store(sx, w.sx);
        store(sy, w.sy);
        store(sz, w.sz);
        store(kx, w.kx);
        store(ky, w.ky);
        store(kz, w.kz);
    }

    /// WatertightRay(rays[l]), bit for bit.
    WatertightRay watertight(int l, const Ray& ray) const {
        return {ray.org, kx[l], ky[l], kz[l], sx[l], sy[l], sz[l], ray.tmin, ray.tmax};
    }
};

/// What the node test needs of a ray, broadcast to W lanes.
template <int W>
struct BoxRay {
    using vf = vfloat<W>;
    vf inv[3], org_inv[3];
    vf org[3];                  ///< Only for rays that are not plain (below).
    vf t_margin, far_t_margin;  ///< BoxLanes'.
    /// Byte offsets in a node of the faces a ray enters and leaves by on each axis (hi when
    /// dir < 0): fixed per ray, so a node's test picks no faces.
    uint32_t enter[3], leave[3];
    // Set only when the ray is not plain, for the test's slow path (BoxLanes' axes):
    bool flat[3];  ///< dir[a] == 0: inside the closed slab when the ray lies in a face's plane.
    bool free[3];  ///< |1 / dir[a]| beyond 2^40: the axis never culls.
    /// No axis flat or free, and not BoxLanes' `subtract`: the slow path's (face - org) * inv
    /// is the form a subtract ray's margin is sized for.
    bool plain;
    bool nonneg_tmin;  ///< tmin >= 0 (widen_interval).

    /// Lane `l` of a batch made by RaySetups.
    template <int K>
    BoxRay(const RaySetups<K>& s, int l, const Ray& ray) {
        for (int a = 0; a < 3; ++a) {
            inv[a] = vf(s.inv[a][l]);
            org_inv[a] = vf(s.org_inv[a][l]);
        }
        t_margin = vf(s.t_margin[l]);
        far_t_margin = vf(s.far_t_margin[l]);
        const uint32_t flat_bits = uint32_t(s.flat[l]), free_bits = uint32_t(s.free[l]);
        plain = (flat_bits | free_bits) == 0 && !((s.subtract >> l) & 1u);
        nonneg_tmin = ray.tmin >= 0.f;
        box_faces<W>(uint32_t(s.negative[l]), enter, leave);
        if (!plain) [[unlikely]] {
            for (int a = 0; a < 3; ++a) {
                org[a] = vf(ray.org[a]);
                flat[a] = (flat_bits >> a) & 1u;
                free[a] = (free_bits >> a) & 1u;
            }
        }
    }

    /// Lanes of the node's children whose box the ray may meet in [tmin, tmax]; their entry
    /// distances (widened) in `near`.
    RTT_FORCEINLINE uint32_t test(const BvhNode<W>& n, float tmin, float tmax, vf& near) const {
        if (plain) [[likely]] {
            // dir[a] != 0: the entry face gives the smaller distance. A padding slot's box (lo
            // +inf, hi -inf) gives tn = +inf and tf = -inf, so it is never entered.
            const char* base = reinterpret_cast<const char*>(&n);
            const auto face = [&](uint32_t offset, int a) {
                return mul_sub(vf::load(reinterpret_cast<const float*>(base + offset)), inv[a],
                               org_inv[a]);
            };
            const vf tn = max(max(face(enter[0], 0), face(enter[1], 1)), face(enter[2], 2));
            const vf tf = min(min(face(leave[0], 0), face(leave[1], 1)), face(leave[2], 2));
            return meets(tn, tf, tmin, tmax, near);
        }
        vf tn(neg_inf), tf(pos_inf);
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
        // Here a padding slot's box spans every slab it is measured on.
        const uint32_t used = (1u << n.count) - 1u;
        return meets(tn, tf, tmin, tmax, near) & used;
    }

private:
    /// Lanes whose interval [tn, tf], widened by twice the margin of trace_ray's split
    /// distances ((1 -+ 2 kd_margin) scales |t| down or up whatever its sign; infinities stay
    /// infinite), meets [tmin, tmax]; the widened entry distances in `near`.
    RTT_FORCEINLINE uint32_t meets(vf tn, vf tf, float tmin, float tmax, vf& near) const {
        vf far;
        if (nonneg_tmin)
            widen_interval<true>(tn, tf, 2.f * kd_margin, t_margin, far_t_margin, near, far);
        else
            widen_interval(tn, tf, 2.f * kd_margin, t_margin, far_t_margin, near, far);
        return movemask(max(near, vf(tmin)) <= min(far, vf(tmax)));
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

/// The closest (or any) hit of `ray`, lane `l` of `setups`. The box test's constants are made
/// in this frame, so that they stay in registers (a BoxRay passed in was 3-6 % slower), and
/// the function is inlined in both its callers (2 % on closest hits).
template <int W, bool AnyHit, int K>
RTT_FORCEINLINE Hit traverse(const Bvh<W>& bvh, const Ray& ray, const RaySetups<K>& setups, int l) {
    Hit best;
    WatertightRay wr = setups.watertight(l, ray);
    const WatertightRay4 wr4(wr);
    const BoxRay<W> br(setups, l, ray);
    // Each node pushes at most W - 1 children: W - 1 per level, bvh_max_depth levels. Any-hit
    // rays need no distances.
    std::conditional_t<AnyHit, uint32_t, StackEntry> stack[(W - 1) * bvh_max_depth + W];
    int top = 0;
    uint32_t cur = 0;  // the root
    for (;;) {
        if (cur & bvh_leaf_bit) {
            const uint32_t first = (cur & ~bvh_leaf_bit) >> 3, count = cur & 7u;
            const bool ended = for_each_leaf_hit(
                bvh, first, count, wr4, ray.tmin, wr.tmax,
                [&](const BvhTriangles4& q, int l, float t) {
                    if (AnyHit || closer(t, q.id[l], best)) {
                        best = {t, q.id[l]};
                        wr.tmax = t;  // inclusive: equal t still reaches the tie-break
                    }
                    return AnyHit;
                });
            if (ended) return best;
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
                const int j = std::countr_zero(mask);
                mask &= mask - 1;
                // Which of the two is nearer, by selects: a branch here mispredicted about once
                // a ray (callgrind).
                const bool j_nearer = d[j] < d[i];
                const int near_c = j_nearer ? j : i, far_c = j_nearer ? i : j;
                stack[top++] = {node.child[far_c], d[far_c]};
                if (!mask) {  // two: the far one waits
                    cur = node.child[near_c];
                    continue;
                }
                // Three or more: sorted far to near on the stack, the nearest popped as the next.
                const int base = top - 1;
                stack[top++] = {node.child[near_c], d[near_c]};
                for (; mask; mask &= mask - 1) {
                    const int c = std::countr_zero(mask);
                    const StackEntry e{node.child[c], d[c]};
                    int k = top++;
                    for (; k > base && stack[k - 1].near < e.near; --k) stack[k] = stack[k - 1];
                    stack[k] = e;
                }
                cur = stack[--top].child;
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

template <int W, bool AnyHit>
Hit traverse(const Bvh<W>& bvh, const Ray& ray) {
    if (bvh.nodes.empty()) return {};
    return traverse<W, AnyHit>(bvh, ray, RaySetups<simd_max_width>(&ray, 1, bvh.padded_bounds), 0);
}

/// answer(i, hit) for every rays[i], the setups made a vector of rays at a time.
template <int W, bool AnyHit, typename Answer>
void traverse_rays(const Bvh<W>& bvh, std::span<const Ray> rays, const Answer& answer) {
    constexpr int K = simd_max_width;
    if (bvh.nodes.empty()) {
        for (size_t i = 0; i < rays.size(); ++i) answer(i, Hit{});
        return;
    }
    for (size_t first = 0; first < rays.size(); first += K) {
        const int n = int(std::min<size_t>(K, rays.size() - first));
        const RaySetups<K> setups(rays.data() + first, n, bvh.padded_bounds);
        for (int l = 0; l < n; ++l)
            answer(first + size_t(l), traverse<W, AnyHit>(bvh, rays[first + size_t(l)], setups, l));
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
    traverse_rays<W, false>(bvh, rays, [&](size_t i, const Hit& hit) { hits[i] = hit; });
}

template <int W>
void visible_bvh_rays(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible) {
    traverse_rays<W, true>(bvh, rays, [&](size_t i, const Hit& hit) { visible[i] = !hit.valid(); });
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
