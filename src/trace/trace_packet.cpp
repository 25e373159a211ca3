#include "trace/trace_packet.h"

#include <bit>
#include <utility>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/kernels.h"
#include "trace/octant_groups.h"
#include "trace/packet_blocks.h"
#include "trace/root_clip.h"
#include "trace/trace_frustum.h"
#include "trace/trace_ray.h"
#include "trace/traced_tile.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

/// One deferred subtree: node, per-lane [t0, t1] and the lanes that visit it.
/// K = 4: one 64-byte cache line per entry. The node is held as a pointer, not an index: see
/// the descent loop in traverse_impl().
template <int K>
struct alignas(sizeof(vfloat<K>)) PacketStackEntry {
    vfloat<K> t0, t1;
    vbool<K> active;
    const KdNode* node;
};
static_assert(sizeof(PacketStackEntry<4>) == 64);
#ifdef RTT_HAVE_SIMD8
static_assert(sizeof(PacketStackEntry<8>) == 128);
#endif
#ifdef RTT_HAVE_SIMD16
static_assert(sizeof(PacketStackEntry<16>) == 192);  // the 16-lane mask is 2 bytes
#endif

/// Result of one packet traversal: closest hits (AnyHit = false) or occluded lanes (true).
template <int K, bool AnyHit>
struct TraversalResult;
template <int K>
struct TraversalResult<K, false> {
    PacketHit<K> best;
};
template <int K>
struct TraversalResult<K, true> {
    vbool<K> occluded = vbool<K>(false);
    uint32_t blocker = ~0u;  ///< The last triangle found blocking a lane, ~0u for none.
};

