// RTT by shaft culling (the "rtt" tracer; "rtt-paper" keeps the corner traversal of
// corner_pass.h): the tile's relevant list and its 4 corners' answers from ONE front-to-back walk
// of the kd-tree entering exactly the nodes whose box may meet the region R of the rays answered
// from the list (ShaftRegion: the cone, the slab between the rays' starts and ends, their end
// plane). Why the list is complete and the corners exact, and how R narrows during the walk:
// docs/design.md, "`rtt`: one shaft walk instead of corners plus culling".
//
// Node test. ShaftRegion::meets' products and sums for 8 half-spaces at once (cone in lanes 0-3,
// slab and end plane in 4-7), done incrementally: a child's box differs from its parent's in one
// coordinate, so only the split axis's terms n_a (x_a - org_a) change, and of R's bounding box
// only the split axis's interval is compared again.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

#include "geom/triangle_simd.h"
#include "relevant_triangles/corner_pass.h"
#include "relevant_triangles/region.h"
#include "rtt/kdtree.h"
#include "simd/isa.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// What `narrow` decided after the corners' hits changed.
enum class Narrowed {
    same,     ///< Region unchanged.
    smaller,  ///< The region argument was replaced by one contained in the previous one.
    abandon,  ///< The tile will not be answered from a list: stop, nothing is answered.
};

/// R's 8 half-spaces (the cone in lanes 0-3, the slab and end plane in 4-7; without a slab every
/// lane of it passes, ShaftRegion::use_slab) and its bounding box, relative to the apex, in
/// registers: the walk's node and triangle tests (file comment, "Node test").
struct WalkRegion {
    static constexpr int W = simd_max_width >= 8 ? 8 : 4;  // lanes per vector
    static constexpr int C = 8 / W;                        // vectors per 8 half-spaces
    using vf = vfloat<W>;
    using vf4 = vfloat4;
    /// lo[a], hi[a]: n_a (box.lo_a - org_a), n_a (box.hi_a - org_a) per half-space.
    struct Terms {
        vf lo[3][C], hi[3][C];
    };

    vf n[3][C], limit[C];
    vf4 bounds_lo, bounds_hi;  // region.bounds, relative to the apex
    float rlo[3], rhi[3];      // the same, for the split tests
    float org[3];
    vf4 org4;

    explicit WalkRegion(const Vec3f& apex) : org{apex.x, apex.y, apex.z}, org4(BoxV::lanes(apex)) {}

    RTT_FORCEINLINE void load(const ShaftRegion& region) {
        bounds_lo = region.bounds.lo;
        bounds_hi = region.bounds.hi;
        for (int a = 0; a < 3; ++a) {
            rlo[a] = region.bounds.lo[a];
            rhi[a] = region.bounds.hi[a];
        }
        const vf4 cone_n[3] = {region.cone.nx, region.cone.ny, region.cone.nz};
        const vf4 slab_n[3] = {region.slab.nx, region.slab.ny, region.slab.nz};
        const vf4 slab_limit = region.use_slab ? region.slab.limit : vf4(neg_inf);
#ifdef RTT_HAVE_SIMD8
        static_assert(C == 1);
        for (int a = 0; a < 3; ++a) n[a][0] = combine(cone_n[a], slab_n[a]);
        limit[0] = combine(region.cone.limit, slab_limit);
#else
        static_assert(C == 2);
        for (int a = 0; a < 3; ++a) {
            n[a][0] = cone_n[a];
            n[a][1] = slab_n[a];
        }
        limit[0] = region.cone.limit;
        limit[1] = slab_limit;
#endif
    }

