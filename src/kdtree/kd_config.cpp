#include <cmath>
#include <string>

#include "rtt/error.h"
#include "rtt/kdtree.h"

namespace rtt {

void KdBuildConfig::validate() const {
    // Both costs must be positive: with a free traversal step a split that changes nothing
    // could look as cheap as a leaf, and the build would only stop at the depth limit.
    if (!(std::isfinite(isect_cost) && isect_cost > 0.f))
        throw Error("kd-tree: intersection cost must be a positive number, got " +
                    std::to_string(isect_cost));
    if (!(std::isfinite(trav_cost) && trav_cost > 0.f))
        throw Error("kd-tree: traversal cost must be a positive number, got " +
                    std::to_string(trav_cost));
    if (!(empty_bonus >= 0.f && empty_bonus < 1.f))
        throw Error("kd-tree: empty-space bonus must be in [0, 1), got " +
                    std::to_string(empty_bonus));
    if (max_depth < 0 || max_depth > kd_max_depth)
        throw Error("kd-tree: maximum depth must be in 0.." + std::to_string(kd_max_depth) +
                    " (0 = automatic), got " + std::to_string(max_depth));
    if (max_leaf_size < 0)
        throw Error("kd-tree: maximum leaf size must not be negative, got " +
                    std::to_string(max_leaf_size));
}

}  // namespace rtt
