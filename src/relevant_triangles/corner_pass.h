// RTT's corner traversal (paper section 3; docs/design.md, "Coverage"), used by "rtt-paper" and by
// "rtt" at K = 1 and 2 (Lean; larger tiles walk the shaft instead, walk.h, sharing the types
// below): the 4 corner rays of a shaft go through the kd-tree as one SSE packet, with trace_ray's
// semantics per lane (they are answers too), and every triangle of every leaf they reach is put
// through the shaft's five conservative tests (conservative_tests.h) to build the tile's relevant
// list.
//
// Why the list holds every triangle an inner ray can hit. The paper argues by coherence: if the
// 4 corners visit exactly the same nodes with the same decisions, the inner rays of the convex
// shaft visit those nodes too. That argument is fragile in floating point (decisions carry
// margins, a margin-only visit of one corner is not a visit of its neighbours, and the corner
// rays that bound the *checked* inner rays are not exactly the tile's corners), and it gives
// up on every tile a split plane cuts. rtt makes the coverage argument exact instead, by shaft
// culling (Haines and Wallace, cited by the paper) of what the corners leave out:
//   * The accepted rays of a shaft (shaft_accepts) lie in the region R: the grown slope quad
//     (4 planes through the apex) between two offsets along kz (the rays' start and end
//     offsets). Any triangle an accepted ray can hit within its interval meets R, and so meets
//     the box of every kd node containing the hit point, and is listed in that node's leaves.
//   * Induction from the root: every node the traversal reaches either is entered by at least
//     one corner lane, whose leaves are then tested, or is one no lane enters: a child the lanes'
//     decisions skip, or a popped node every lane has passed (closest hit). The latter are kept
//     aside ("deferred", with their boxes) and, once R's end is known (the corners' hits),
//     traversed by shaft culling: a node is entered when its box may meet R (collect_deferred;
//     the tolerance of the box test, region.h PlaneSet, exceeds the float test's fuzz). A first
//     child lying wholly on the far side of a split from the apex is not kept: the cone's rays
//     all move away from it.
// So every leaf whose box meets R is tested, whatever the corners did. The paper's incoherence
// flag remains as a statistic (CornerResult::coherent: some node was entered by only some of the
// lanes, or the lanes ended in different nodes); with coherent corners nothing deferred meets
// the region in practice, and shaft culling costs one box test per skipped child.
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <optional>
#include <span>
#include <vector>

#include "geom/triangle_simd.h"
#include "relevant_triangles/conservative_tests.h"
#include "relevant_triangles/region.h"
#include "relevant_triangles/relevant_list.h"
#include "rtt/kdtree.h"
#include "rtt/math.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Capacity of the deferred nodes of one tile; more ends RTT for the tile.
inline constexpr int rtt_max_deferred = 256;

struct DeferredNode {
    BoxV box;
    uint32_t node;
};

/// Nodes kept aside for shaft culling. Each box is one record of 8 floats, lo (x, y, z, 0) and
/// hi (x, y, z, 0): the traversal writes it with two vector stores, and the batch test reads K
/// records as structure of arrays in registers (load_records8), the survivors as vectors.
struct DeferredNodes {
    int count = 0;
    alignas(64) float box[rtt_max_deferred][8];
    uint32_t node[rtt_max_deferred];

    void add(uint32_t index, const BoxV& b) {
        store(box[count], b.lo);
        store(box[count] + 4, b.hi);
        node[count++] = index;
    }
    BoxV get(int i) const {
        BoxV b;
        b.lo = vfloat4::load(box[i]);
        b.hi = vfloat4::load(box[i] + 4);
        return b;
    }
};

enum class CornerStatus {
    untraced,  ///< Corners not traced: direction signs differ (no common traversal order).
    traced,    ///< Corners answered; `list` and `deferred` describe what they reached.
    blocked,   ///< Shadows: `blocker` provably blocks every accepted segment of the tile.
    overflow,  ///< Corners answered, but no list: it or the deferred nodes overflowed, or
               ///< (any-hit) all 4 corners are blocked by different triangles.
};

/// Why a tile is traced instead of answered from a list (RttStats' declined_* counters); the
/// passes record theirs in CornerResult::declined when they give up.
enum class Decline : uint8_t {
    none,
    no_shaft,        ///< The corners make no shaft (origins, axis orders, a refused slope quad), or
                     ///< the tile is not a shaft tile.
    no_end,          ///< R gets no end: the corners' hits lie on several planes or move to another
                     ///< one during the walk, or a corner missed where an end is needed; shadows:
                     ///< samples on several receiver planes, the light on the plane, or a corner
                     ///< point off it.
    budget,          ///< More nodes than the walk's or the deferred culling's budget, or more
                     ///< deferred nodes than they hold.
    list_full,       ///< The relevant list overflowed.
    corners_parted,  ///< The corner packet's lanes parted (lean pass; rtt-paper's flag), their
                     ///< direction signs differ, or (shadows) all 4 corners are blocked by
                     ///< different triangles.
};

struct CornerResult {
    Hit hit[4];             ///< Closest-hit mode: each corner's closest hit (trace_ray's answer).
    uint32_t occluded = 0;  ///< Any-hit mode: corners whose segment is blocked.
    uint32_t blocker = invalid_triangle;
    bool coherent = true;              ///< The paper's flag was never raised.
    Decline declined = Decline::none;  ///< Why the pass gave up, if it did.
    RelevantList list;
    DeferredNodes deferred;

