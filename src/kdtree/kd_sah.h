// The SAH split search of the Wald–Havran build: one sweep over each axis's sorted events.
#pragma once

#include "kdtree/kd_events.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

struct SplitChoice {
    int axis = -1;              ///< -1: no split that makes progress exists.
    float pos = 0.f;
    bool planar_left = false;   ///< Side of the triangles lying in the split plane (pside).
    double cost = pos_inf;      ///< SAH cost relative to a ray that hits the node.
    size_t left_count = 0;      ///< Triangles the cost counts in the below child (before
    size_t right_count = 0;     ///< clipping, so at least what the children will hold).
};

/// Cheapest split of the node with bounds `box` and events `ev` (Wald & Havran 2006,
/// Algorithm 4): cost = lambda * (trav + isect * (P_L n_L + P_R n_R)), P = area ratio to the
/// node, lambda = 1 - empty_bonus when one side is empty. Triangles lying in the plane are tried
/// on both sides. A split that would give a child equal to the node (same box, all its
/// triangles) is never returned, so every split makes progress. Compare the result with the
/// leaf cost isect * n.
SplitChoice find_split(const NodeEvents& ev, const Bbox3f& box, const KdBuildConfig& config);

}  // namespace rtt::kd
