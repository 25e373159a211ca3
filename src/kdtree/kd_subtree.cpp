#include "kdtree/kd_subtree.h"

#include <algorithm>

#include "rtt/error.h"

namespace rtt::kd {

void too_large(const std::string& what) {
    throw Error("scene too large for the kd-tree: " + what);
}

void Subtree::end_inner(size_t index, const SplitChoice& split) {
    const size_t above = nodes.size();
    if (above > KdNode::max_index ||
        !nodes[index].set_inner(split.axis, split.pos, uint32_t(above)))
        too_large("more than 2^30 nodes");
}

void Subtree::add_leaf(size_t first) {
    if (leaf_triangles.size() > UINT32_MAX) too_large("more than 2^32 leaf references");
    std::sort(leaf_triangles.begin() + std::ptrdiff_t(first), leaf_triangles.end());
    KdNode leaf;
    if (!leaf.set_leaf(uint32_t(first), uint32_t(leaf_triangles.size() - first)))
        too_large("a leaf with more than 2^30 triangles");
    nodes.push_back(leaf);
}

KdNode rebased(KdNode n, size_t node_base, size_t leaf_base) {
    const bool ok =
        n.is_leaf() ? n.first_triangle() + leaf_base <= UINT32_MAX &&
                          n.set_leaf(n.first_triangle() + uint32_t(leaf_base), n.triangle_count())
                    : node_base <= KdNode::max_index &&
                          n.set_inner(n.axis(), n.split, n.above_child() + uint32_t(node_base));
    if (!ok) too_large("node index out of range");
    return n;
}

void Subtree::append(const Subtree& other) {
    const size_t node_base = nodes.size(), leaf_base = leaf_triangles.size();
    if (node_base + other.nodes.size() > KdNode::max_index) too_large("more than 2^30 nodes");
    if (leaf_base + other.leaf_triangles.size() > UINT32_MAX)
        too_large("more than 2^32 leaf references");
    nodes.reserve(node_base + other.nodes.size());
    for (KdNode n : other.nodes) nodes.push_back(rebased(n, node_base, leaf_base));
    leaf_triangles.insert(leaf_triangles.end(), other.leaf_triangles.begin(),
                          other.leaf_triangles.end());
}

}  // namespace rtt::kd