    /// Forgets the previous tile's answers, list and deferred nodes.
    void reset() {
        list.count = 0;
        deferred.count = 0;
        occluded = 0;
        coherent = true;
        declined = Decline::none;
        for (Hit& h : hit) h = Hit{};
    }
};

/// Records why a pass gave up; returns `status`.
inline CornerStatus give_up(CornerResult& out, Decline why,
                            CornerStatus status = CornerStatus::untraced) {
    out.declined = why;
    return status;
}

/// How a corner pass treats the paper's incoherence flag: as a statistic (paper: the pass goes
/// on and shaft culling covers what the corners left out) or as the end of the pass (lean).
enum class CornerPass { paper, lean };

/// What taking one triangle's corner verdict did to a corner pass.
enum class VerdictTaken {
    ok,
    blocked,      ///< Any-hit: the triangle blocks every accepted segment of the tile.
    all_blocked,  ///< Any-hit: all 4 corners are now blocked, by different triangles.
    list_full,    ///< The triangle is relevant but the list has no room left.
};

/// Takes triangle `id`'s verdict `v` into a corner pass (trace_corners, cull_shaft): shadow
/// blockers into `out.occluded`, or closer hits into `best` with `lane_tmax` following
/// (inclusive, as trace_ray; `closer` set when some corner's hit came nearer); a relevant
/// triangle is appended to `out.list`. Callers decide what a stop means for their pass.
template <Query Q>
inline VerdictTaken take_verdict(const CornerVerdict& v, uint32_t id, CornerResult& out,
                                 PacketHit<4>& best, vfloat4& lane_tmax, bool& closer) {
    constexpr bool AnyHit = Q == Query::any_hit;
    if constexpr (AnyHit) {
        out.occluded |= v.hit;
        if (v.blocks_all) {
            out.blocker = id;
            out.occluded = 0xF;
            return VerdictTaken::blocked;
        }
        // All 4 corners blocked, by different triangles: the tile is most likely in shadow,
        // and tracing its segments (which stop at their first blocker) is cheaper than the
        // rest of the list. The corners are answered.
        if (out.occluded == 0xF) return VerdictTaken::all_blocked;
    } else if (v.hit) {
        const vbool4 take = best.update(vbool4::from_bits(v.hit), v.t, id);
        lane_tmax = select(take, v.t, lane_tmax);
        closer |= any(take);
    }
    if (v.relevant) {
        if (out.list.count == rtt_max_relevant) return VerdictTaken::list_full;
        out.list.tri[out.list.count] = id;
        out.list.min_offset[out.list.count++] = v.min_offset;
    }
    return VerdictTaken::ok;
}

/// The status a corner pass stops with after `taken`, or nothing to go on. A full list gives up
/// (Decline::list_full) unless `listing` is given: then the pass goes on without a list
/// (*listing = false).
inline std::optional<CornerStatus> stop_status(VerdictTaken taken, CornerResult& out,
                                               bool* listing = nullptr) {
    switch (taken) {
        case VerdictTaken::ok:
            return std::nullopt;
        case VerdictTaken::blocked:
            return CornerStatus::blocked;
        case VerdictTaken::all_blocked:
            return give_up(out, Decline::corners_parted, CornerStatus::overflow);
        case VerdictTaken::list_full:
            if (!listing) return give_up(out, Decline::list_full);
            out.declined = Decline::list_full;
            *listing = false;
            return std::nullopt;
    }
    return std::nullopt;
}

/// Traces the shaft's corners `corners` (corner_sample order, the rays `shaft` was made from).
/// Query::closest_hit: closest hits, lanes terminating as trace_ray's do (`out.hit`); any_hit:
/// shadow segments (`out.occluded`), traced to their ends (no early exit) unless one triangle
/// blocks every accepted segment. Starts a new mailbox tile. The corners' answers are valid unless
/// `untraced`.
/// Nodes no lane enters are deferred (any_hit: only when their box meets `*region`, which must
/// hold every point of every segment answered from the list; unused, may be null, for closest
/// hits).
/// CornerPass::lean (closest hits, "rtt" at K = 1 and 2): the paper's incoherence flag ends the
/// pass at once (`untraced`).
/// `shaft` may lack its quad (make_shaft_corners only): it is completed (make_shaft_quad) when
/// the first triangle is tested, which most passes that give up never reach; a refused quad
/// ends the pass (`untraced`).
template <Query Q, CornerPass P = CornerPass::paper>
CornerStatus trace_corners(const KdTree& tree, std::span<const TriangleVerts> triangles,
                           Shaft& shaft, const ShaftRegion* region, const Ray (&corners)[4],
                           TriangleMailbox& mailbox, CornerResult& out);

/// Completes the list of a `traced` result by shaft culling of its deferred nodes against
/// `region`, which must hold every point of every ray answered from the list. Returns `traced`
/// (list complete), `blocked` (any_hit: `out.blocker` blocks every accepted segment) or
/// `overflow` (the list overflowed, or more than `budget` nodes had to be entered: a tile so
/// incoherent that tracing its rays is cheaper).
template <Query Q>
CornerStatus collect_deferred(const KdTree& tree, std::span<const TriangleVerts> triangles,
                              const Shaft& shaft, const ShaftRegion& region, int budget,
                              TriangleMailbox& mailbox, CornerResult& out);

}  // namespace RTT_ISA_NS
}  // namespace rtt
