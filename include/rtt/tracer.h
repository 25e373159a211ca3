// The tracer interface: every tracer (reference single ray, SIMD packets, RTT, Embree) answers
// the same batches, so they are compared on exactly the same rays and timed separately for
// primary, shadow and secondary rays.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rtt/kdtree.h"
#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

/// Shadow segments stop this far (in the segment's parameter) from both ends (CONVENTIONS).
inline constexpr float shadow_epsilon = 1e-4f;

/// The one definition of a shadow segment used by every tracer: from the light L towards the
/// hit point p, s in [1e-4, 1 - 1e-4] of L + s (p - L). (CONVENTIONS lets a tracer trace either
/// way.)
inline Ray shadow_ray(const Vec3f& light, const Vec3f& point) {
    return Ray{light, point - light, shadow_epsilon, 1.f - shadow_epsilon};
}

/// A tile of rays laid out as a grid of `width` x `height` samples, row-major. For a 4x4-pixel
/// image tile with K x K antialiasing that is 4K x 4K samples in CONVENTIONS' sample order
/// restricted to the tile (sample row, then sample column).
struct RayTile {
    int width = 0;
    int height = 0;
    std::span<const Ray> rays;  ///< width * height rays.
    /// True when every ray starts from one apex (rays[i].org identical) and the directions were
    /// generated on a planar grid (pinhole camera; planar-mirror reflection about the mirrored
    /// eye), so the 4 corner rays bound a convex shaft holding every other ray of the tile.
    bool shaft = false;
    /// Side in samples of the renderer's 4x4-pixel tiles (4K) when the tile is a larger region
    /// of them (RenderOptions::region); 0 = the tile is one such tile. Tracers may size their
    /// work by it (RTT's walk budget); answers never depend on it.
    int cell = 0;
};

/// Shadow segments from one point light to the hit points of a tile (same grid as RayTile).
struct SegmentTile {
    int width = 0;
    int height = 0;
    Vec3f light;
    std::span<const Vec3f> points;        ///< Hit point p of each sample.
    std::span<const uint32_t> triangles;  ///< Triangle the sample's ray hit (plane identity).
    std::span<const uint8_t> active;      ///< 1 = answer this segment; 0 = skip (visible = 0).
    bool shaft = false;                   ///< Points come from a shaft tile (see RayTile).
    int cell = 0;                         ///< As RayTile::cell.
};

/// Counters every tracer keeps, added up over tiles and threads. RTT's own counters (rays
/// answered from lists, why tiles were declined) are RttStats (rtt/rtt_options.h).
struct TraceStats {
    uint64_t tiles = 0;   ///< Tiles handed to the tracer.
    uint64_t rays = 0;    ///< Rays (or active segments) asked for.
    uint64_t traced = 0;  ///< Rays traversed through the tracer's structure (RTT: not answered).

    /// Every counter, for code that adds or ships them all (sums, MPI ranks).
    std::array<uint64_t*, 3> counters() { return {&tiles, &rays, &traced}; }
    std::array<uint64_t, 3> counter_values() const { return {tiles, rays, traced}; }
    TraceStats& operator+=(const TraceStats& o) {
        tiles += o.tiles;
        rays += o.rays;
        traced += o.traced;
        return *this;
    }
};

struct RttStats;

/// How a sample was answered, for the paper's Figure 5 maps.
enum class SampleAnswer : uint8_t {
    traced = 0,          ///< Traversed through the kd-tree.
    answered_empty = 1,  ///< RTT, relevant list empty (shadows: unoccluded without a test).
    answered_list = 2,   ///< RTT, tested against a non-empty relevant list.
};

/// What a caller may ask of a tile's tracing besides the answers, all optional (Embree's
/// context argument plays this part): counters to add to, and how each sample was answered.
struct TraceContext {
    TraceStats* stats = nullptr;  ///< Added to: the tile's counters.
    RttStats* rtt = nullptr;      ///< Added to by the RTT tracers; others leave it.
    /// One entry per ray (segment) of the tile: how it was answered (Figure 5); empty: none.
    std::span<SampleAnswer> answers;
};

class Tracer {
public:
    virtual ~Tracer() = default;
    virtual std::string_view name() const = 0;

