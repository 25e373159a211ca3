// Coherent rays through the BVH in packets of the ISA's widest vector: each node's boxes are
// fetched once for all lanes and each child is tested against every lane at once, so rays that
// travel together (a tile's rows, reflections off one curved mirror) share the traversal.
// Exact: a lane enters a child when its own widened slab interval meets its [tmin, closest hit]
// (trace_bvh.cpp's test, lane by lane: docs/design.md, "The BVH for arbitrary rays"), and its
// triangles are tested with the packet form of the one watertight test, so every lane's hit is
// trace_bvh's bit for bit. Lanes whose direction has a zero or tiny component take the
// single-ray kernel, which handles those axes.
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstddef>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/trace_bvh.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

constexpr int K = simd_max_width;
using vf = vfloat<K>;
using vb = vbool<K>;

/// Up to K rays as vectors, and the per-lane constants of the node test.
struct PacketRays {
    Vec3v<K> org, dir;
    vf tmin, tmax;
    vf inv[3], org_inv[3];
    vf t_margin;  ///< As trace_bvh.cpp's BoxRay::t_margin, per lane.
    /// Every traced lane's direction has one sign per axis: the faces each axis enters and
    /// leaves by are then the packet's, at these byte offsets from a child's lo.x.
    bool same_signs = false;
    uint32_t enter[3] = {}, leave[3] = {};
    vb active;            ///< Lanes traced here.
    uint32_t single = 0;  ///< Lanes left to the single-ray kernel.

    PacketRays(std::span<const Ray> rays, const Bbox3f& bounds) {
        alignas(64) float o[3][K], d[3][K], t0[K], t1[K];
        for (int i = 0; i < K; ++i) {
            // Unused lanes copy ray 0: finite values keep the arithmetic free of denormals.
            const Ray& r = rays[size_t(i) < rays.size() ? size_t(i) : 0];
            for (int a = 0; a < 3; ++a) {
                o[a][i] = r.org[a];
                d[a][i] = r.dir[a];
            }
            t0[i] = r.tmin;
            t1[i] = r.tmax;
        }
        org = {vf::load(o[0]), vf::load(o[1]), vf::load(o[2])};
        dir = {vf::load(d[0]), vf::load(d[1]), vf::load(d[2])};
        tmin = vf::load(t0);
        tmax = vf::load(t1);
        const vf* dv[3] = {&dir.x, &dir.y, &dir.z};
        const vf* ov[3] = {&org.x, &org.y, &org.z};
        vb odd(false);
        vf dist(0.f), dmax(0.f), org_t(0.f);
        for (int a = 0; a < 3; ++a) {
            inv[a] = vf(1.f) / *dv[a];
            org_inv[a] = *ov[a] * inv[a];
            odd |= (*dv[a] == vf(0.f)) | !(abs(inv[a]) <= vf(0x1p40f));
            dist = max(dist, max(abs(vf(bounds.lo[a]) - *ov[a]), abs(vf(bounds.hi[a]) - *ov[a])));
            dmax = max(dmax, abs(*dv[a]));
            org_t = max(org_t, abs(org_inv[a]));
        }
        const uint32_t used = rays.size() >= size_t(K) ? ~0u >> (32 - K) : (1u << rays.size()) - 1u;
        single = movemask(odd) & used;
        active = vb::from_bits(used & ~single);
        same_signs = true;
        using Node = BvhNode<bvh_width>;
        for (int a = 0; a < 3; ++a) {
            const uint32_t traced = movemask(active), neg = signbits(*dv[a]) & traced;
            same_signs &= neg == 0 || neg == traced;
            const uint32_t lo = uint32_t(sizeof(float) * bvh_width * size_t(a));
            const uint32_t hi = lo + uint32_t(offsetof(Node, hi) - offsetof(Node, lo));
            enter[a] = neg ? hi : lo;
            leave[a] = neg ? lo : hi;
        }
        const vf scale = min(dist / dmax, vf(FLT_MAX)) + org_t * vf(0x1p-6f);
        t_margin = vf(2.f * kd_margin) * min(scale, vf(FLT_MAX));
    }

