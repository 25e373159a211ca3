#include "relevant_triangles/corner_pass.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "geom/triangle_simd.h"
#include "relevant_triangles/tolerances.h"
#include "trace/root_clip.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

using vf = vfloat4;
using vb = vbool4;

/// Deferred subtree of the lanes' traversal: trace_ray's per-lane intervals, the node's box and
/// the lanes that visit it.
struct alignas(16) CornerStackEntry {
    vf t0, t1;
    BoxV box;
    uint32_t node;
    uint32_t lanes;
};

/// How far (coordinate units) the apex must lie beyond a split for the child on its side to be
/// out of reach of every accepted ray: far more than the float test's fuzz (see PlaneSet).
float behind_margin_of(const Bbox3f& bounds, const Vec3f& org) {
    return tolerance::box_test * 3.f *
           std::max({std::fabs(bounds.lo.x - org.x), std::fabs(bounds.hi.x - org.x),
                     std::fabs(bounds.lo.y - org.y), std::fabs(bounds.hi.y - org.y),
                     std::fabs(bounds.lo.z - org.z), std::fabs(bounds.hi.z - org.z)});
}

/// Keeps a node no lane enters for shaft culling. Shadows test it against the region at once
/// (their region is final); closest hits keep it untested: their region's end is known only at
/// the end, and tiles whose corners part ways never need the test. Lean tiles too:
/// collect_deferred tests every kept box against the final region R, which lies in the shaft's
/// cone, so a box test against the cone here would only repeat (one box at a time) a test that
/// the batch does 16 boxes at a time, and for every tile that gives up later would be wasted.
/// The set of nodes entered is the same; only a tile with more than rtt_max_deferred skipped
/// nodes gives up (`listing` false: traced by packets, still exact).
template <bool AnyHit>
RTT_FORCEINLINE void defer_node(uint32_t node, const BoxV& box, const ShaftRegion* region,
                                CornerResult& out, bool& listing) {
    if (AnyHit && !region->meets(box)) return;
    DeferredNodes& d = out.deferred;
    if (d.count == rtt_max_deferred) {
        listing = false;
        out.declined = Decline::budget;
        return;
    }
    d.add(node, box);
}

/// The corners' tests against one leaf's triangles not met before; the status the pass stops
/// with, or nothing to go on. A full list only stops the listing (`listing` false).
template <Query Q>
RTT_FORCEINLINE std::optional<CornerStatus> corners_leaf(
    const KdNode& leaf, const uint32_t* leaf_ids, std::span<const TriangleVerts> triangles,
    Shaft& shaft, TriangleMailbox& mailbox, CornerResult& out, PacketHit<4>& best, vf& lane_tmax,
    bool& closer, bool& listing) {
    const uint32_t* ids = leaf_ids + leaf.first_triangle();
    for (uint32_t k = 0, count = leaf.triangle_count(); k < count; ++k) {
        const uint32_t id = ids[k];
        // A triangle met again in another leaf: its corner tests cannot change (the lanes'
        // tmax only shrank) and its relevance was decided.
        if (mailbox.seen(id)) continue;
        if (!complete_shaft(shaft)) return give_up(out, Decline::no_shaft);
        // Every lane tests every triangle met: a superset of the leaves trace_ray visits per
        // lane, which returns the same answers (trace_ray.h).
        const CornerVerdict v = test_corners<Q>(shaft, triangles[id], lane_tmax);
        if (const std::optional<CornerStatus> stop =
                stop_status(take_verdict<Q>(v, id, out, best, lane_tmax, closer), out, &listing))
            return stop;
    }
    return std::nullopt;
}

}  // namespace

