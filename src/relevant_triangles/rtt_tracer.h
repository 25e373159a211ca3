// The RTT tracers ("rtt", "rtt-paper"): relevant triangles tracing (Dmitriev, Havran, Seidel
// 2004, section 3) behind the Tracer interface. What a tile goes through, and why every answer
// equals trace_ray's: docs/design.md, "RTT exactness" and the sections after it. One file per
// step in this folder:
//   shaft.h / shaft.cpp   the shaft of a tile's 4 corner rays and the per-ray check;
//   conservative_tests.h  the five conservative tests (and the corners' own watertight tests);
//   region.h              the region R of the rays answered from a list, and boxes against it;
//   relevant_list.h       the list and the mailbox;
//   walk.h                the shaft walk: corners and list from one walk of the kd-tree through R;
//   corner_pass.h/.cpp,   the corners as one SSE packet (the paper's, and the lean pass), then
//   deferred_nodes.cpp    shaft culling of the nodes they left out;
//   list_lean.cpp,        the procedures that list a primary tile, one each: the lean corner
//   list_walk.cpp,        pass (small camera tiles), the shaft walk (regions, larger and
//   list_paper.cpp        reflected tiles), the paper's rules ("rtt-paper");
//   inner_rays.h          the inner rays K at a time against the list;
//   tile.h                tile helpers: samples still to trace, corners, end planes;
//   primary_tiles.cpp     primary and reflected tiles: the list's use and the answers;
//   shadow_tiles.cpp      shadow segments;
//   rtt_options.cpp       RttOptions' checks.
// Every ray not answered from a list is traced: declined camera and mirror regions as one
// large packet (src/trace/trace_frustum.h) when narrow, the rest as the widest packets
// (src/trace/trace_packet.h). Counters: TraceStats' traced = corner rays and segments plus
// fallbacks, RttStats' answered = rays answered from a list; rays = traced + answered.
//
// This header: the tracer's class and shared constants (internal to this folder).
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "geom/plane_id.h"
#include "relevant_triangles/corner_pass.h"
#include "relevant_triangles/region.h"
#include "relevant_triangles/tile.h"
#include "relevant_triangles/tolerances.h"
#include "rtt/tracer.h"
#include "simd/isa.h"
#include "simd/simd.h"
#include "trace/blocker_cache.h"
#include "trace/trace_bvh.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

/// Adds its lifetime in nanoseconds to `ns`: wraps each call of the fallback
/// (RttStats::fallback_ns). Two clock reads per declined tile, of 256 rays or more.
class FallbackClock {
public:
    explicit FallbackClock(uint64_t& ns) : ns_(ns), start_(std::chrono::steady_clock::now()) {}
    ~FallbackClock() {
        ns_ += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - start_)
                            .count());
    }
    FallbackClock(const FallbackClock&) = delete;
    FallbackClock& operator=(const FallbackClock&) = delete;

private:
    uint64_t& ns_;
    std::chrono::steady_clock::time_point start_;
};

/// Inner rays go K at a time: 16 with AVX-512, 8 with AVX2, else 4.
inline constexpr int inner_width = simd_max_width;
/// Packet width of the fallback for rays RTT does not answer: the widest packets, whose
/// tracer is the fastest (4x4 samples per packet with AVX-512).
inline constexpr int fallback_width = simd_max_width;
/// Tiles that are no shaft: cosine of the widest angle from the first ray's direction that
/// still goes as packets, and the spread rays per triangle after which the BVH is built for
/// them (RttTracer::spread, bvh_pays; measured in docs/benchmarks.md, "Loose rays").
inline constexpr float loose_cos_max = 0.99619f;  // cos(5 degrees)
inline constexpr double loose_rays_per_triangle = 10.0;
/// Rays of declined regions per triangle after which the BVH is built for them: its
/// build over what it saves per such ray (docs/benchmarks.md, "RTT's fallback").
inline constexpr double declined_rays_per_triangle = 30.0;
// The budgets and the lean pass's extent are RttOptions (include/rtt/rtt_options.h); the
// defaults there were measured in docs/benchmarks.md ("RTT: where it pays", "Regions", "RTT's
// fallback"). Cost rules, not exactness ones.
/// Whether a primary or reflected shaft tile of n samples whose corners are `corners` takes the
/// lean pass. Reflected tiles start on their mirror plane, not at the apex, and the corners'
/// intervals part at the first splits near it: at K = 2 the walk answers 3x more of their rays
/// and is faster; at K = 1 the lean pass stays slightly faster.
inline bool takes_lean_pass(int n, int lean_max_samples, const Ray (&corners)[4]) {
    if (n == 16) return true;
    if (n > lean_max_samples) return false;
    for (const Ray& c : corners)
        if (c.tmin != 0.f) return false;
    return true;
}
using tolerance::unit_roundoff;