    /// Closest hit of every ray: hits[i] for tile.rays[i]; t and the triangle index, or a miss.
    /// Thread-safe: tiles may be traced concurrently.
    virtual void intersect(const RayTile& tile, std::span<Hit> hits,
                           const TraceContext& context = {}) const = 0;

    /// Visibility of every active segment: visible[i] = 1 when no triangle meets
    /// shadow_ray(tile.light, tile.points[i]) in its parameter range, else 0 (also 0 when
    /// inactive).
    virtual void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                          const TraceContext& context = {}) const = 0;

    /// Closest hits of rays without a tile shape (any origins, directions and intervals, the
    /// spans of equal size): hits[i] for rays[i]. intersect_rays() calls it on chunks of its
    /// rays, concurrently. The default traces them as a one-row tile without a shaft; a tracer
    /// overrides it where another path is faster for such rays (RTT: the BVH kernel).
    virtual void intersect_arbitrary(std::span<const Ray> rays, std::span<Hit> hits,
                                     TraceStats* stats = nullptr) const;

    /// visible[i] = 1 when no triangle meets rays[i] for t in [tmin, tmax], else 0; as
    /// intersect_arbitrary. The default answers from intersect_arbitrary's closest hits;
    /// tracers with an any-hit traversal override it.
    virtual void visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                                   TraceStats* stats = nullptr) const;

    /// Whether intersect_rays and visible_rays trace a large batch grouped by direction and
    /// origin rather than in the caller's order (the answers are the same). Embree's kinds keep
    /// the caller's order: they stand for Embree as its users call it.
    virtual bool reorders_batches() const { return true; }
};

/// Closest hits of arbitrary rays (any origins, directions and [tmin, tmax]): hits[i] for
/// rays[i], through Tracer::intersect_arbitrary on chunks of rays (packet tracers trace them as
/// packets, so rays that are neighbours in the array should be neighbours in space; `rtt` and
/// `bvh` trace them one by one through a BVH). A batch of 16,384 rays or more goes in chunks
/// grouped by direction octant and origin (reorders_batches()), so that rays sharing the tree's
/// nodes follow each other; a smaller one in chunks of consecutive rays. Runs on the calling
/// thread's oneTBB arena (limit it with tbb::global_control or a tbb::task_arena); the answers do
/// not depend on the thread count. Throws rtt::Error when the spans differ in size or a ray has a
/// NaN or infinite value, a zero direction or tmin > tmax.
void intersect_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits,
                    TraceStats* stats = nullptr);

/// Visibility along arbitrary rays: visible[i] = 1 when no triangle meets rays[i] for t in
/// [tmin, tmax], else 0, through Tracer::visible_arbitrary (an any-hit traversal where the
/// tracer has one). The same rays, threads and errors as intersect_rays, but a large batch goes
/// in the grouped order only when a few of its chunks, timed, show its rays waiting on memory:
/// any-hit rays end early, and on most scenes gathering them cost more than it saved (the answers
/// are the same either way; docs/benchmarks.md, "Arbitrary rays"). For a shadow segment from
/// a light L to a point p, pass shadow_ray(L, p): the answers then equal Tracer::occluded's.
void visible_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<uint8_t> visible,
                  TraceStats* stats = nullptr);

/// Names accepted by make_tracer on this build ("ray", "packet", "rtt", ...).
std::vector<std::string> tracer_kinds();

/// Throws rtt::Error, naming the kinds this build has, when `kind` is not one of them: the one
/// check (and message) of a tracer kind for every caller (command line, viewer, Python).
void check_tracer_kind(std::string_view kind);

/// Whether tracers of `kind` read the kd-tree passed to make_tracer. "bvh", "brute" and the
/// Embree kinds build structures of their own: skip the kd-tree's build for them and pass an
/// empty KdTree. Throws as check_tracer_kind.
bool tracer_uses_kdtree(std::string_view kind);

/// Creates a tracer over `scene` and `tree` (both must outlive it; `tree` may be an empty
/// KdTree where !tracer_uses_kdtree(kind)). Throws rtt::Error for an unknown kind
/// (check_tracer_kind), or one this machine or build cannot run.
std::unique_ptr<Tracer> make_tracer(std::string_view kind, const Scene& scene, const KdTree& tree);

}  // namespace rtt