/// Traverses the tree with the lanes `in` of `rays`, all of which share the sign of every
/// direction component (the caller splits the others off).
///
/// Per lane this is trace_ray's traversal (trace_ray.h), step for step:
///  * interval: [tmin, tmax] clipped to the padded bounds; a NaN slab distance never shrinks
///    it (max/min return their second operand on NaN, as the scalar `if (tn > t0)` does); the
///    ends the box moved are widened by the split margin, within [tmin, tmax];
///  * inner node: d, m = (|d| + s) * kd_margin (0 along a zero direction component),
///    first_hi = min(tb, d + m), second_lo = max(ta, d - m) with the scalar std::min/std::max
///    results (see vfloat4.h: std::min(x, y) == min(y, x)), so a NaN d gives [ta, tb] to both
///    children, as the scalar NaN branch does; the packet enters a child when some lane does,
///    with exactly those lanes active;
///  * a popped entry drops the lanes whose t0 exceeds their best t. A lane that visits only the
///    far child while its neighbours take the near one reaches that child through the stack,
///    where the scalar ray enters it directly, untested. The test cannot drop such a lane: it
///    skips the near child only when ta > d + m >= d - m, so its far interval starts at its
///    current ta, and ta has not changed since the lane's last pop passed the test (descending
///    keeps ta, except into a pushed far child) while best t has not changed either (no leaf on
///    the way). So each lane visits exactly the scalar ray's nodes, in the same order, and
///    meets the same triangles: the answers are trace_ray's bit for bit, even on a tree that
///    lost a triangle (tests/packet_test.cpp checks both).
///  * leaves: each triangle against the active lanes' [tmin, best t] (inclusive); ties at
///    equal t go to the smaller index (PacketHit::update). Any-hit lanes retire on their first
///    hit; the traversal ends when every lane has.
///
/// ZeroDir: some lane of `in` has a zero direction component (its split distances along that
/// axis take no margin). Without such lanes the margin needs no per-axis select.
/// `blockers` (any hit only, may be null): triangles tested on every lane before the traversal
/// (BlockerCache); lanes they block are occluded whatever the traversal would meet first.
template <int K, bool AnyHit, bool CollectStats, bool ZeroDir>
RTT_FORCEINLINE TraversalResult<K, AnyHit> traverse_impl(const KdTree& tree,
                                                         std::span<const TriangleVerts> triangles,
                                                         const RayPacket<K>& rays, uint32_t in,
                                                         PacketStats* stats,
                                                         const BlockerCache* blockers) {
    using vf = vfloat<K>;
    using vb = vbool<K>;
    TraversalResult<K, AnyHit> result;

    const Vec3v<K> org{vf::load(rays.org[0]), vf::load(rays.org[1]), vf::load(rays.org[2])};
    const Vec3v<K> dir{vf::load(rays.dir[0]), vf::load(rays.dir[1]), vf::load(rays.dir[2])};
    const vf inv[3] = {rcp(dir.x), rcp(dir.y), rcp(dir.z)};
    const vf orgv[3] = {org.x, org.y, org.z};
    const vb in_mask = vb::from_bits(in);
    WatertightPacket<K> wp(org, dir, vf::load(rays.tmin), vf::load(rays.tmax), in_mask);
    // The common sign: the child on the side the rays come from first is `above` when the
    // direction's sign bit is set (also for -0), as in trace_ray. Bit a = axis a.
    const uint32_t above_first = ((signbits(dir.x) & in) != 0 ? 1u : 0u) |
                                 ((signbits(dir.y) & in) != 0 ? 2u : 0u) |
                                 ((signbits(dir.z) & in) != 0 ? 4u : 0u);
    if constexpr (AnyHit) {
        if (blockers) {
            result.occluded = blocked_by(*blockers, wp, in_mask);
            if constexpr (CollectStats) stats->cached += uint64_t(popcount(result.occluded));
            if ((movemask(result.occluded) & in) == in) return result;
        }
    }

    vf t0, t1, t_scale;
    clip_to_root<K>(padded_bounds(tree.bounds), orgv, dir, inv, wp.tmin, wp.tmax, t0, t1, t_scale);
    const vb dir_zero[3] = {dir.x == vf(0.f), dir.y == vf(0.f), dir.z == vf(0.f)};
    if constexpr (CollectStats) {
        stats->packets += 1;
        stats->lanes += uint64_t(std::popcount(in));
    }
    const vb start = in_mask & (t0 <= t1);
    if (none(start)) return result;
    const uint32_t started = movemask(start);

    PacketStackEntry<K> stack[kd_max_depth + 1];
    int top = 0;
    // Entries are written and read field by field: building one in a temporary and copying it
    // made GCC move it with unaligned 32-byte loads that stall on store forwarding.
    const auto push = [&](const KdNode* node, vf lo, vf hi, vb lanes) {
        PacketStackEntry<K>& s = stack[top++];
        s.t0 = lo;
        s.t1 = hi;
        s.active = lanes;
        s.node = node;
    };
    const KdNode* nodes = tree.nodes.data();
    push(nodes, t0, t1, start);
    const uint32_t* leaf_ids = tree.leaf_triangles.data();
    const vf margin(kd_margin);

    while (top > 0) {
        const PacketStackEntry<K>& e = stack[--top];
        vf ta = e.t0, tb = e.t1;
        vb active = e.active;
        const KdNode* node = e.node;
        if constexpr (AnyHit) {
            active = andnot(active, result.occluded);
        } else {
            active = not_greater(active, ta, result.best.t);
        }
        if (none(active)) continue;
        // The descent waits on its pointer chain (node -> its bits -> next node), so children
        // are pointers: `below` is node + 1 without waiting for the load, `above` one shift and
        // one lea after it (uint32_t indices cost GCC a copy and a scaled lea per step).
        while (!node->is_leaf()) {
            if constexpr (CollectStats) {
                stats->inner += 1;
                stats->inner_lanes += uint64_t(popcount(active));
            }
            const KdNode& n = *node;
            const int axis = n.axis();
            const KdNode* below = node + 1;
            const KdNode* above = nodes + n.above_child();
            // A branch, not a blend: it is predicted right (one sign per packet and axis), and
            // it keeps the next node's address off the SIMD dependency chain and, when it is
            // `below`, off the node's load.
            const bool flip = (above_first >> axis) & 1u;
            const KdNode* first = below;
            const KdNode* second = above;
            if (flip) {
                // GCC turned selects into cmovs, which wait for the node's load; the empty asm
                // keeps this a branch.
                asm("" : "+r"(first), "+r"(second));
                std::swap(first, second);
            }
            const vf d = (vf(n.split) - orgv[axis]) * inv[axis];
            vf m = (abs(d) + t_scale) * margin;
            if constexpr (ZeroDir) m = select(dir_zero[axis], vf(0.f), m);
            const vf hi = d + m, lo = d - m;
            const vf first_hi = min(hi, tb);
            const vf second_lo = max(lo, ta);
            // ta <= first_hi and second_lo <= tb, shortened: active lanes have ta <= tb (every
            // interval is entered only when non-empty), so ta <= min(tb, hi) is !(ta > hi),
            // NaN included; this keeps min/max off the path to the branch.
            // Masked compares: at K = 16 the masks stay in mask registers for the branches.
            const vb visit_first = not_greater(active, ta, hi);
            const vb visit_second = not_greater(active, lo, tb);
            if (any(visit_first)) {
                if (any(visit_second)) {
                    // Loaded by the time the stack returns to it: it pays on caches other work
                    // filled, as in a renderer (docs/benchmarks.md, "Packet tracer").
                    __builtin_prefetch(second);
                    push(second, second_lo, tb, visit_second);
                }
                node = first;
                tb = first_hi;
                active = visit_first;
            } else {
                // Every active lane visits a child: missing both would need
                // tb < d - m <= d + m < ta with m >= 0 (NaNs make a visit), but ta <= tb.
                node = second;
                ta = second_lo;
                active = visit_second;
            }
        }
        const KdNode& leaf = *node;
        const uint32_t* ids = leaf_ids + leaf.first_triangle();
        if constexpr (CollectStats) stats->leaves += 1;
        const uint32_t count = leaf.triangle_count();
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t id = ids[k];
            if constexpr (CollectStats) {
                stats->tests += 1;
                stats->test_lanes += uint64_t(popcount(active));
            }
            vf t;
            // Closest hit: no early return, which triangles a coherent packet misses altogether
            // is hard to predict and a mispredicted exit costs more than the division it saves.
            // Any hit: the exit pays; shadow packets miss most leaf triangles outright (plants
            // -16 %, docs/benchmarks.md "Packet tracer").
            const vb hit = intersect_watertight<K, AnyHit>(wp, active, triangles[id], t);
            if constexpr (AnyHit) {
                result.occluded |= hit;
                result.blocker = movemask(hit) ? id : result.blocker;
                active = andnot(active, hit);
                if (none(active)) break;
            } else {
                // inclusive tmax: a later equal-t hit still reaches the index tie-break
                wp.tmax = select(result.best.update(hit, t, id), t, wp.tmax);
            }
        }
        if constexpr (AnyHit) {
            if ((movemask(result.occluded) & started) == started) return result;
        }
    }
    return result;
}