/// Adds one tile of `rays` rays, `st.answered` of them from a list, to the context's counters.
inline void record_tile(uint64_t rays, const RttStats& st, const TraceContext& context) {
    if (context.stats) *context.stats += TraceStats{1, rays, rays - st.answered};
    if (context.rtt) *context.rtt += st;
}

/// Adds a declined tile to the counter of its reason (corner_pass.h, Decline).
inline void count_decline(RttStats& st, Decline why) {
    switch (why) {
        case Decline::none:
            break;
        case Decline::no_shaft:
            ++st.declined_shaft;
            break;
        case Decline::no_end:
            ++st.declined_end;
            break;
        case Decline::budget:
            ++st.declined_budget;
            break;
        case Decline::list_full:
            ++st.declined_list;
            break;
        case Decline::corners_parted:
            ++st.declined_corners;
            break;
    }
}

/// The procedures that make a primary shaft's list (list_lean.cpp, list_walk.cpp,
/// list_paper.cpp). Each traces the corners into tls_corners (their hits, and the list).
enum class ListProcedure { lean, walk, paper };
/// What a list procedure left: a list to answer from (`listed`); the corners answered and the
/// rest to trace (`declined`); nothing answered, the whole tile to trace (`untraced`).
enum class ListOutcome { listed, declined, untraced };

/// Per-thread scratch (tracers are called concurrently): the mailbox of the current tile and
/// the corners' result with its list and deferred nodes (too big for the stack of a tile call).
inline thread_local TriangleMailbox tls_mailbox;
inline thread_local CornerResult tls_corners;

class RttTracer final : public Tracer {
public:
    /// RttRules::extended ("rtt"): corners and list from one shaft walk (walk.h), whatever
    /// the paper's incoherence flag would say; primary tiles whose corners hit several triangles
    /// of one plane (and, from 8x8 samples on, of several planes) are answered too. paper
    /// ("rtt-paper"): the paper's corner packet (corner_pass.h) and rules, coherent corners on
    /// one triangle (shadows: coherent corners).
    RttTracer(const Scene& scene, const KdTree& tree, const RttOptions& options)
        : tree_(tree),
          triangles_(gather_triangles(scene)),
          planes_(compute_plane_ids(triangles_)),
          normals_(triangles_, planes_),
          options_(options),
          extended_(options.rules == RttRules::extended) {
        if (options.bvh_at_setup) bvh();
    }
    std::string_view name() const override { return extended_ ? "rtt" : "rtt-paper"; }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override;
    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override;
    /// Rays without a tile shape go through a BVH (trace_bvh.h), built on the first call: one
    /// by one through it they are faster than packets through the kd-tree
    /// (docs/benchmarks.md, "Arbitrary rays").
    void intersect_arbitrary(std::span<const Ray> rays, std::span<Hit> hits,
                             TraceStats* stats) const override;
    void visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                           TraceStats* stats) const override;

