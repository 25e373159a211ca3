// The exact part of the kd-tree build: Wald & Havran's event sweep with perfect splits
// (kd_sweep_build.cpp), for the subtrees below the binned top levels.
#pragma once

#include <memory>
#include <span>

#include "geom/triangle.h"
#include "kdtree/kd_events.h"
#include "kdtree/kd_subtree.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

/// One for the whole build: its per-thread working memory is reused from subtree to subtree.
class SweepBuilder {
public:
    SweepBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config,
                 int max_depth);
    ~SweepBuilder();

    /// Builds the subtree of the node with box `box` holding `items` at the end of `out`;
    /// `budget` is the number of leaf references the subtree may hold (kd_build.cpp).
    void build(std::span<const TriBox> items, const Bbox3f& box, int depth, double budget,
               Subtree& out);

private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rtt::kd