/// traverse_impl() for the lanes `in`, with the margin select only when some lane needs it.
template <int K, bool AnyHit, bool CollectStats>
RTT_FORCEINLINE TraversalResult<K, AnyHit> traverse(const KdTree& tree,
                                                    std::span<const TriangleVerts> triangles,
                                                    const RayPacket<K>& rays, uint32_t in,
                                                    PacketStats* stats,
                                                    const BlockerCache* blockers = nullptr) {
    using vf = vfloat<K>;
    const vf zero(0.f);
    const uint32_t zero_lanes =
        movemask((vf::load(rays.dir[0]) == zero) | (vf::load(rays.dir[1]) == zero) |
                 (vf::load(rays.dir[2]) == zero));
    if (zero_lanes & in) [[unlikely]]
        return traverse_impl<K, AnyHit, CollectStats, true>(tree, triangles, rays, in, stats,
                                                            blockers);
    return traverse_impl<K, AnyHit, CollectStats, false>(tree, triangles, rays, in, stats,
                                                         blockers);
}

/// Groups the lanes of `active` by the octant of their direction (sign bits of x, y, z) and
/// calls `one(lane)` for a lone lane, `many(lanes)` for a group of several.
template <int K, typename One, typename Many>
RTT_FORCEINLINE void for_each_octant(const RayPacket<K>& rays, uint32_t active, One&& one,
                                     Many&& many) {
    for_each_octant_group(
        signbits(vfloat<K>::load(rays.dir[0])), signbits(vfloat<K>::load(rays.dir[1])),
        signbits(vfloat<K>::load(rays.dir[2])), active, [&](uint32_t lanes, uint32_t) {
            if (std::has_single_bit(lanes))
                one(std::countr_zero(lanes));
            else
                many(lanes);
        });
}

}  // namespace

