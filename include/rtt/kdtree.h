// SAH kd-tree over the scene's triangles (Wald & Havran 2006, O(N log N), perfect splits).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rtt/kd_node.h"
#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

struct KdBuildConfig {
    /// Cost of one ray/triangle test relative to one traversal step. Default 0.25, measured for
    /// the 16-wide packets and RTT that trace most rays (docs/benchmarks.md, "SAH constants");
    /// Havran's 1.5 suits single rays.
    float isect_cost = 0.25f;
    /// Cost of one traversal step. Default 1.
    float trav_cost = 1.f;
    /// Fraction of the cost saved when a split cuts off empty space. Default 0.2.
    float empty_bonus = 0.2f;
    /// Maximum depth; 0 = automatic, 8 + 1.3 log2(N), capped at 64.
    int max_depth = 0;
    /// Nodes with at most this many triangles become leaves. Default 1.
    int max_leaf_size = 1;

    /// Throws rtt::Error when a value is outside its meaningful range.
    void validate() const;
};

/// Maximum depth any tree may have; traversal stacks are sized by it.
inline constexpr int kd_max_depth = 64;

struct KdStats {
    size_t triangles = 0;
    size_t nodes = 0;
    size_t leaves = 0;
    size_t empty_leaves = 0;
    int max_depth = 0;
    double avg_leaf_depth = 0;       ///< Average depth over all leaves.
    double avg_leaf_triangles = 0;   ///< Average triangle count over non-empty leaves.
    size_t triangle_references = 0;  ///< Sum of leaf triangle counts.
    double sah_cost = 0;             ///< Expected cost of a random ray, by the SAH.
    double build_seconds = 0;
    /// Phases of the build, wall seconds: the triangles and their bounds, the tree (binned
    /// levels and the small subtrees below them), and laying the nodes out in one array.
    double setup_seconds = 0, tree_seconds = 0, layout_seconds = 0;
    size_t binned_nodes = 0;    ///< Inner nodes split on binned (and refined) planes.
    size_t small_subtrees = 0;  ///< Subtrees below them (small nodes' subtrees and leaves).
    size_t memory_bytes = 0;    ///< Nodes plus leaf triangle lists.
};

struct KdTree {
    std::vector<KdNode> nodes;  ///< nodes[0] is the root.
    std::vector<uint32_t> leaf_triangles;
    Bbox3f bounds;  ///< Bounds of all triangles.
    KdStats stats;
};

/// Builds the tree. Degenerate (zero-area) triangles are kept: they can still be hit edge-on
/// by the watertight test, so they must stay findable. Throws rtt::Error on bad config.
KdTree build_kdtree(const Scene& scene, const KdBuildConfig& config = {});

/// Recomputes the structural statistics of a tree (everything but build time).
KdStats compute_stats(const KdTree& tree, const KdBuildConfig& config);

}  // namespace rtt
