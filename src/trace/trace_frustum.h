// Large-packet ("frustum") tracing through the kd-tree: all rays of a region that share one
// origin (a pinhole tile of 16x16 .. 64x64 samples) traverse the tree as ONE packet, one
// direction octant at a time, with scalar work per inner node and SIMD work only at leaves.
//
// Exactness (docs/design.md, "The frustum tracer"): for each ray, trace_ray's node interval
// [ta, tb] at every node lies inside the packet's scalar interval [TA, TB], because the split
// distance d = (split - org) * inv of every ray is bounded by the products with the packet's
// smallest and largest inverse direction (float multiplication is monotone), and so are the
// margins. The packet therefore enters every child some ray enters; at a leaf each ray's own
// interval is re-derived from the leaf's faces (a superset of trace_ray's), and the ray is
// tested, with the one watertight test, unless that interval is empty or starts after its
// closest hit so far. Each ray thus tests every leaf trace_ray can find its answer in, and
// the closest (t, index) over a superset is the same answer.
#pragma once

#include <span>

#include "geom/triangle.h"
#include "rtt/kdtree.h"
#include "rtt/math.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Closest hit of every ray of a `width` x `height` grid (row-major; the grid only groups
/// neighbours into SIMD blocks): hits[i] == trace_ray(tree, triangles, rays[i]). Returns false,
/// touching nothing, when some ray's origin differs from rays[0]'s (bit for bit).
bool trace_frustum(const KdTree& tree, std::span<const TriangleVerts> triangles,
                   std::span<const Ray> rays, int width, int height, std::span<Hit> hits);

}  // namespace RTT_ISA_NS
}  // namespace rtt
