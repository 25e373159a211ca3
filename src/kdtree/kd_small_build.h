// The bottom of the kd-tree: nodes of a few dozen triangles, built without event lists.
//
// Most of a kd-tree's nodes hold few triangles; there an event sweep's per-node work (six event
// lists, sorting the straddlers' new events, merging) costs more than the triangles themselves.
// This builder keeps each node's triangles as bounds in one stack-like buffer and counts every
// candidate plane directly, O(n^2) per axis on n <= small_max_triangles, vectorised. It picks
// exactly the plane Wald and Havran's sweep picks (every triangle bound a candidate, the same
// counts, costs and ties).
#pragma once

#include <span>
#include <vector>

#include "geom/triangle.h"
#include "kdtree/kd_events.h"
#include "kdtree/kd_sah.h"
#include "kdtree/kd_subtree.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

/// Nodes with at most this many triangles are built here (docs/benchmarks.md, "kd-tree build").
inline constexpr size_t small_max_triangles = 64;

/// The exact sweep's choice for the node `box` holding `items`, counted directly.
SplitChoice find_small_split(std::span<const TriBox> items, const Bbox3f& box,
                             const KdBuildConfig& config);

class SmallBuilder {
public:
    SmallBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config,
                 int max_depth)
        : triangles_(triangles), config_(config), max_depth_(max_depth) {}

    /// Builds the subtree of the node `box` holding `items` (at most small_max_triangles) at
    /// the end of `out`; `budget` as for the sweep.
    void build(std::span<const TriBox> items, const Bbox3f& box, int depth, double budget,
               Subtree& out) const;

private:
    /// The node's items are the last n of `stack`; they are popped on return.
    void build_top(std::vector<TriBox>& stack, size_t n, const Bbox3f& box, int depth,
                   double budget, Subtree& out) const;

    std::span<const TriangleVerts> triangles_;
    const KdBuildConfig& config_;
    int max_depth_;
};

}  // namespace rtt::kd