    RTT_FORCEINLINE void terms_of(const vf4& blo, const vf4& bhi, Terms& t) const {
        const vf4 dlo = blo - org4, dhi = bhi - org4;
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < C; ++c) {
                t.lo[a][c] = n[a][c] * vf(dlo[a]);
                t.hi[a][c] = n[a][c] * vf(dhi[a]);
            }
    }
    /// Whether all half-spaces may meet the box of terms t (ShaftRegion::meets' sums).
    RTT_FORCEINLINE bool meets(const Terms& t) const {
        bool in = true;
        for (int c = 0; c < C; ++c) {
            const vf best = (max(t.lo[0][c], t.hi[0][c]) + max(t.lo[1][c], t.hi[1][c])) +
                            max(t.lo[2][c], t.hi[2][c]);
            in &= movemask(best >= limit[c]) == all_lanes<W>;
        }
        return in;
    }
    /// Whether the box (relative to the apex) may meet region.bounds.
    RTT_FORCEINLINE bool in_bounds(const vf4& dlo, const vf4& dhi) const {
        return (movemask((dlo <= bounds_hi) & (dhi >= bounds_lo)) & 7) == 7;
    }
    RTT_FORCEINLINE bool box_meets(const vf4& blo, const vf4& bhi) const {
        Terms t;
        terms_of(blo, bhi, t);
        return in_bounds(blo - org4, bhi - org4) && meets(t);
    }
    /// The same for a triangle's bounding box, from scalars (no vector built in memory).
    RTT_FORCEINLINE bool triangle_meets(const TriangleVerts& tri) const {
        Terms t;
        for (int a = 0; a < 3; ++a) {
            const float lo = std::min({tri.v0[a], tri.v1[a], tri.v2[a]}) - org[a];
            const float hi = std::max({tri.v0[a], tri.v1[a], tri.v2[a]}) - org[a];
            if (lo > rhi[a] || hi < rlo[a]) return false;
            for (int c = 0; c < C; ++c) {
                t.lo[a][c] = n[a][c] * vf(lo);
                t.hi[a][c] = n[a][c] * vf(hi);
            }
        }
        return meets(t);
    }
    /// Which children of a split at `split` on axis A may meet the region, given the parent's
    /// terms t; v receives the split's terms n_A (split - org_A). (The sums' order differs from
    /// ShaftRegion::meets for some axes: PlaneSet's tolerance covers any order.)
    template <int A>
    RTT_FORCEINLINE void children_in(float split, const Terms& t, vf (&v)[C], bool& below_in,
                                     bool& above_in) const {
        constexpr int A1 = (A + 1) % 3, A2 = (A + 2) % 3;
        const float dv = split - org[A];
        // The parent meets region.bounds: a child may only leave them along A.
        below_in = dv >= rlo[A];
        above_in = dv <= rhi[A];
        for (int c = 0; c < C; ++c) {
            v[c] = n[A][c] * vf(dv);
            const vf others = max(t.lo[A1][c], t.hi[A1][c]) + max(t.lo[A2][c], t.hi[A2][c]);
            below_in &= movemask(others + max(t.lo[A][c], v[c]) >= limit[c]) == all_lanes<W>;
            above_in &= movemask(others + max(v[c], t.hi[A][c]) >= limit[c]) == all_lanes<W>;
        }
    }
};

/// The triangles of one leaf through the walk's tests (cull_shaft): each not seen before whose
/// box meets the region goes through test_corners and into the corners' answers or the list.
/// Returns the status the walk stops with, or nothing to go on; `shortened`: a corner's hit
/// came nearer.
template <Query Q>
RTT_FORCEINLINE std::optional<CornerStatus> walk_leaf(const KdNode& leaf, const uint32_t* leaf_ids,
                                                      std::span<const TriangleVerts> triangles,
                                                      const Shaft& shaft, const WalkRegion& r,
                                                      TriangleMailbox& mailbox, CornerResult& out,
                                                      PacketHit<4>& best, vfloat4& lane_tmax,
                                                      bool& shortened) {
    const uint32_t* ids = leaf_ids + leaf.first_triangle();
    // Each vertex load waits on its id's load and on the previous triangle's branches: start
    // them all before the first test.
    for (uint32_t k = 0, count = leaf.triangle_count(); k < count; ++k) {
        const char* p = reinterpret_cast<const char*>(&triangles[ids[k]]);
        __builtin_prefetch(p);
        __builtin_prefetch(p + sizeof(TriangleVerts) - 1);
    }
    for (uint32_t k = 0, count = leaf.triangle_count(); k < count; ++k) {
        const uint32_t id = ids[k];
        if (mailbox.seen(id)) continue;
        const TriangleVerts& tri = triangles[id];
        // A triangle whose box misses the region cannot be hit by an accepted ray, nor by a
        // corner before its current hit (the region only shrinks: it stays missed).
        if (!r.triangle_meets(tri)) continue;
        const CornerVerdict cv = test_corners<Q>(shaft, tri, lane_tmax);
        if (const std::optional<CornerStatus> stop =
                stop_status(take_verdict<Q>(cv, id, out, best, lane_tmax, shortened), out))
            return stop;
    }
    return std::nullopt;
}