private:
    const Bvh<bvh_width>& bvh() const;
    // Tiles that are no shaft (reflections off curved mirrors, their shadow segments) go
    // through the BVH's packets rather than the kd-tree's when it is built or has paid for its
    // build; reflected rays only when their directions spread widely (docs/benchmarks.md,
    // "Loose rays"). Declined shaft regions go through it too.
    static bool spread(std::span<const Ray> rays);
    /// Whether `rays` more (counted in `seen`) may take the BVH: it is built, or such rays
    /// reached `per_triangle` per triangle.
    bool bvh_pays(std::atomic<uint64_t>& seen, double per_triangle, size_t rays) const;
    static bool shaft_tile(bool shaft, int width, int height, size_t n) {
        return shaft && width >= 2 && height >= 2 && size_t(width) * size_t(height) == n &&
               n <= size_t(rtt_max_tile_samples);
    }
    /// A region of several 4x4-pixel tiles (RayTile::cell): tried as one shaft, and traced
    /// whole by packets when the shaft gives no list.
    static bool is_region(int width, int height, int cell) {
        return cell > 0 && (width > cell || height > cell);
    }
    /// A primary shaft tile as the list procedures see it: its corners, the shaft, and what they
    /// found (the end of R, the region, why a tile is declined).
    struct PrimaryShaft;
    ListOutcome list_lean(const RayTile& tile, PrimaryShaft& p) const;
    ListOutcome list_walk(const RayTile& tile, PrimaryShaft& p) const;
    ListOutcome list_paper(const RayTile& tile, PrimaryShaft& p) const;
    /// One shaft tile: answers every ray, adds the rays answered from a list, the tile and its
    /// list length to `st`.
    void intersect_shaft(const RayTile& tile, std::span<Hit> hits, std::span<SampleAnswer> answers,
                         RttStats& st) const;
    /// A shaft tile no list answers, with corner rays `corners` (0 and 3, 1 and 2 opposite):
    /// one large kd-tree packet (trace_frustum.h) when its rays share an origin and lie
    /// densely, else the BVH's packets (built on the first such tile); counts BVH rays in `st`.
    void trace_declined(const RayTile& tile, const Ray (&corners)[4], std::span<Hit> hits,
                        RttStats& st) const;
    void occluded_shaft(const SegmentTile& tile, std::span<uint8_t> visible,
                        std::span<SampleAnswer> answers, RttStats& st) const;
    /// A shadow region no list answers, `active` segments: the kd-tree's packets, or the BVH's
    /// once it is built or has paid for its build, as RttOptions::shadow_fallback says; counts
    /// BVH rays in `st`.
    void trace_declined(const SegmentTile& tile, std::span<uint8_t> visible, BlockerCache& blockers,
                        uint64_t active, RttStats& st) const;
    bool one_receiver_plane(const SegmentTile& tile) const;
    /// Where a primary shaft's region ends: the slab end of the 4 corner hits (t, tri) and the
    /// plane they all lie on (plane_id = no_plane when they lie on several, or the apex is on
    /// it).
    struct PrimaryEnd {
        uint32_t plane_id = no_plane;
        FacingPlane plane;
        float end_limit = 0.f, end_tol = 0.f;
    };
    struct PrimaryShaft {
        Ray corners[4];
        int cs[4];  ///< Their samples.
        Shaft shaft;
        PrimaryEnd end;
        std::optional<ShaftRegion> region;  ///< primary_region(shaft, end), once built.
        bool open = false;                  ///< Listed by a walk without an end.
        Decline declined = Decline::none;   ///< Why, when not listed.
    };
    /// False when some corner missed.
    bool primary_end(const Shaft& shaft, const Ray (&corners)[4], const vfloat4& t,
                     const vint4& tri, PrimaryEnd& e) const;
    /// The same for the corners' closest hits.
    bool primary_end(const Shaft& shaft, const Ray (&corners)[4], const Hit (&hits)[4],
                     PrimaryEnd& e) const;
    /// The region of e (primary_region) from a region of the same shaft and start.
    void narrow_to(ShaftRegion& region, const PrimaryEnd& e) const;
    ShaftRegion primary_region(const Shaft& shaft, const PrimaryEnd& e) const;
    uint64_t answer_primary(const RayTile& tile, const Shaft& s, const RelevantList& list,
                            float end_limit, const FacingPlane* end, float end_tol,
                            std::span<Hit> hits, std::span<SampleAnswer> answers,
                            SampleBits& need) const;
    uint64_t answer_shadows(const SegmentTile& tile, const Shaft& s, const RelevantList& list,
                            bool blocked, const FacingPlane& receiver, float receiver_tol,
                            std::span<uint8_t> visible, std::span<SampleAnswer> answers,
                            SampleBits& need) const;

    const KdTree& tree_;
    TriangleArray triangles_;
    PlaneIds planes_;
    PlaneNormals normals_;
    /// Nodes the shaft walk (walk.h) and the paper's culling of deferred nodes may enter
    /// for a tile of n samples before the tile is traced instead.
    int walk_budget(int n, bool region, bool shadow) const {
        const int divisor =
            shadow ? options_.shadow_region_budget_divisor : options_.region_budget_divisor;
        return options_.walk_budget_base +
               (region ? n / divisor : options_.walk_budget_per_sample * n);
    }
    int deferred_budget(int n) const { return options_.deferred_budget_base + n; }

    RttOptions options_;
    bool extended_;
    mutable std::once_flag bvh_once_;
    mutable std::unique_ptr<const Bvh<bvh_width>> bvh_;
    mutable std::atomic<bool> bvh_built_{false};
    mutable std::atomic<uint64_t> loose_rays_{0};     ///< Spread rays of tiles that are no shaft.
    mutable std::atomic<uint64_t> declined_rays_{0};  ///< Rays of declined regions.
};

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