    /// Lanes of `lanes` whose widened interval in child `c`'s box meets [tmin, tmax]; their
    /// widened entry distances in `near`.
    template <bool SameSigns, int W>
    RTT_FORCEINLINE vb test(const BvhNode<W>& n, int c, vb lanes, vf tmax_now, vf& near) const {
        static_assert(W == bvh_width);
        vf tn = tmin, tf = tmax_now;
        vf enter_t, leave_t;
        if constexpr (SameSigns) {
            const char* base = reinterpret_cast<const char*>(&n.lo[0][c]);
            const auto face = [&](uint32_t offset, int a) {
                const float f = *reinterpret_cast<const float*>(base + offset);
                return mul_sub(vf(f), inv[a], org_inv[a]);
            };
            enter_t = max(max(face(enter[0], 0), face(enter[1], 1)), face(enter[2], 2));
            leave_t = min(min(face(leave[0], 0), face(leave[1], 1)), face(leave[2], 2));
        } else {
            vf lo_t[3], hi_t[3];
            for (int a = 0; a < 3; ++a) {
                lo_t[a] = mul_sub(vf(n.lo[a][c]), inv[a], org_inv[a]);
                hi_t[a] = mul_sub(vf(n.hi[a][c]), inv[a], org_inv[a]);
            }
            enter_t = max(max(min(lo_t[0], hi_t[0]), min(lo_t[1], hi_t[1])), min(lo_t[2], hi_t[2]));
            leave_t = min(min(max(lo_t[0], hi_t[0]), max(lo_t[1], hi_t[1])), max(lo_t[2], hi_t[2]));
        }
        const vf enter = enter_t, leave = leave_t;
        const vf shrink(1.f - 2.f * kd_margin), grow(1.f + 2.f * kd_margin);
        near = min(mul_sub(enter, shrink, t_margin), mul_sub(enter, grow, t_margin));
        const vf far = max(mul_add(leave, grow, t_margin), mul_add(leave, shrink, t_margin));
        return lanes & (max(near, tn) <= min(far, tf));
    }
};

template <int W>
struct PacketEntry {
    vf near;  ///< Widened entry distance per lane; +inf where the lane does not enter.
    uint32_t child;
};

/// Closest hits (AnyHit: whether some triangle blocks) of the packet's active lanes.
template <int W, bool AnyHit, bool SameSigns>
void traverse(const Bvh<W>& bvh, const PacketRays& rays, PacketHit<K>& best, vb& blocked) {
    WatertightPacket<K> wp(rays.org, rays.dir, rays.tmin, rays.tmax, rays.active);
    vb alive = rays.active;  // AnyHit: lanes not blocked yet
    PacketEntry<W> stack[(W - 1) * bvh_max_depth + W];
    int top = 0;
    uint32_t cur = 0;
    vf cur_near = select(rays.active, rays.tmin, vf(pos_inf));
    const vf inf(pos_inf);
    for (;;) {
        const vb active = alive & (cur_near <= wp.tmax);
        if (cur & bvh_leaf_bit) {
            const uint32_t first = (cur & ~bvh_leaf_bit) >> 3, count = cur & 7u;
            vb lanes = active;
            for (uint32_t k = first; k < first + count && any(lanes); ++k) {
                const BvhTriangles4& q = bvh.blocks[k];
                for (int l = 0; l < 4; ++l) {
                    const uint32_t id = q.id[l];
                    if (id == invalid_triangle) continue;
                    const TriangleVerts tri{{q.v0[0][l], q.v0[1][l], q.v0[2][l]},
                                            {q.v1[0][l], q.v1[1][l], q.v1[2][l]},
                                            {q.v2[0][l], q.v2[1][l], q.v2[2][l]}};
                    vf t(0.f);
                    const vb hit = intersect_watertight<K>(wp, lanes, tri, t);
                    if constexpr (AnyHit) {
                        blocked |= hit;
                        lanes = andnot(lanes, hit);
                        alive = andnot(alive, hit);
                    } else {
                        // inclusive tmax: a later equal-t hit still reaches the index tie-break
                        wp.tmax = select(best.update(hit, t, id), t, wp.tmax);
                    }
                }
            }
        } else if (any(active)) {
            const BvhNode<W>& node = bvh.nodes[cur];
            bool have = false;
            uint32_t next = 0;
            vf next_near = inf;
            for (int c = 0; c < int(node.count); ++c) {
                vf near;
                const vb enter = rays.template test<SameSigns>(node, c, active, wp.tmax, near);
                if (none(enter)) continue;
                const vf dist = select(enter, near, inf);
                if (!have) {
                    have = true;
                    next = node.child[c];
                    next_near = dist;
                } else if (any(dist < next_near)) {  // nearer for some lane: that one first
                    stack[top++] = {next_near, next};
                    next = node.child[c];
                    next_near = dist;
                } else {
                    stack[top++] = {dist, node.child[c]};
                }
            }
            if (have) {
                cur = next;
                cur_near = next_near;
                continue;
            }
        }
        // Next: a waiting subtree some live lane may still find a closer hit in.
        for (;;) {
            if (top == 0) return;
            const PacketEntry<W>& e = stack[--top];
            if (any(alive & (e.near <= wp.tmax))) {
                cur = e.child;
                cur_near = e.near;
                break;
            }
        }
    }
}

