// Bounding volume hierarchies for arbitrary rays (the "bvh" and "bvh-high" tracers,
// trace_bvh.cpp): binned SAH, W children per node (4 for SSE kernels, 8 for AVX2, 16 for AVX-512).
// Without spatial splits each triangle is listed once, in one leaf, and node boxes are the exact
// bounds of what is under them; with them a triangle may be listed in several leaves, each copy's
// box holding its part of the triangle (rounded outward). docs/design.md, "The BVH for arbitrary
// rays", says why the traversal's box margins keep it exact either way.
#pragma once

#include <concepts>
#include <cstdint>
#include <span>
#include <vector>

#include "core/large_arrays.h"
#include "geom/triangle.h"
#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

/// W children's boxes, structure of arrays for one SIMD test. An inner child is a node index; a
/// leaf child has bit 31 set, its first block in bits 3-30 and its block count in 0-2.
template <int W>
struct alignas(64) BvhNode {
    float lo[3][W], hi[3][W];
    uint32_t child[W];
    uint32_t count = 0;  ///< Children in use: slots 0..count-1.
};

/// Four triangles of a leaf, structure of arrays for one SIMD watertight test; unused lanes
/// have the id invalid_triangle. 160 bytes, not padded to whole cache lines (192): the first
/// image pays about a millisecond per MB of fresh memory, and traversal ran as fast
/// (docs/benchmarks.md, "Arbitrary rays").
struct alignas(16) BvhTriangles4 {
    float v0[3][4], v1[3][4], v2[3][4];
    uint32_t id[4];
};

inline constexpr uint32_t bvh_leaf_bit = 0x80000000u;
inline constexpr uint32_t bvh_leaf_max = 16;             ///< Triangles per leaf, at most.
inline constexpr uint32_t bvh_max_triangles = 1u << 27;  ///< What a leaf child can address.
/// Binary splits on a path at most (SAH to depth 64, halves below): 64 + log2(2^27).
inline constexpr int bvh_max_depth = 64 + 27;

template <int W>
struct Bvh {
    large_vector<BvhNode<W>> nodes;      ///< nodes[0] is the root (when not empty).
    large_vector<BvhTriangles4> blocks;  ///< The leaves' triangles, in leaf order.
    /// Of every triangle, padded as trace_ray pads the kd-tree's (the rays' split-margin scale).
    Bbox3f padded_bounds;
};
using Bvh4 = Bvh<4>;
using Bvh8 = Bvh<8>;

struct BvhBuildOptions {
    /// Spatial splits (Stich, Friedrich and Dietrich 2009) where a node's children would overlap,
    /// with room for copies of up to this fraction of the triangles; 0: object splits only.
    float spatial_split_budget = 0.f;
};
/// The "bvh-high" tracer's build: a quarter's room (the splits take 6-8 % on the built-in
/// scenes; docs/benchmarks.md, "Arbitrary rays").
inline constexpr BvhBuildOptions bvh_high_quality{0.25f};

/// The triangles a BVH is built over: vertex triples, or a scene's vertices and index triples
/// read in place (a copy of 900k triangles' triples cost the first image 50 ms of fresh memory;
/// docs/benchmarks.md, "First image").
class BuildTriangles {
public:
    /// Any contiguous array of triples (TriangleArray, std::vector, span).
    template <typename Triples>
    requires std::convertible_to<const Triples&, std::span<const TriangleVerts>> BuildTriangles(
        const Triples& triples)
        : triples_(triples) {}
    explicit BuildTriangles(const Scene& scene)
        : vertices_(scene.vertices), indices_(scene.triangles), indexed_(true) {}

    size_t size() const { return indexed_ ? indices_.size() : triples_.size(); }
    bool empty() const { return size() == 0; }
    TriangleVerts operator[](size_t i) const {
        if (!indexed_) return triples_[i];
        const TriangleIndices& t = indices_[i];
        return {vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]};
    }

private:
    std::span<const TriangleVerts> triples_;
    std::span<const Vec3f> vertices_;
    std::span<const TriangleIndices> indices_;
    bool indexed_ = false;
};

/// Builds the hierarchy over `triangles` (binned SAH) on the calling thread's oneTBB arena; the
/// result does not depend on the number of threads. Throws rtt::Error beyond bvh_max_triangles.
template <int W>
Bvh<W> build_bvh(const BuildTriangles& triangles, const BvhBuildOptions& options = {});

}  // namespace rtt