template <Query Q, CornerPass P>
CornerStatus trace_corners(const KdTree& tree, std::span<const TriangleVerts> triangles,
                           Shaft& shaft, const ShaftRegion* region, const Ray (&corners)[4],
                           TriangleMailbox& mailbox, CornerResult& out) {
    constexpr bool AnyHit = Q == Query::any_hit, Lean = P == CornerPass::lean;
    out.reset();
    mailbox.begin(triangles.size());
    if (tree.nodes.empty()) return CornerStatus::traced;
    const Vec3f org = shaft.org;
    const CornerLanes corner_lanes(corners);
    const vf dir[3] = {corner_lanes.dir.x, corner_lanes.dir.y, corner_lanes.dir.z};
    const vf ray_tmin = corner_lanes.tmin, ray_tmax = corner_lanes.tmax;
    const vf inv[3] = {rcp(dir[0]), rcp(dir[1]), rcp(dir[2])};  // 1.f / d, as trace_ray
    bool above_first[3];
    vb zero_dir[3];
    for (int a = 0; a < 3; ++a) {
        const uint32_t bits = signbits(dir[a]);
        if (bits != 0 && bits != 0xF)  // lanes order children differently
            return give_up(out, Decline::corners_parted);
        above_first[a] = bits != 0;
        zero_dir[a] = dir[a] == vf(0.f);
    }
    const float behind_margin = behind_margin_of(tree.bounds, org);
    // trace_ray's clip to the padded root box and its scene_t_scale, per lane.
    const vf org4[3] = {vf(org.x), vf(org.y), vf(org.z)};
    vf t0, t1, tscale;
    clip_to_root<4>(padded_bounds(tree.bounds), org4, corner_lanes.dir, inv, ray_tmin, ray_tmax, t0,
                    t1, tscale);
    const uint32_t entering = movemask(t0 <= t1);
    if (entering != 0xF) {
        if constexpr (Lean) return give_up(out, Decline::corners_parted);
        out.coherent = false;
    }

    bool listing = true;  // list and deferred nodes within capacity
    bool closer = false;  // take_verdict's flag: this pass does not narrow its region
    const auto defer = [&](uint32_t node, const BoxV& box) {
        defer_node<AnyHit>(node, box, region, out, listing);
    };
    PacketHit<4> best;
    vf lane_tmax = ray_tmax;
    const vf margin(kd_margin);
    CornerStackEntry stack[kd_max_depth + 1];
    int top = 0;
    // Entries are written and read field by field: copying a whole one made GCC move it with
    // wide loads that stall on store forwarding (as in trace_packet.cpp).
    const auto push = [&](uint32_t node, vf ta, vf tb, const BoxV& box, uint32_t lanes) {
        CornerStackEntry& e = stack[top++];
        e.t0 = ta;
        e.t1 = tb;
        e.box.lo = box.lo;
        e.box.hi = box.hi;
        e.node = node;
        e.lanes = lanes;
    };
    const BoxV root(tree.bounds);
    if (entering) {
        push(0, t0, t1, root, entering);
    } else {
        defer(0, root);
    }
    const vb axis_lane[3] = {vb::from_bits(1), vb::from_bits(2), vb::from_bits(4)};
    const KdNode* nodes = tree.nodes.data();
    const uint32_t* leaf_ids = tree.leaf_triangles.data();

    while (top > 0) {
        --top;
        vf ta = stack[top].t0, tb = stack[top].t1;
        BoxV box;
        box.lo = stack[top].box.lo;
        box.hi = stack[top].box.hi;
        uint32_t index = stack[top].node, lanes = stack[top].lanes;
        if constexpr (!AnyHit) {
            // trace_ray: a popped node whose interval starts after best.t is skipped. A node all
            // lanes skip may still hold what an inner ray hits before its end: deferred.
            const uint32_t done = movemask(ta > best.t) & lanes;
            if (done) {
                if (done != lanes) {
                    if constexpr (Lean) return give_up(out, Decline::corners_parted);
                    out.coherent = false;
                }
                lanes &= ~done;
                if (!lanes) {
                    defer(index, box);
                    continue;
                }
            }
        }
        while (!nodes[index].is_leaf()) {
            const KdNode& n = nodes[index];
            const int axis = n.axis();
            const uint32_t below = index + 1, above = n.above_child();
            const vf ds = vf(n.split - org[axis]) * inv[axis];
            // trace_ray's margin: exact (0) for a zero direction component (d = +-inf); a NaN d
            // leaves both children [ta, tb] through min / max, as trace_ray's NaN branch.
            const vf m = select(zero_dir[axis], vf(0.f), (abs(ds) + tscale) * margin);
            const vf first_hi = min(ds + m, tb);   // std::min(tb, d + m)
            const vf second_lo = max(ds - m, ta);  // std::max(ta, d - m)
            const uint32_t go_first = movemask(ta <= first_hi) & lanes;
            const uint32_t go_second = movemask(second_lo <= tb) & lanes;
            if ((go_first && go_first != lanes) || (go_second && go_second != lanes)) {
                if constexpr (Lean) return give_up(out, Decline::corners_parted);
                out.coherent = false;
            }
            // Children boxes: the box cut at the split (each closed).
            BoxV below_box = box, above_box = box;
            below_box.hi = select(axis_lane[axis], vf(n.split), box.hi);
            above_box.lo = select(axis_lane[axis], vf(n.split), box.lo);
            const BoxV& first_box = above_first[axis] ? above_box : below_box;
            const BoxV& second_box = above_first[axis] ? below_box : above_box;
            const uint32_t first = above_first[axis] ? above : below;
            const uint32_t second = above_first[axis] ? below : above;
            // The first child lies on the side the rays come from. With the apex clearly on the
            // other side (farther than the float test's fuzz, see PlaneSet), every ray of the
            // cone moves away from it for t > 0 (the direction signs are common): no accepted
            // ray reaches it, nor passes close enough to be "hit" by rounding.
            const float beyond = above_first[axis] ? n.split - org[axis] : org[axis] - n.split;
            const bool behind = beyond > behind_margin;
            if (!go_first && !behind) defer(first, first_box);
            if (!go_second) defer(second, second_box);
            if (go_first && go_second) push(second, second_lo, tb, second_box, go_second);
            if (go_first) {
                index = first;
                tb = first_hi;
                box = first_box;
                lanes = go_first;
            } else if (go_second) {
                index = second;
                ta = second_lo;
                box = second_box;
                lanes = go_second;
            } else {
                index = invalid_triangle;  // every interval empty (cannot happen for ta <= tb)
                break;
            }
        }
        if (index == invalid_triangle) continue;
        if (const std::optional<CornerStatus> stop =
                corners_leaf<Q>(nodes[index], leaf_ids, triangles, shaft, mailbox, out, best,
                                lane_tmax, closer, listing))
            return *stop;
    }
    if constexpr (!AnyHit)
        for (int i = 0; i < 4; ++i) out.hit[i] = Hit{best.t[i], uint32_t(best.tri[i])};
    return listing ? CornerStatus::traced : CornerStatus::overflow;
}

template CornerStatus trace_corners<Query::closest_hit, CornerPass::lean>(
    const KdTree&, std::span<const TriangleVerts>, Shaft&, const ShaftRegion*, const Ray (&)[4],
    TriangleMailbox&, CornerResult&);
template CornerStatus trace_corners<Query::closest_hit>(const KdTree&,
                                                        std::span<const TriangleVerts>, Shaft&,
                                                        const ShaftRegion*, const Ray (&)[4],
                                                        TriangleMailbox&, CornerResult&);
template CornerStatus trace_corners<Query::any_hit>(const KdTree&, std::span<const TriangleVerts>,
                                                    Shaft&, const ShaftRegion*, const Ray (&)[4],
                                                    TriangleMailbox&, CornerResult&);

}  // namespace RTT_ISA_NS
}  // namespace rtt