/// Walks the kd-tree through the shaft (file comment). The corners of `shaft` are traced as
/// test_corners traces them: Query::closest_hit closest hits (out.hit), any_hit occluded segments
/// (out.occluded, to their ends unless one triangle blocks them all). `region` must hold every
/// point of every accepted ray up to its answer (any_hit: to its end); `narrow(best, region)`
/// (closest hits only) may replace it by a smaller one after the corners' hits changed.
/// Returns
///   traced:   corners answered; out.list holds every triangle an accepted ray can hit in the
///             last region;
///   blocked:  (any_hit) out.blocker blocks every accepted segment; corners answered;
///   overflow: (any_hit) all 4 corners blocked, by different triangles; corners answered, no list;
///   untraced: gave up (more than `budget` nodes, a full list, or `narrow` said so): nothing
///             is answered, not even the corners.
template <Query Q, typename Narrow>
CornerStatus cull_shaft(const KdTree& tree, std::span<const TriangleVerts> triangles,
                        const Shaft& shaft, ShaftRegion& region, int budget,
                        TriangleMailbox& mailbox, CornerResult& out, Narrow&& narrow) {
    constexpr bool AnyHit = Q == Query::any_hit;
    constexpr int C = WalkRegion::C;
    using vf = WalkRegion::vf;
    using vf4 = vfloat4;
    using Terms = WalkRegion::Terms;
    out.reset();
    mailbox.begin(triangles.size());
    if (tree.nodes.empty()) return CornerStatus::traced;

    WalkRegion r(shaft.org);
    r.load(region);
    struct Entry {
        vf4 lo, hi;
        uint32_t node;
        uint32_t generation;  // region generation the box was tested with
    };
    Entry stack[kd_max_depth + 1];
    int top = 0;
    // Written and read field by field: whole-entry copies went through store-forwarding stalls
    // (as in trace_packet.cpp).
    const auto push = [&](const vf4& lo, const vf4& hi, uint32_t node, uint32_t gen) {
        Entry& e = stack[top++];
        e.lo = lo;
        e.hi = hi;
        e.node = node;
        e.generation = gen;
    };
    uint32_t generation = 0;
    const vbool4 axis_lane[3] = {vbool4::from_bits(1), vbool4::from_bits(2), vbool4::from_bits(4)};
    const KdNode* nodes = tree.nodes.data();
    PacketHit<4> best;
    vf4 lane_tmax = vf4::load(shaft.tmax);

    const BoxV root(tree.bounds);
    if (!r.box_meets(root.lo, root.hi)) return CornerStatus::traced;  // nothing can be hit
    push(root.lo, root.hi, 0, generation);
    while (top > 0) {
        --top;
        vf4 blo = stack[top].lo, bhi = stack[top].hi;
        uint32_t index = stack[top].node;
        const bool retest = stack[top].generation != generation;
        Terms t;
        r.terms_of(blo, bhi, t);
        if (retest && !(r.in_bounds(blo - r.org4, bhi - r.org4) && r.meets(t))) continue;
        // One inner node along axis A (a template, so that the terms stay in registers):
        // false when neither child may meet the region.
        const auto step = [&]<int A>(const KdNode& node) {
            const float split = node.split;
            vf v[C];
            bool below_in, above_in;
            r.children_in<A>(split, t, v, below_in, above_in);
            // The apex's side first: along every ray from the apex, the points on that side of
            // the split come before those on the other.
            const bool below_first = r.org[A] <= split;
            const vf4 vsplit(split);
            const uint32_t below = index + 1, above = node.above_child();
            if (below_in && above_in) {
                if (below_first)
                    push(select(axis_lane[A], vsplit, blo), bhi, above, generation);
                else
                    push(blo, select(axis_lane[A], vsplit, bhi), below, generation);
            } else if (!below_in && !above_in) {
                return false;
            }
            if (below_in && (below_first || !above_in)) {
                bhi = select(axis_lane[A], vsplit, bhi);
                for (int c = 0; c < C; ++c) t.hi[A][c] = v[c];
                index = below;
            } else {
                blo = select(axis_lane[A], vsplit, blo);
                for (int c = 0; c < C; ++c) t.lo[A][c] = v[c];
                index = above;
            }
            return true;
        };
        for (;;) {
            if (--budget < 0) return give_up(out, Decline::budget);
            const KdNode& node = nodes[index];
            if (node.is_leaf()) break;
            // The below child is the next node; the above one lies far away and is what misses
            // (whether the walk takes it now or pops it later).
            __builtin_prefetch(nodes + node.above_child());
            const int axis = node.axis();
            const bool entered = axis == 0   ? step.template operator()<0>(node)
                                 : axis == 1 ? step.template operator()<1>(node)
                                             : step.template operator()<2>(node);
            if (!entered) {
                index = invalid_triangle;
                break;
            }
        }
        if (index == invalid_triangle) continue;
        bool shortened = false;
        if (const std::optional<CornerStatus> stop =
                walk_leaf<Q>(nodes[index], tree.leaf_triangles.data(), triangles, shaft, r, mailbox,
                             out, best, lane_tmax, shortened))
            return *stop;
        if constexpr (!AnyHit) {
            if (shortened) {
                const Narrowed n = narrow(best, region);
                if (n == Narrowed::abandon) return give_up(out, Decline::no_end);
                if (n == Narrowed::smaller) {
                    r.load(region);
                    ++generation;
                }
            }
        }
    }
    if constexpr (!AnyHit)
        for (int i = 0; i < 4; ++i) out.hit[i] = Hit{best.t[i], uint32_t(best.tri[i])};
    return CornerStatus::traced;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
