// The kd-tree build: binned SAH from the root down over all cores, the exact Wald–Havran sweep
// with perfect splits below (Shevtsov, Soupikov and Kapustin 2007; Wald and Havran 2006).
//
// A node of more than sweep_min_triangles triangles holds its triangles with the bounds of
// their part inside it (kd::TriBox) and picks its plane among kd::binned_planes per axis
// (kd_binned_sah.cpp): one parallel pass, no sorted event lists to keep up. Its triangles are
// split in parallel, straddlers clipped to each child (perfect splits, as below). Smaller
// nodes are handed to the sweep (kd_sweep_build.cpp), which sorts their events once and
// places its planes exactly; so does a top node whose planes find no split worth taking,
// since the sweep may still find one the bins miss, or makes the leaf.
//
// The tree does not depend on the thread count: bins hold integer counts, the sweep sorts its
// events in a total order, leaf lists are sorted, and subtrees are concatenated in one fixed
// order (below child first).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "geom/triangle.h"
#include "kdtree/kd_binned_sah.h"
#include "kdtree/kd_clip.h"
#include "kdtree/kd_events.h"
#include "kdtree/kd_sah.h"
#include "kdtree/kd_subtree.h"
#include "kdtree/kd_sweep_build.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "rtt/memory_budget.h"

namespace rtt {
namespace {

using kd::SplitChoice;
using kd::Subtree;
using kd::TriBox;

/// Leaf references the whole tree may hold, per triangle. The SAH alone does not bound them:
/// n thin triangles along x crossing n along y in one plane make every split cut through one
/// family, and the SAH keeps splitting down to the depth limit; 2 x 2000 such triangles gave
/// 11.7 million references and 15.5 million nodes (O(n^2) cells). Ordinary scenes hold 2 to 6
/// references per triangle in total; a node only splits if its children's references fit its
/// share of this budget (tests/limits_test.cpp).
constexpr double reference_budget = 32.0;

/// Nodes with more triangles split on binned planes. Below, the sweep's exact planes are worth
/// their cost: the SAH cost of the tree stays within 1 % of an all-sweep build
/// (docs/benchmarks.md, "kd-tree build").
constexpr size_t sweep_min_triangles = 8192;

/// Triangles per task when a top node bins or splits its triangles.
constexpr size_t grain = 4096;

/// The binned top levels: inner nodes down to the subtrees the sweep builds.
struct TopNode {
    SplitChoice split;  ///< axis < 0: a sweep subtree
    std::unique_ptr<TopNode> below, above;
    // A sweep subtree: its node's box and triangles, then the subtree built from them.
    std::vector<TriBox> items;
    Bbox3f box;
    int depth = 0;
    double budget = 0;
    Subtree built;
};

class TopBuilder {
public:
    TopBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config, int max_depth)
        : triangles_(triangles), config_(config), max_depth_(max_depth) {}

