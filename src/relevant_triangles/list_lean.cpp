// The lean corner pass, one of the procedures that list a primary shaft (rtt_tracer.h): the
// paper's corner packet stopped at the first sign of incoherence, for small tiles from the apex.
#include "relevant_triangles/rtt_tracer.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

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

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
