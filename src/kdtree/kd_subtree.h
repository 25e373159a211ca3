// The output of a kd-tree build: nodes and leaf lists of one subtree, with above-child indices
// and leaf offsets relative to the start of its own arrays until it is appended to its parent's.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kdtree/kd_sah.h"
#include "rtt/kd_node.h"

namespace rtt::kd {

[[noreturn]] void too_large(const std::string& what);

struct Subtree {
    std::vector<KdNode> nodes;
    std::vector<uint32_t> leaf_triangles;

    /// Reserves the node of an inner node whose children follow; returns its index.
    size_t begin_inner() {
        nodes.emplace_back();
        return nodes.size() - 1;
    }
    /// Completes the inner node at `index` once its below subtree is in place: the above
    /// child starts at the current end.
    void end_inner(size_t index, const SplitChoice& split);
    /// Adds a leaf holding the triangles appended to leaf_triangles since `first` (sorts them).
    void add_leaf(size_t first);
    /// Appends a subtree built separately (in parallel) and rebases its indices.
    void append(const Subtree& other);
};

/// A node of a subtree placed at `node_base` in the tree, its leaf list at `leaf_base`.
KdNode rebased(KdNode n, size_t node_base, size_t leaf_base);

}  // namespace rtt::kd