    /// The top levels over the node `box` holding `items` (consumed), in parallel.
    std::unique_ptr<TopNode> build(std::vector<TriBox>&& items, const Bbox3f& box, int depth,
                                   double budget) const {
        auto node = std::make_unique<TopNode>();
        const size_t n = items.size();
        if (n > sweep_min_triangles && n > size_t(config_.max_leaf_size) && depth < max_depth_)
            node->split = kd::find_binned_split(items, box, config_);
        // Without a split worth taking the sweep decides: it may find a plane the bins miss.
        if (!kd::takes_split(node->split, n, budget, config_)) {
            node->split = {};
            node->items = std::move(items);
            node->box = box;
            node->depth = depth;
            node->budget = budget;
            return node;
        }
        const SplitChoice& split = node->split;
        Bbox3f left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        std::vector<TriBox> left, right;
        partition(items, split, left_box, right_box, left, right);
        std::vector<TriBox>().swap(items);  // release now, not when the children return
        tbb::parallel_invoke(
            [&] {
                node->below = build(std::move(left), left_box, depth + 1,
                                    kd::child_budget(budget, split, true));
            },
            [&] {
                node->above = build(std::move(right), right_box, depth + 1,
                                    kd::child_budget(budget, split, false));
            });
        return node;
    }

private:
    /// The children's triangles, with the sweep's rule (kd_sweep_build.cpp): a triangle that
    /// only touches the plane goes to the side it lies on, one lying in it to the side the SAH
    /// picked, and one crossing it is clipped to each child (perfect splits).
    void partition(const std::vector<TriBox>& items, const SplitChoice& split,
                   const Bbox3f& left_box, const Bbox3f& right_box, std::vector<TriBox>& left,
                   std::vector<TriBox>& right) const {
        const int a = split.axis;
        const float p = split.pos;
        const size_t chunks = (items.size() + grain - 1) / grain;
        std::vector<std::vector<TriBox>> lefts(chunks), rights(chunks);
        tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
            std::vector<TriBox>&l = lefts[c], &r = rights[c];
            Bbox3f b;
            for (size_t i = c * grain; i < std::min(items.size(), (c + 1) * grain); ++i) {
                const TriBox& t = items[i];
                const float lo = t.box.lo[a], hi = t.box.hi[a];
                if (lo == hi) {
                    (lo < p || (lo == p && split.planar_left) ? l : r).push_back(t);
                } else if (hi <= p) {
                    l.push_back(t);
                } else if (lo >= p) {
                    r.push_back(t);
                } else {
                    if (clip_triangle_to_box(triangles_[t.tri], left_box, b)) l.push_back({b, t.tri});
                    if (clip_triangle_to_box(triangles_[t.tri], right_box, b)) r.push_back({b, t.tri});
                }
            }
        });
        concatenate(lefts, left);
        concatenate(rights, right);
    }

    static void concatenate(const std::vector<std::vector<TriBox>>& parts, std::vector<TriBox>& all) {
        size_t total = 0;
        for (const auto& part : parts) total += part.size();
        all.reserve(total);
        for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
    }

    std::span<const TriangleVerts> triangles_;
    const KdBuildConfig& config_;
    int max_depth_;
};

/// The sweep subtrees under `node`, below child first.
void collect_subtrees(TopNode& node, std::vector<TopNode*>& out) {
    if (node.split.axis < 0) {
        out.push_back(&node);
        return;
    }
    collect_subtrees(*node.below, out);
    collect_subtrees(*node.above, out);
}

/// Lays the tree out in one array in depth-first order, below child first: the top's inner
/// nodes at their places, each sweep subtree copied once (in parallel) and rebased.
void lay_out(TopNode& root, KdTree& tree) {
    struct Placed {
        Subtree* subtree;
        size_t node_base, leaf_base;
    };
    std::vector<Placed> placed;
    std::vector<std::pair<size_t, KdNode>> inner;  // the top's inner nodes and their places
    size_t nodes = 0, refs = 0;
    const auto place = [&](const auto& self, TopNode& node) -> void {
        if (node.split.axis < 0) {
            placed.push_back({&node.built, nodes, refs});
            nodes += node.built.nodes.size();
            refs += node.built.leaf_triangles.size();
            return;
        }
        const size_t index = nodes++;
        self(self, *node.below);
        KdNode n;
        if (nodes > KdNode::max_index || !n.set_inner(node.split.axis, node.split.pos, uint32_t(nodes)))
            kd::too_large("more than 2^30 nodes");
        inner.emplace_back(index, n);
        self(self, *node.above);
    };
    place(place, root);
    if (nodes > KdNode::max_index) kd::too_large("more than 2^30 nodes");
    if (refs > UINT32_MAX) kd::too_large("more than 2^32 leaf references");

    tree.nodes.resize(nodes);
    tree.leaf_triangles.resize(refs);
    for (const auto& [index, n] : inner) tree.nodes[index] = n;
    tbb::parallel_for(size_t(0), placed.size(), [&](size_t i) {
        const Placed& p = placed[i];
        std::transform(p.subtree->nodes.begin(), p.subtree->nodes.end(),
                       tree.nodes.begin() + std::ptrdiff_t(p.node_base),
                       [&](KdNode n) { return kd::rebased(n, p.node_base, p.leaf_base); });
        std::copy(p.subtree->leaf_triangles.begin(), p.subtree->leaf_triangles.end(),
                  tree.leaf_triangles.begin() + std::ptrdiff_t(p.leaf_base));
        *p.subtree = Subtree{};
    });
}

