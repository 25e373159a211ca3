// Shadow segments as large any-hit packets from the light (issue 30, item 3): the segments of
// up to simd_max_width blocks of a tile (16x16 points at AVX-512) share the light as origin and
// traverse the kd-tree once, each block carried by one lane of a vector of frusta; leaves test
// their triangles against the blocks still open, 16 (8, 4) segments per watertight test.
//
// Exactness (docs/design.md, "The shadow frustum"): a node is left out for a block only when
// the node's cell, grown by far more than trace_ray's split margins, lies outside one of the
// block's bounding planes (its segments' slopes along the chunk's dominant axis, widened past
// their rounding) or beyond its farthest end; so the block reaches every leaf trace_ray can
// find a blocker of one of its segments in, and tests each open segment against every
// triangle there with the one watertight test. A blocker found anywhere is a blocker
// trace_ray finds (it equals brute force on a valid tree), so the answers are occluded_ray's.
#pragma once

#include <cstdint>
#include <span>

#include "geom/triangle.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Visibility of a shadow tile's active segments (shadow_ray(tile.light, point)):
/// visible[i] = 1 when unoccluded, 0 when occluded or inactive, exactly as
/// occluded_tile_packets. Parts of the tile whose segments no frustum bounds (segments more
/// than 76 degrees off their dominant axis, zero-length ones) go to the widest packets.
/// Returns the number of active segments.
uint64_t occluded_frustum(const KdTree& tree, std::span<const TriangleVerts> triangles,
                          const SegmentTile& tile, std::span<uint8_t> visible);

}  // namespace RTT_ISA_NS
}  // namespace rtt
