// Which of two exact ways of tracing is faster on this scene, measured while tracing. Declined
// shadow regions have two: the kd-tree's packets behind the blocker cache, faster where the
// segments end in foliage (plants at K = 4), and the BVH's, faster where they leave dense
// meshes (docs/benchmarks.md, "RTT's fallback"). No count predicted which; timing both does.
// Only the speed depends on the choice, never an answer.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

class MeasuredChoice {
public:
    /// Rays timed per way before the choice. Half of every fourth pair of tiles are each way's
    /// probes, spread over the image (a choice from the first few dozen tiles, the image's top,
    /// was wrong on office); the tiles between take the way that leads so far.
    static constexpr uint64_t probe_rays = uint64_t(1) << 18;
    /// A lead of a quarter once both ways have this many rays decides early: on a 900k-triangle
    /// sphere with 279k segments a frame the full probe lasted several frames, a quarter of
    /// them the slow way (docs/benchmarks.md, "RTT's fallback").
    static constexpr uint64_t early_rays = uint64_t(1) << 15;
    static constexpr double clear_lead = 1.25;

    /// The way (0 or 1) for the next tile.
    int pick() {
        const int chosen = chosen_.load(std::memory_order_relaxed);
        if (chosen >= 0) return chosen;
        const uint32_t turn = turn_.fetch_add(1, std::memory_order_relaxed);
        return turn % 4 < 2 ? int(turn & 1u) : leader();
    }

    /// A tile of `rays` traced by `way` in `ns`. Once both ways have probe_rays, the one with
    /// fewer nanoseconds per ray is chosen.
    void record(int way, uint64_t ns, uint64_t rays) {
        if (chosen_.load(std::memory_order_relaxed) >= 0) return;
        ns_[way].fetch_add(ns, std::memory_order_relaxed);
        const uint64_t before = rays_[way].fetch_add(rays, std::memory_order_acq_rel);
        if (lead() >= clear_lead) {
            chosen_.store(leader(), std::memory_order_relaxed);
            return;
        }
        if (before >= probe_rays || before + rays < probe_rays) return;
        // This tile completed `way`'s probe; the second way to complete decides (a record
        // still under way may be left out).
        if (ready_.fetch_add(1, std::memory_order_acq_rel) == 1)
            chosen_.store(leader(), std::memory_order_relaxed);
    }

    /// The way chosen, or -1 while both are still timed.
    int chosen() const { return chosen_.load(std::memory_order_relaxed); }

private:
    /// The slower way's nanoseconds per ray over the faster's, once both have early_rays.
    double lead() const {
        const uint64_t r0 = rays_[0].load(std::memory_order_relaxed);
        const uint64_t r1 = rays_[1].load(std::memory_order_relaxed);
        if (r0 < early_rays || r1 < early_rays) return 1.0;
        const double per_ray0 = double(ns_[0].load(std::memory_order_relaxed)) / double(r0);
        const double per_ray1 = double(ns_[1].load(std::memory_order_relaxed)) / double(r1);
        return std::max(per_ray0, per_ray1) / std::max(std::min(per_ray0, per_ray1), 1e-9);
    }

    /// The way with fewer nanoseconds per ray so far; the first until both have been timed.
    int leader() const {
        const uint64_t r0 = rays_[0].load(std::memory_order_relaxed);
        const uint64_t r1 = rays_[1].load(std::memory_order_relaxed);
        if (r0 == 0 || r1 == 0) return 0;
        const double per_ray0 = double(ns_[0].load(std::memory_order_relaxed)) / double(r0);
        const double per_ray1 = double(ns_[1].load(std::memory_order_relaxed)) / double(r1);
        return per_ray1 < per_ray0 ? 1 : 0;
    }

    std::atomic<int> chosen_{-1};
    std::atomic<uint32_t> turn_{0}, ready_{0};
    std::atomic<uint64_t> ns_[2] = {0, 0}, rays_[2] = {0, 0};
};

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