/// Runs `packet(rays, first)` on each packet of K consecutive rays.
/// traverse() with the node test the packet's direction signs allow.
template <int W, bool AnyHit>
void traverse_packet(const Bvh<W>& bvh, const PacketRays& p, PacketHit<K>& best, vb& blocked) {
    if (!any(p.active)) return;
    if (p.same_signs)
        traverse<W, AnyHit, true>(bvh, p, best, blocked);
    else
        traverse<W, AnyHit, false>(bvh, p, best, blocked);
}

template <typename Packet>
void for_each_packet(std::span<const Ray> rays, Packet&& packet) {
    for (size_t first = 0; first < rays.size(); first += K)
        packet(rays.subspan(first, std::min(size_t(K), rays.size() - first)), first);
}

}  // namespace

template <int W>
void trace_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
    if (bvh.nodes.empty()) return std::fill(hits.begin(), hits.end(), Hit{});
    for_each_packet(rays, [&](std::span<const Ray> part, size_t first) {
        const PacketRays p(part, bvh.padded_bounds);
        PacketHit<K> best;
        vb unused(false);
        traverse_packet<W, false>(bvh, p, best, unused);
        for (size_t i = 0; i < part.size(); ++i)
            hits[first + i] = (p.single >> i) & 1u ? trace_bvh(bvh, part[i])
                              : best.tri[int(i)] == int32_t(invalid_triangle)
                                  ? Hit{}
                                  : Hit{best.t[int(i)], uint32_t(best.tri[int(i)])};
    });
}

template <int W>
void visible_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible) {
    if (bvh.nodes.empty()) return std::fill(visible.begin(), visible.end(), uint8_t(1));
    for_each_packet(rays, [&](std::span<const Ray> part, size_t first) {
        const PacketRays p(part, bvh.padded_bounds);
        PacketHit<K> unused;
        vb blocked(false);
        traverse_packet<W, true>(bvh, p, unused, blocked);
        const uint32_t bits = movemask(blocked);
        for (size_t i = 0; i < part.size(); ++i)
            visible[first + i] =
                (p.single >> i) & 1u ? !occluded_bvh(bvh, part[i]) : !((bits >> i) & 1u);
    });
}

template <int W>
uint64_t visible_segment_packets(const Bvh<W>& bvh, const SegmentTile& tile,
                                 std::span<uint8_t> visible) {
    // The active segments as shadow rays, K at a time.
    Ray rays[K];
    size_t index[K];
    size_t n = 0;
    uint64_t traced = 0;
    uint8_t out[K];
    const auto flush = [&] {
        visible_bvh_packets(bvh, std::span<const Ray>(rays, n), std::span<uint8_t>(out, n));
        for (size_t j = 0; j < n; ++j) visible[index[j]] = out[j];
        traced += n;
        n = 0;
    };
    for (size_t i = 0; i < tile.points.size(); ++i) {
        visible[i] = 0;
        if (!tile.active[i]) continue;
        rays[n] = shadow_ray(tile.light, tile.points[i]);
        index[n++] = i;
        if (n == size_t(K)) flush();
    }
    if (n > 0) flush();
    return traced;
}

template void trace_bvh_packets<bvh_width>(const Bvh<bvh_width>&, std::span<const Ray>,
                                           std::span<Hit>);
template void visible_bvh_packets<bvh_width>(const Bvh<bvh_width>&, std::span<const Ray>,
                                             std::span<uint8_t>);
template uint64_t visible_segment_packets<bvh_width>(const Bvh<bvh_width>&, const SegmentTile&,
                                                     std::span<uint8_t>);

}  // namespace RTT_ISA_NS
}  // namespace rtt
