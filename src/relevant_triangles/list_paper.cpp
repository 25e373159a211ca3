// The paper's procedure ("rtt-paper"), one of those that list a primary shaft (rtt_tracer.h):
// coherent corners on one triangle, the nodes they left out shaft culled.
#include "relevant_triangles/rtt_tracer.h"
#include "trace/trace_packet.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

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

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
