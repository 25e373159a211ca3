// The order in which a large batch of arbitrary rays is traced (ray_batches.cpp): rays that
// start close together and head the same way go together, so they find the tree's nodes and
// leaf blocks in cache (ray reordering, as in Pharr et al. 1997 and Moon et al. 2010;
// docs/benchmarks.md, "Arbitrary rays", has what it saves).
#pragma once

#include <cstdint>
#include <span>

#include "core/large_arrays.h"
#include "rtt/math.h"

namespace rtt {

/// Batches smaller than this are traced in the caller's order: their rays are too far apart
/// for the order to share anything, and the sort would cost more than it saves.
inline constexpr size_t reorder_min_rays = 16384;

/// Positions of `rays` in tracing order: by direction octant, then by the origin's cell along
/// a Morton curve over the origins' bounds (about four rays per cell and octant); rays of one
/// cell and octant keep the caller's order. Empty (trace them as they come) when
/// rays.size() < reorder_min_rays (or beyond 32-bit positions) or when most neighbours in the array
/// already start in one cell. The rays' origins must be finite. The same for any number of threads.
large_vector<uint32_t> coherent_order(std::span<const Ray> rays);

}  // namespace rtt
