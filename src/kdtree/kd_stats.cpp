// Structural statistics of a kd-tree, for `rtt info`, the benchmarks and the tests.
#include <algorithm>
#include <vector>

#include "rtt/kdtree.h"

namespace rtt {

KdStats compute_stats(const KdTree& tree, const KdBuildConfig& config) {
    KdStats s;
    s.nodes = tree.nodes.size();
    s.memory_bytes =
        tree.nodes.size() * sizeof(KdNode) + tree.leaf_triangles.size() * sizeof(uint32_t);
    if (tree.nodes.empty()) return s;

    // SAH cost: the probability that a random ray meeting the root also meets a node is the
    // ratio of their surface areas (half areas here; only ratios matter). A root without area
    // (all triangles on one segment or point) counts every node as always visited.
    const double root_area = tree.bounds.half_area();
    const auto probability = [&](const Bbox3f& b) {
        return root_area > 0.0 ? double(b.half_area()) / root_area : 1.0;
    };

    struct Item {
        uint32_t node;
        int depth;
        Bbox3f box;
    };
    std::vector<Item> stack{{0, 0, tree.bounds}};
    size_t leaf_depth_sum = 0, nonempty = 0;
    uint32_t max_tri = 0;
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const KdNode& n = tree.nodes[it.node];
        if (n.is_leaf()) {
            const uint32_t count = n.triangle_count();
            ++s.leaves;
            s.empty_leaves += count == 0;
            nonempty += count != 0;
            s.triangle_references += count;
            s.max_depth = std::max(s.max_depth, it.depth);
            leaf_depth_sum += size_t(it.depth);
            s.sah_cost += double(config.isect_cost) * count * probability(it.box);
            for (uint32_t k = 0; k < count; ++k)
                max_tri = std::max(max_tri, tree.leaf_triangles[n.first_triangle() + k] + 1);
            continue;
        }
        s.sah_cost += double(config.trav_cost) * probability(it.box);
        Bbox3f below = it.box, above = it.box;
        below.hi[n.axis()] = n.split;
        above.lo[n.axis()] = n.split;
        stack.push_back({n.above_child(), it.depth + 1, above});
        stack.push_back({it.node + 1, it.depth + 1, below});
    }
    s.avg_leaf_depth = s.leaves ? double(leaf_depth_sum) / double(s.leaves) : 0.0;
    s.avg_leaf_triangles = nonempty ? double(s.triangle_references) / double(nonempty) : 0.0;
    // Every triangle is referenced by some leaf, so the largest index tells the count.
    s.triangles = max_tri;
    return s;
}

}  // namespace rtt
