// RTT with typed options: what make_tracer("rtt") and make_tracer("rtt-paper") build, with
// every knob of the method named. No option changes an answer: they decide how much work RTT
// tries before tracing a tile with packets, never whether an answer is exact (docs/design.md,
// "RTT exactness").
#pragma once

#include <cstdint>
#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

/// Which procedure answers a shaft tile.
enum class RttRules : uint8_t {
    /// "rtt": corners and relevant list from one front-to-back walk of the shaft, primary tiles
    /// answered when the corners hit one plane (several planes from 8x8 samples on).
    extended,
    /// "rtt-paper": the paper's corner packet and rules, coherent corners on one triangle.
    paper,
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
