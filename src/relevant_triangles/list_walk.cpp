// The shaft walk, one of the procedures that list a primary shaft (rtt_tracer.h): one
// front-to-back walk of the kd-tree through the region R, narrowed as the corners' hits come in.
#include "relevant_triangles/rtt_tracer.h"
#include "relevant_triangles/walk.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

ListOutcome RttTracer::list_walk(const RayTile& tile, PrimaryShaft& p) const {
    // One walk through the shaft (walk.h), narrowed as the corners' hits come nearer. Each
    // region must contain the next one (walk.h): the end offset and tolerance only shrink with
    // the hits.
    //  * When the 4 hits first lie on one plane P, R narrows to P, and the walk gives up if the
    //    hits later move to another plane (the regions of two planes need not nest once the
    //    slope quad is grown): the whole tile is traced.
    //  * When they first lie on several planes, R's slab end narrows only, and inner rays are
    //    answered within the slab (an object's silhouette over a wall: nearly all of them).
    //    Measured in docs/benchmarks.md, "RTT: where it pays".
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
        walk_budget(n, is_region(tile.width, tile.height, tile.cell), false), tls_mailbox, res,
        narrow);
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

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