PacketStats& PacketStats::operator+=(const PacketStats& o) {
    packets += o.packets;
    lanes += o.lanes;
    single_rays += o.single_rays;
    inner += o.inner;
    inner_lanes += o.inner_lanes;
    leaves += o.leaves;
    tests += o.tests;
    test_lanes += o.test_lanes;
    cached += o.cached;
    return *this;
}

template <int K>
void trace_packet(const KdTree& tree, std::span<const TriangleVerts> triangles,
                  const RayPacket<K>& rays, uint32_t active, Hit* hits, PacketStats* stats) {
    if (tree.nodes.empty()) {
        for (uint32_t b = active; b; b &= b - 1) hits[std::countr_zero(b)] = Hit{};
        return;
    }
    for_each_octant<K>(
        rays, active,
        [&](int lane) {
            hits[lane] = trace_ray(tree, triangles, rays.get(lane));
            if (stats) stats->single_rays += 1;
        },
        [&](uint32_t lanes) {
            // The hits are read from the traversal's result in place: copying the PacketHit
            // first (a conditional's member) moved it with a load wider than its stores, which
            // stalled on store forwarding (perf, `packet`).
            const auto write = [&](const PacketHit<K>& best) {
                for (uint32_t b = lanes; b; b &= b - 1) {
                    const int lane = std::countr_zero(b);
                    hits[lane] = Hit{best.t[lane], uint32_t(best.tri[lane])};
                }
            };
            if (stats)
                write(traverse<K, false, true>(tree, triangles, rays, lanes, stats).best);
            else
                write(traverse<K, false, false>(tree, triangles, rays, lanes, nullptr).best);
        });
}

template <int K>
uint32_t occluded_packet(const KdTree& tree, std::span<const TriangleVerts> triangles,
                         const RayPacket<K>& rays, uint32_t active, PacketStats* stats,
                         BlockerCache* blockers) {
    if (tree.nodes.empty()) return 0;
    uint32_t occluded = 0;
    for_each_octant<K>(
        rays, active,
        [&](int lane) {
            occluded |= uint32_t(occluded_ray(tree, triangles, rays.get(lane))) << lane;
            if (stats) stats->single_rays += 1;
        },
        [&](uint32_t lanes) {
            const TraversalResult<K, true> r =
                stats ? traverse<K, true, true>(tree, triangles, rays, lanes, stats, blockers)
                      : traverse<K, true, false>(tree, triangles, rays, lanes, nullptr, blockers);
            occluded |= movemask(r.occluded) & lanes;
            if (blockers && r.blocker != ~0u) blockers->note(r.blocker, triangles[r.blocker]);
        });
    return occluded;
}

template <int K>
void trace_tile_packets(const KdTree& tree, std::span<const TriangleVerts> triangles,
                        const RayTile& tile, std::span<Hit> hits, PacketStats* stats) {
    for_each_ray_block<K>(
        tile, [](int) { return true; },
        [&](const RayPacket<K>& packet, uint32_t active, const int* sample) {
            Hit out[K];
            trace_packet<K>(tree, triangles, packet, active, out, stats);
            for (uint32_t b = active; b; b &= b - 1)
                hits[sample[std::countr_zero(b)]] = out[std::countr_zero(b)];
        });
}

