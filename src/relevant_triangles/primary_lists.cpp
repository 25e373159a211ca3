// The three procedures that make a primary shaft's relevant list (rtt_tracer.h, "Per tile"):
// the lean corner pass, the shaft walk and the paper's corner packet. Each traces the corners
// into tls_corners (their hits, and the list) and says whether the tile is listed, declined
// (corners answered, the rest traced) or untraced (nothing answered).
#include "relevant_triangles/rtt_tracer.h"
#include "relevant_triangles/walk.h"
#include "trace/trace_packet.h"

namespace rtt::rtt_detail {

ListOutcome RttTracer::list_lean(const RayTile& tile, PrimaryShaft& p) const {
    // Small tiles (takes_lean_pass): the paper's procedure, leaner than the walk. The corners go
    // through the tree as one SSE packet and the pass stops at the first sign of incoherence
    // (the tile is then traced by the widest packets at once); nodes no corner enters are
    // deferred untested and shaft culled against R afterwards, 16 boxes per test
    // (collect_deferred, within deferred_budget). Exact as rtt-paper: every leaf whose box may
    // meet R is tested (corner_pass.h).
    const int n = int(tile.rays.size());
    CornerResult& res = tls_corners;
    const CornerStatus status = trace_corners<Query::closest_hit, CornerPass::lean>(
        tree_, triangles_, p.shaft, nullptr, p.corners, tls_mailbox, res);
    p.declined = res.declined;
    if (status == CornerStatus::untraced) return ListOutcome::untraced;
    // One plane P for the 4 hits, as the walk asks (primary_end): R ends on P.
    if (status != CornerStatus::traced) return ListOutcome::declined;
    if (!primary_end(p.shaft, p.corners, res.hit, p.end) || p.end.plane_id == no_plane) {
        p.declined = Decline::no_end;
        return ListOutcome::declined;
    }
    if (!complete_shaft(p.shaft)) {
        p.declined = Decline::no_shaft;
        return ListOutcome::declined;
    }
    p.region.emplace(primary_region(p.shaft, p.end));
    if (collect_deferred<Query::closest_hit>(tree_, triangles_, p.shaft, *p.region,
                                             deferred_budget(n), tls_mailbox,
                                             res) != CornerStatus::traced) {
        p.declined = res.declined;
        return ListOutcome::declined;
    }
    return ListOutcome::listed;
}

ListOutcome RttTracer::list_walk(const RayTile& tile, PrimaryShaft& p) const {
    // One walk through the shaft (walk.h), narrowed as the corners' hits come nearer. Each
    // region must contain the next one (walk.h): the end offset and tolerance only shrink with
    // the hits.
    //  * When the 4 hits first lie on one plane P, R narrows to P, and the walk gives up if the
    //    hits later move to another plane (the regions of two planes need not nest once the
    //    slope quad is grown): the whole tile is traced.
    //  * When they first lie on several planes, R's slab end narrows only, and inner rays are
    //    answered within the slab (an object's silhouette over a wall: nearly all of them).
    //    Measured in docs/benchmarks.md, "The lean corner pass at K = 2".
    const int n = int(tile.rays.size());
    CornerResult& res = tls_corners;
    ShaftRegion walk_region(p.shaft, tree_.bounds, p.shaft.start_lo, pos_inf);
    uint32_t plane = no_plane;
    bool slab_only = false;
    const auto narrow = [&](const PacketHit<4>& best, ShaftRegion& r) {
        PrimaryEnd e;
        if (!primary_end(p.shaft, p.corners, best.t, best.tri, e)) return Narrowed::same;
        if (plane == no_plane && !slab_only) {
            slab_only = e.plane_id == no_plane;
            plane = e.plane_id;
        }
        if (slab_only) e.plane_id = no_plane;  // the slab's end only
        if (e.plane_id != plane) return Narrowed::abandon;
        narrow_to(r, e);
        return Narrowed::smaller;
    };
    const CornerStatus status = cull_shaft<Query::closest_hit>(
        tree_, triangles_, p.shaft, walk_region,
        walk_budget(n, is_region(tile.width, tile.height, tile.cell)), tls_mailbox, res, narrow);
    p.declined = res.declined;
    if (status == CornerStatus::untraced) return ListOutcome::untraced;
    if (primary_end(p.shaft, p.corners, res.hit, p.end)) {
        if (slab_only || p.end.plane_id != no_plane) return ListOutcome::listed;
        p.declined = Decline::no_end;
        return ListOutcome::declined;
    }
    // A corner missed: `narrow` never narrowed, and the completed walk listed every triangle an
    // accepted ray can hit anywhere in the cone beyond the start (within the scene's bounds), so
    // a ray that hits none of them misses (docs/design.md, "Walks without an end").
    p.open = true;
    p.end.end_limit = pos_inf;
    p.end.plane_id = no_plane;
    return ListOutcome::listed;
}

ListOutcome RttTracer::list_paper(const RayTile& tile, PrimaryShaft& p) const {
    // The paper's rules: the corners as one SSE packet with the incoherence flag, answered only
    // when they stayed coherent and hit one triangle; the nodes they left out shaft culled.
    const int n = int(tile.rays.size());
    CornerResult& res = tls_corners;
    const CornerStatus status = trace_corners<Query::closest_hit>(
        tree_, triangles_, p.shaft, nullptr, p.corners, tls_mailbox, res);
    if (status == CornerStatus::untraced) {
        RayPacket<4> packet;
        for (int i = 0; i < 4; ++i) packet.set(i, p.corners[i]);
        trace_packet<4>(tree_, triangles_, packet, 0xF, res.hit);
    }
    const bool one_triangle = res.hit[1].tri == res.hit[0].tri &&
                              res.hit[2].tri == res.hit[0].tri && res.hit[3].tri == res.hit[0].tri;
    p.declined = res.declined;
    if (status != CornerStatus::traced) return ListOutcome::declined;
    if (!res.coherent) {
        p.declined = Decline::corners_parted;
        return ListOutcome::declined;
    }
    if (!one_triangle || !primary_end(p.shaft, p.corners, res.hit, p.end) ||
        p.end.plane_id == no_plane) {
        p.declined = Decline::no_end;
        return ListOutcome::declined;
    }
    if (collect_deferred<Query::closest_hit>(tree_, triangles_, p.shaft,
                                             primary_region(p.shaft, p.end), deferred_budget(n),
                                             tls_mailbox, res) != CornerStatus::traced) {
        p.declined = res.declined;
        return ListOutcome::declined;
    }
    return ListOutcome::listed;
}

}  // namespace rtt::rtt_detail
