// How intersect_rays and visible_rays (rtt/tracer.h) split a batch of arbitrary rays: chunks in
// parallel, in the order of ray_order.h where it pays. Here for the tests, which force each way.
#pragma once

#include <cstdint>
#include <span>

#include "rtt/tracer.h"

namespace rtt {

/// An any-hit batch (visible_rays) is traced in coherent_order only when its rays wait on
/// memory: a few chunks of it, traced as given and at once again, took at least this many times
/// as long the first time as the second, when their nodes were in cache. Any-hit rays end at
/// their first blocker, so on most scenes the order's gathering costs more than it saves
/// (docs/benchmarks.md, "Arbitrary rays", has the measurements behind the figure).
inline constexpr double order_any_hit_above = 2.6;

/// visible_rays with the probe's threshold as a parameter: 0 orders every batch the order
/// accepts after the probe, infinity none. The answers are the same either way.
void visible_rays_probed(const Tracer& tracer, std::span<const Ray> rays,
                         std::span<uint8_t> visible, TraceStats* stats, double order_above);

}  // namespace rtt