/// Checks what the build relies on (indices in range, finite coordinates, index fits 30 bits).
void check_input(const Scene& scene) {
    if (scene.triangles.size() > kd::Event::tri_mask)
        kd::too_large(std::to_string(scene.triangles.size()) + " triangles, at most 2^30 - 1");
    require_memory(scene_memory_bytes(scene.vertices.size(), scene.triangles.size()),
                   "a kd-tree over " + std::to_string(scene.triangles.size()) + " triangles");
    for (size_t i = 0; i < scene.triangles.size(); ++i)
        for (uint32_t v : scene.triangles[i]) {
            if (v >= scene.vertices.size())
                throw Error("kd-tree: triangle " + std::to_string(i) + " uses vertex " +
                            std::to_string(v) + " but there are " +
                            std::to_string(scene.vertices.size()));
            if (!is_finite(scene.vertices[v]))
                throw Error("kd-tree: triangle " + std::to_string(i) +
                            " has a NaN or infinite coordinate");
        }
}

int auto_max_depth(size_t n) {
    const double d = 8.0 + 1.3 * std::log2(double(std::max<size_t>(n, 1)));
    return std::min(kd_max_depth, int(d));
}

}  // namespace

KdTree build_kdtree(const Scene& scene, const KdBuildConfig& config) {
    config.validate();
    check_input(scene);
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const std::vector<TriangleVerts> triangles = gather_triangles(scene);
    const size_t n = triangles.size();

    KdTree tree;
    std::vector<TriBox> items(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) items[i] = {triangle_bounds(triangles[i]), uint32_t(i)};
    });
    for (const TriBox& t : items) tree.bounds.extend(t.box);
    const auto setup_done = Clock::now();

    const int max_depth = config.max_depth > 0 ? config.max_depth : auto_max_depth(n);
    const std::unique_ptr<TopNode> top = TopBuilder(triangles, config, max_depth)
                                             .build(std::move(items), tree.bounds, 0,
                                                    reference_budget * double(n));
    std::vector<TopNode*> subtrees;
    collect_subtrees(*top, subtrees);
    const auto top_done = Clock::now();

    // Largest first, so that no big subtree starts last (most hold at most sweep_min_triangles;
    // a big one is a node the bins found no split for).
    std::stable_sort(subtrees.begin(), subtrees.end(), [](const TopNode* a, const TopNode* b) {
        return a->items.size() > b->items.size();
    });
    kd::SweepBuilder sweep(triangles, config, max_depth);
    tbb::parallel_for(
        size_t(0), subtrees.size(),
        [&](size_t i) {
            TopNode& t = *subtrees[i];
            sweep.build(t.items, t.box, t.depth, t.budget, t.built);
            std::vector<TriBox>().swap(t.items);
        },
        tbb::simple_partitioner());
    const auto sweep_done = Clock::now();

    lay_out(*top, tree);
    const auto end = Clock::now();
    const double seconds = std::chrono::duration<double>(end - start).count();

    tree.stats = compute_stats(tree, config);
    tree.stats.triangles = n;
    tree.stats.build_seconds = seconds;
    tree.stats.setup_seconds = std::chrono::duration<double>(setup_done - start).count();
    tree.stats.top_seconds = std::chrono::duration<double>(top_done - setup_done).count();
    tree.stats.sweep_seconds = std::chrono::duration<double>(sweep_done - top_done).count();
    tree.stats.layout_seconds = std::chrono::duration<double>(end - sweep_done).count();
    tree.stats.top_nodes = subtrees.size() - 1;  // a binary tree's inner nodes
    tree.stats.sweep_subtrees = subtrees.size();
    return tree;
}

}  // namespace rtt
