// A 4-wide bounding volume hierarchy for arbitrary rays (the "bvh" tracer, trace_bvh.cpp):
// binned-SAH binary tree collapsed to four children per node. Each triangle is listed once, in
// one leaf; node boxes are the exact bounds of what is under them. docs/design.md, "The BVH for
// arbitrary rays", says why the traversal's box margins keep it exact.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geom/triangle.h"
#include "rtt/math.h"

namespace rtt {

/// Four children's boxes, structure of arrays for one SIMD test. An inner child is a node
/// index; a leaf child has bit 31 set, its first block in bits 3-30 and its block count in 0-2.
struct alignas(64) Bvh4Node {
    float lo[3][4], hi[3][4];
    uint32_t child[4];
    uint32_t count = 0;  ///< Children in use: slots 0..count-1.
};

/// Four triangles of a leaf, structure of arrays for one SIMD watertight test; unused lanes
/// have the id invalid_triangle.
struct alignas(64) BvhTriangles4 {
    float v0[3][4], v1[3][4], v2[3][4];
    uint32_t id[4];
};

inline constexpr uint32_t bvh_leaf_bit = 0x80000000u;
inline constexpr uint32_t bvh_leaf_max = 16;             ///< Triangles per leaf, at most.
inline constexpr uint32_t bvh_max_triangles = 1u << 27;  ///< What a leaf child can address.
/// Depth of the binary tree at most (SAH to depth 64, halves below): 64 + log2(2^27).
inline constexpr int bvh_max_depth = 64 + 27;

struct Bvh4 {
    std::vector<Bvh4Node> nodes;        ///< nodes[0] is the root (when not empty).
    std::vector<BvhTriangles4> blocks;  ///< The leaves' triangles, in leaf order.
    /// Of every triangle, padded as trace_ray pads the kd-tree's (the rays' split-margin scale).
    Bbox3f padded_bounds;
};

/// Builds the hierarchy over `triangles` (binned SAH, deterministic). Throws rtt::Error beyond
/// bvh_max_triangles.
Bvh4 build_bvh4(std::span<const TriangleVerts> triangles);

}  // namespace rtt
