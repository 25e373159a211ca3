// RTT with typed options: what make_tracer("rtt") and make_tracer("rtt-paper") build, with
// every knob of the method named. No option changes an answer: they decide how much work RTT
// tries before tracing a tile with packets, never whether an answer is exact (docs/design.md,
// "RTT exactness").
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <utility>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

/// RTT's counters (TraceContext::rtt), added up over tiles and threads: with TraceStats, the
/// rows of the paper's Table 1 and the reasons tiles were traced rather than answered.
struct RttStats {
    uint64_t rtt_tiles = 0;     ///< Tiles whose inner rays RTT answered from the relevant list.
    uint64_t answered = 0;      ///< Rays answered from a relevant list without traversal.
    uint64_t relevant_sum = 0;  ///< Sum of relevant-list lengths over RTT tiles.
    uint64_t open_tiles = 0;    ///< RTT tiles listed by a walk without an end (a corner missed).
    uint64_t empty_tiles = 0;   ///< Of those, tiles whose list is empty: every accepted ray misses.
    // Tiles traced instead of answered from a list, by the first reason met (docs/design.md,
    // "Why a tile is declined"); with rtt_tiles they add up to the tiles that had something to
    // answer.
    uint64_t declined_shaft = 0;    ///< No shaft: not a shaft tile, or corners that make none.
    uint64_t declined_end = 0;      ///< R gets no end (hits or receivers on several planes).
    uint64_t declined_budget = 0;   ///< The walk or the deferred nodes' culling ran out of nodes.
    uint64_t declined_list = 0;     ///< The relevant list overflowed.
    uint64_t declined_corners = 0;  ///< The corner packet parted, or all 4 shadow corners blocked.
    /// Nanoseconds, summed over threads, spent tracing the rays not answered (declined tiles
    /// and refused rays); the rest of RTT's time went to answered tiles.
    uint64_t fallback_ns = 0;
    /// Of the rays traced, those that went through the BVH rather than the kd-tree: declined
    /// regions, and tiles that are no shaft (reflections off curved mirrors, their shadows).
    uint64_t bvh_rays = 0;

    /// Every counter, for code that adds or ships them all (sums, MPI ranks).
    std::array<uint64_t*, 12> counters() {
        return {&rtt_tiles,     &answered,         &relevant_sum, &open_tiles,
                &empty_tiles,   &declined_shaft,   &declined_end, &declined_budget,
                &declined_list, &declined_corners, &fallback_ns,  &bvh_rays};
    }
    std::array<uint64_t, 12> counter_values() const {
        return {rtt_tiles,     answered,         relevant_sum, open_tiles,
                empty_tiles,   declined_shaft,   declined_end, declined_budget,
                declined_list, declined_corners, fallback_ns,  bvh_rays};
    }
    RttStats& operator+=(const RttStats& o) {
        const auto values = o.counter_values();
        const auto fields = counters();
        for (size_t i = 0; i < fields.size(); ++i) *fields[i] += values[i];
        return *this;
    }
    /// Sum of the declined_* counters.
    uint64_t declined() const {
        return declined_shaft + declined_end + declined_budget + declined_list + declined_corners;
    }
    double fallback_seconds() const { return double(fallback_ns) * 1e-9; }
    double avg_relevant() const {
        return rtt_tiles ? double(relevant_sum) / double(rtt_tiles) : 0.0;
    }
};

/// RttStats' declined_* counters with their names in JSON (--stats-json, rtt bench) and
/// Python (last_stats["declined"]).
inline constexpr std::array<std::pair<const char*, uint64_t RttStats::*>, 5> declined_fields{{
    {"no_shaft", &RttStats::declined_shaft},
    {"no_end", &RttStats::declined_end},
    {"budget", &RttStats::declined_budget},
    {"list_full", &RttStats::declined_list},
    {"corners_parted", &RttStats::declined_corners},
}};

/// Which procedure answers a shaft tile.
enum class RttRules : uint8_t {
    /// "rtt": corners and relevant list from one front-to-back walk of the shaft, primary tiles
    /// answered when the corners hit one plane (several planes from 8x8 samples on).
    extended,
    /// "rtt-paper": the paper's corner packet and rules, coherent corners on one triangle.
    paper,
};

/// How RTT traces the shadow regions it declines once its BVH is built (RttOptions).
enum class ShadowFallback : uint8_t {
    /// The BVH's packets, behind the blocker cache: faster in every scene and K measured
    /// (docs/benchmarks.md, "RTT's fallback").
    bvh,
    /// The kd-tree's packets, behind the blocker cache (for comparison).
    kd_tree,
};

struct RttOptions {
    RttRules rules = RttRules::extended;
    /// The shaft walk gives a tile of n samples up (and traces it) after entering
    /// walk_budget_base + walk_budget_per_sample * n kd-tree nodes: at the default, about what
    /// one 16-wide packet visits for a 4x4-sample tile (docs/benchmarks.md). >= 1 and >= 0.
    int walk_budget_base = 48;
    int walk_budget_per_sample = 1;
    /// Regions of several 4x4-pixel tiles (RayTile::cell, RenderOptions::region) of n samples
    /// are walked with walk_budget_base + n / region_budget_divisor nodes instead (primary and
    /// reflected rays; shadow rays with shadow_region_budget_divisor): a region whose shaft gives
    /// no list is traced whole, so its walk should give up early. At K = 1, 48 + 256 / 16 nodes
    /// for primary regions (docs/benchmarks.md, "Regions"). >= 1.
    int region_budget_divisor = 16;
    int shadow_region_budget_divisor = 4;
    /// The same for the paper's shaft culling of what its corners left out (rtt-paper, and
    /// the lean pass of `extended`): deferred_budget_base + n nodes. >= 1.
    int deferred_budget_base = 8;
    /// Tiles from the apex of up to this many samples take the lean corner pass (the paper's
    /// corner packet, stopped at the first sign of incoherence) instead of the walk under
    /// `extended` rules: the default 64 covers K = 1 and 2, where it measured faster. 0 = always
    /// walk (4x4-sample tiles still take the lean pass). At most rtt_max_samples_per_tile.
    int lean_max_samples = 64;
    /// Declined regions (docs/benchmarks.md, "RTT's fallback") are traced faster through a BVH
    /// than through the kd-tree, but the BVH costs a build. By default it is built once such rays
    /// have paid for it (about 30 per triangle, tens of frames); bvh_at_setup builds it with the
    /// tracer, for long renders and for benchmarks that time frames apart from builds. Loose rays
    /// off curved mirrors use the same BVH.
    bool bvh_at_setup = false;
    /// Declined shadow regions take the BVH too once it is built (their segments count
    /// towards its build with the camera's declined rays).
    ShadowFallback shadow_fallback = ShadowFallback::bvh;

    /// Throws rtt::Error for a value out of range.
    void validate() const;
};

/// Largest tile (samples) RTT answers as a shaft; bigger tiles are traced as packets.
inline constexpr int rtt_max_samples_per_tile = 64 * 64;

/// An RTT tracer over `scene` and `tree` (both must outlive it; thread-safe like every tracer).
/// Rays it does not answer from a relevant list, and tiles without a shaft, go to the widest
/// packets of the build. Throws rtt::Error for invalid options.
std::unique_ptr<Tracer> make_rtt_tracer(const Scene& scene, const KdTree& tree,
                                        const RttOptions& options = {});

}  // namespace rtt