template <int K>
uint64_t occluded_tile_packets(const KdTree& tree, std::span<const TriangleVerts> triangles,
                               const SegmentTile& tile, std::span<uint8_t> visible,
                               PacketStats* stats, BlockerCache* blockers) {
    for (uint8_t& v : visible) v = 0;
    uint64_t count = 0;
    for_each_segment_block<K>(
        tile, [&](int s) { return tile.active[s] != 0; },
        [&](const RayPacket<K>& packet, uint32_t active, const int* sample) {
            const uint32_t occluded =
                occluded_packet<K>(tree, triangles, packet, active, stats, blockers);
            for (uint32_t b = active; b; b &= b - 1) {
                const int lane = std::countr_zero(b);
                visible[sample[lane]] = !((occluded >> lane) & 1u);
            }
            count += uint64_t(std::popcount(active));
        });
    return count;
}

namespace {

/// The packet tracers behind the Tracer interface: "packet" (K = 4, the paper's baseline),
/// "packet8", "packet16"; and "frustum" (K = the widest), which traces a shaft tile whose rays
/// share an origin as one large packet (trace_frustum.h), anything else as K-wide packets, its
/// shadow packets with a BlockerCache.
template <int K>
class PacketTracer final : public Tracer {
public:
    PacketTracer(const Scene& scene, const KdTree& tree, bool frustum = false)
        : tree_(tree), triangles_(gather_triangles(scene)), frustum_(frustum) {}
    std::string_view name() const override {
        return frustum_ ? "frustum" : K == 4 ? "packet" : (K == 8 ? "packet8" : "packet16");
    }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        if (!frustum_ || !tile.shaft ||
            !trace_frustum(tree_, triangles_, tile.rays, tile.width, tile.height, hits))
            trace_tile_packets<K>(tree_, triangles_, tile, hits);
        record_traced_tile(tile.rays.size(), context);
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        // The paper's packet baselines stay plain (BlockerCache says why).
        BlockerCache blockers;
        const uint64_t n = occluded_tile_packets<K>(tree_, triangles_, tile, visible, nullptr,
                                                    frustum_ ? &blockers : nullptr);
        record_traced_tile(n, context);
    }

private:
    const KdTree& tree_;
    TriangleArray triangles_;
    bool frustum_;
};

}  // namespace

template <int K>
std::unique_ptr<Tracer> make_packet_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<PacketTracer<K>>(scene, tree);
}

std::unique_ptr<Tracer> make_frustum_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<PacketTracer<simd_max_width>>(scene, tree, true);
}

#define RTT_INSTANTIATE_PACKET(K)                                                             \
    template void trace_packet<K>(const KdTree&, std::span<const TriangleVerts>,              \
                                  const RayPacket<K>&, uint32_t, Hit*, PacketStats*);         \
    template uint32_t occluded_packet<K>(const KdTree&, std::span<const TriangleVerts>,       \
                                         const RayPacket<K>&, uint32_t, PacketStats*,         \
                                         BlockerCache*);                                      \
    template void trace_tile_packets<K>(const KdTree&, std::span<const TriangleVerts>,        \
                                        const RayTile&, std::span<Hit>, PacketStats*);        \
    template uint64_t occluded_tile_packets<K>(const KdTree&, std::span<const TriangleVerts>, \
                                               const SegmentTile&, std::span<uint8_t>,        \
                                               PacketStats*, BlockerCache*);                  \
    template std::unique_ptr<Tracer> make_packet_tracer<K>(const Scene&, const KdTree&);

RTT_INSTANTIATE_PACKET(4)
#ifdef RTT_HAVE_SIMD8
RTT_INSTANTIATE_PACKET(8)
#endif
#ifdef RTT_HAVE_SIMD16
RTT_INSTANTIATE_PACKET(16)
#endif

}  // namespace RTT_ISA_NS
}  // namespace rtt
