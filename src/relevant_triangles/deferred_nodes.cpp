// Shaft culling of the nodes the corner lanes left out (corner_pass.h: collect_deferred).
#include <bit>

#include "geom/triangle_simd.h"
#include "relevant_triangles/corner_pass.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <Query Q>
CornerStatus collect_deferred(const KdTree& tree, std::span<const TriangleVerts> triangles,
                              const Shaft& shaft, const ShaftRegion& region, int budget,
                              TriangleMailbox& mailbox, CornerResult& out) {
    constexpr bool AnyHit = Q == Query::any_hit;
    const vfloat4 lane_tmax = vfloat4::load(shaft.tmax);
    const vbool4 lane_of[3] = {vbool4::from_bits(1), vbool4::from_bits(2), vbool4::from_bits(4)};
    DeferredNode stack[kd_max_depth + 1];
    const KdNode* nodes = tree.nodes.data();
    const uint32_t* leaf_ids = tree.leaf_triangles.data();
    const DeferredNodes& d = out.deferred;
    // The deferred boxes are tested K at a time (most fail: branch-free); the survivors are
    // descended one by one.
    constexpr int K = simd_max_width;
    for (int base = 0; base < d.count; base += K) {
        using vf = vfloat<K>;
        vf rec[8];
        load_records8(d.box[base], rec);
        const vf lo[3] = {rec[0], rec[1], rec[2]}, hi[3] = {rec[4], rec[5], rec[6]};
        const int in_batch = std::min(K, d.count - base);
        uint32_t survivors =
            movemask(region.meets<K>(lo, hi)) & (in_batch == 32 ? ~0u : (1u << in_batch) - 1u);
        for (; survivors; survivors &= survivors - 1) {
            const int i = base + std::countr_zero(survivors);
            int top = 0;
            const BoxV box = d.get(i);
            stack[top].box.lo = box.lo;
            stack[top].box.hi = box.hi;
            stack[top++].node = d.node[i];
            bool first = true;  // the deferred node itself passed the batch test
            while (top > 0) {
                --top;
                DeferredNode e;
                e.box.lo = stack[top].box.lo;
                e.box.hi = stack[top].box.hi;
                e.node = stack[top].node;
                while (first || region.meets(e.box)) {
                    first = false;
                    if (--budget < 0) return give_up(out, Decline::budget, CornerStatus::overflow);
                    const KdNode& n = nodes[e.node];
                    if (!n.is_leaf()) {
                        // Children: the box cut at the split, each closed.
                        const int axis = n.axis();
                        DeferredNode& above = stack[top++];
                        above.box.lo = select(lane_of[axis], vfloat4(n.split), e.box.lo);
                        above.box.hi = e.box.hi;
                        above.node = n.above_child();
                        e.box.hi = select(lane_of[axis], vfloat4(n.split), e.box.hi);
                        e.node += 1;
                        continue;
                    }
                    const uint32_t* ids = leaf_ids + n.first_triangle();
                    for (uint32_t k = 0, count = n.triangle_count(); k < count; ++k) {
                        const uint32_t id = ids[k];
                        if (mailbox.seen(id)) continue;
                        // A triangle whose box misses the region cannot be hit by an accepted
                        // ray (PlaneSet's tolerance covers the float test's fuzz).
                        const TriangleVerts& tri = triangles[id];
                        BoxV tb;
                        tb.lo =
                            min(min(BoxV::lanes(tri.v0), BoxV::lanes(tri.v1)), BoxV::lanes(tri.v2));
                        tb.hi =
                            max(max(BoxV::lanes(tri.v0), BoxV::lanes(tri.v1)), BoxV::lanes(tri.v2));
                        if (!region.meets(tb)) continue;
                        const CornerVerdict v = test_corners<Q>(shaft, tri, lane_tmax);
                        if constexpr (AnyHit) {
                            if (v.blocks_all) {
                                out.blocker = id;
                                return CornerStatus::blocked;
                            }
                        }
                        if (!v.relevant) continue;
                        if (out.list.count == rtt_max_relevant)
                            return give_up(out, Decline::list_full, CornerStatus::overflow);
                        out.list.tri[out.list.count] = id;
                        out.list.min_offset[out.list.count++] = v.min_offset;
                    }
                    break;
                }
            }
        }
    }
    out.deferred.count = 0;
    return CornerStatus::traced;
}

template CornerStatus collect_deferred<Query::closest_hit>(const KdTree&,
                                                           std::span<const TriangleVerts>,
                                                           const Shaft&, const ShaftRegion&, int,
                                                           TriangleMailbox&, CornerResult&);
template CornerStatus collect_deferred<Query::any_hit>(const KdTree&,
                                                       std::span<const TriangleVerts>, const Shaft&,
                                                       const ShaftRegion&, int, TriangleMailbox&,
                                                       CornerResult&);

}  // namespace RTT_ISA_NS
}  // namespace rtt
