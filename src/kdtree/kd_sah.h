// The SAH cost of kd-tree splits and the rules for taking one (kd_binned_sah.cpp and
// kd_small_build.cpp search the planes). A split that would give a child equal to the node
// (same box, all its triangles) costs infinity, so every split taken makes progress.
#pragma once

#include <span>

#include "kdtree/kd_events.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

struct SplitChoice {
    int axis = -1;  ///< -1: no split that makes progress exists.
    float pos = 0.f;
    bool planar_left = false;  ///< Side of the triangles lying in the split plane (pside).
    double cost = pos_inf;     ///< SAH cost relative to a ray that hits the node.
    size_t left_count = 0;     ///< Triangles the cost counts in the below child (before
    size_t right_count = 0;    ///< clipping, so at least what the children will hold).
};

/// SAH cost of the splits of one node along one axis: lambda * (trav + isect * (P_L n_L +
/// P_R n_R)), P = area ratio to the node, lambda = 1 - empty_bonus when one side is empty.
class AxisCost {
public:
    AxisCost(int axis, const Bbox3f& box, size_t triangles, const KdBuildConfig& config)
        : n_(triangles),
          trav_(config.trav_cost),
          isect_(config.isect_cost),
          bonus_factor_(1.0 - double(config.empty_bonus)),
          lo_(box.lo[axis]),
          hi_(box.hi[axis]) {
        const Vec3f diag = box.diagonal();
        area_ = double(diag.x) * diag.y + double(diag.y) * diag.z + double(diag.z) * diag.x;
        inv_area_ = 1.0 / area_;
        // Half area of a child of extent w along the axis: w * (d1 + d2) + d1 * d2.
        const double d1 = diag[(axis + 1) % 3], d2 = diag[(axis + 2) % 3];
        cap_ = d1 * d2;
        perimeter_ = d1 + d2;
    }

    /// A box that is a segment or a point holds only degenerate triangles no ray can tell
    /// apart; and area ratios are undefined there: no split.
    bool has_area() const { return area_ > 0.0; }

    /// Cost of the split at p with cl triangles below and cr above; infinite when the split
    /// would make no progress.
    double operator()(float p, size_t cl, size_t cr) const {
        // A split at the node's face leaves the other child equal to the node; it is progress
        // only if that child loses triangles (a flat cell took them).
        if ((double(p) == hi_ && cl == n_) || (double(p) == lo_ && cr == n_)) return pos_inf;
        const double pl = (cap_ + (double(p) - lo_) * perimeter_) * inv_area_;
        const double pr = (cap_ + (hi_ - double(p)) * perimeter_) * inv_area_;
        double cost = trav_ + isect_ * (pl * double(cl) + pr * double(cr));
        if (cl == 0 || cr == 0) cost *= bonus_factor_;
        return cost;
    }

private:
    size_t n_;
    double trav_, isect_, bonus_factor_, lo_, hi_;
    double area_, inv_area_, cap_, perimeter_;
};

/// The better of two choices, ties to `a` (the lower axis).
inline const SplitChoice& better(const SplitChoice& a, const SplitChoice& b) {
    return b.cost < a.cost ? b : a;
}

/// Whether the node splits: the split exists, is cheaper than a leaf, and its children's
/// references fit the node's share `budget` of the reference budget (kd_build.cpp).
inline bool takes_split(const SplitChoice& split, size_t triangles, double budget,
                        const KdBuildConfig& config) {
    const double children = double(split.left_count) + double(split.right_count);
    return split.axis >= 0 && split.cost < double(config.isect_cost) * double(triangles) &&
           children <= budget;
}

/// Each child's share of the budget follows its share of the references, so every node keeps
/// budget >= its triangle count and the leaves hold at most the root's budget.
inline double child_budget(double budget, const SplitChoice& split, bool left) {
    const double children = double(split.left_count) + double(split.right_count);
    return budget * double(left ? split.left_count : split.right_count) / children;
}

}  // namespace rtt::kd
