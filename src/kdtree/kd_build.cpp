// The kd-tree build: binned SAH from the root down over all cores, refined to exact planes
// near the best bin, with perfect splits (Shevtsov, Soupikov and Kapustin 2007; Wald and Havran
// 2006), and the small nodes' exact search below (kd_small_build.cpp).
//
// A node of more than small_max_triangles triangles holds its triangles with the bounds of their
// part inside it (kd::TriBox) and picks its plane with kd::find_binned_split: one counting pass,
// no sorted event lists to keep from node to node. Its triangles are split in parallel,
// straddlers clipped to each child (perfect splits). A small node builds its whole subtree at
// once with kd::SmallBuilder, which picks exactly the sweep's planes.
//
// The tree does not depend on the thread count: bins hold integer counts, every choice is made
// from the node's own triangles whatever their order, leaf lists are sorted, and subtrees are
// concatenated in one fixed order (below child first).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
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
#include "kdtree/kd_small_build.h"
#include "kdtree/kd_subtree.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "rtt/memory_budget.h"

namespace rtt {
namespace {

using kd::SplitChoice;
using kd::Subtree;
using kd::TriBox;
using kd::TriBoxes;

/// Leaf references the whole tree may hold, per triangle. The SAH alone does not bound them:
/// n thin triangles along x crossing n along y in one plane make every split cut through one
/// family, and the SAH keeps splitting down to the depth limit; 2 x 2000 such triangles gave
/// 11.7 million references and 15.5 million nodes (O(n^2) cells). Ordinary scenes hold 2 to 6
/// references per triangle in total; a node only splits if its children's references fit its
/// share of this budget (tests/limits_test.cpp).
constexpr double reference_budget = 32.0;

/// Triangles per task when a node splits its triangles.
constexpr size_t grain = 4096;

/// Nodes with at least this many triangles build their children in parallel.
constexpr size_t parallel_min_triangles = 1024;

/// The binned levels: inner nodes down to the leaves and small subtrees below them.
struct TopNode {
    SplitChoice split;  ///< axis < 0: `built` holds the subtree (a leaf or a small subtree)
    std::unique_ptr<TopNode> below, above;
    Subtree built;
};

class TopBuilder {
public:
    TopBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config, int max_depth)
        : triangles_(triangles), config_(config), max_depth_(max_depth) {}

    /// The tree over the node `box` holding `items` (consumed), in parallel.
    std::unique_ptr<TopNode> build(TriBoxes&& items, const Bbox3f& box, int depth,
                                   double budget) const {
        auto node = std::make_unique<TopNode>();
        const size_t n = items.size();
        if (n <= kd::small_max_triangles) {
            kd::SmallBuilder(triangles_, config_, max_depth_)
                .build(items, box, depth, budget, node->built);
            // Held until the layout copies it: without the growth slack, or the build's peak
            // memory would exceed the tree's by up to 2x.
            node->built.nodes.shrink_to_fit();
            node->built.leaf_triangles.shrink_to_fit();
            return node;
        }
        if (n > size_t(config_.max_leaf_size) && depth < max_depth_) {
            node->split = kd::find_binned_split(items, box, config_);
            // The bins only refine around their best plane; a plane elsewhere may still do.
            if (!kd::takes_split(node->split, n, budget, config_))
                node->split = kd::find_exact_split(items, box, config_);
        }
        if (!kd::takes_split(node->split, n, budget, config_)) {
            node->split = {};
            for (const TriBox& t : items) node->built.leaf_triangles.push_back(t.tri);
            node->built.add_leaf(0);
            return node;
        }
        const SplitChoice& split = node->split;
        Bbox3f left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        TriBoxes left, right;
        partition(std::move(items), split, box, left, right);
        const auto build_below = [&] {
            node->below =
                build(std::move(left), left_box, depth + 1, kd::child_budget(budget, split, true));
        };
        const auto build_above = [&] {
            node->above = build(std::move(right), right_box, depth + 1,
                                kd::child_budget(budget, split, false));
        };
        if (n >= parallel_min_triangles) {
            tbb::parallel_invoke(build_below, build_above);
        } else {
            build_below();
            build_above();
        }
        return node;
    }

private:
    /// The children's triangles: a triangle that only touches the plane goes to the side it lies
    /// on, one lying in it to the side the SAH picked (pside), and one crossing it is clipped to
    /// each child (perfect splits). Every point of a triangle stays in some leaf that lists it,
    /// and every leaf whose interior the triangle meets lists it (trace/trace_ray.h relies on it).
    /// Consumes `items`, released as soon as they are read: the build's peak memory is the
    /// largest node's triangles about twice, not three times.
    void partition(TriBoxes&& items, const SplitChoice& split, const Bbox3f& box, TriBoxes& left,
                   TriBoxes& right) const {
        const size_t n = items.size();
        const auto part = [&](size_t begin, size_t end, TriBoxes& l, TriBoxes& r) {
            const int a = split.axis;
            const float p = split.pos;
            for (size_t i = begin; i < end; ++i) {
                const TriBox& t = items[i];
                const float lo = t.box.lo[a], hi = t.box.hi[a];
                if (lo == hi) {
                    (lo < p || (lo == p && split.planar_left) ? l : r).push_back(t);
                } else if (hi <= p) {
                    l.push_back(t);
                } else if (lo >= p) {
                    r.push_back(t);
                } else {
                    const ClippedSides c = clip_triangle_to_children(triangles_[t.tri], box, a, p);
                    if (c.left) l.push_back({c.left_box, t.tri});
                    if (c.right) r.push_back({c.right_box, t.tri});
                }
            }
        };
        if (n <= grain) {
            left.reserve(split.left_count);
            right.reserve(split.right_count);
            part(0, n, left, right);
            TriBoxes().swap(items);
            return;
        }
        const size_t chunks = (n + grain - 1) / grain;
        std::vector<TriBoxes> lefts(chunks), rights(chunks);
        tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
            part(c * grain, std::min(n, (c + 1) * grain), lefts[c], rights[c]);
        });
        TriBoxes().swap(items);
        concatenate(lefts, left);
        concatenate(rights, right);
    }

    /// Appends the parts in order, releasing each once copied.
    static void concatenate(std::vector<TriBoxes>& parts, TriBoxes& all) {
        size_t total = 0;
        for (const auto& part : parts) total += part.size();
        all.reserve(total);
        for (auto& part : parts) {
            all.insert(all.end(), part.begin(), part.end());
            TriBoxes().swap(part);
        }
    }

    std::span<const TriangleVerts> triangles_;
    const KdBuildConfig& config_;
    int max_depth_;
};

/// Lays the tree out in one array in depth-first order, below child first: the binned inner
/// nodes at their places, each subtree below them copied once (in parallel) and rebased.
/// Returns the number of those subtrees.
size_t lay_out(TopNode& root, KdTree& tree) {
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
        if (nodes > KdNode::max_index ||
            !n.set_inner(node.split.axis, node.split.pos, uint32_t(nodes)))
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
    return placed.size();
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
    const TriangleArray triangles = gather_triangles(scene);
    const size_t n = triangles.size();

    KdTree tree;
    TriBoxes items(n);
    tree.bounds = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n, grain), Bbox3f{},
        [&](const tbb::blocked_range<size_t>& r, Bbox3f bounds) {
            for (size_t i = r.begin(); i < r.end(); ++i) {
                items[i] = {triangle_bounds(triangles[i]), uint32_t(i)};
                bounds.extend(items[i].box);
            }
            return bounds;
        },
        [](Bbox3f a, const Bbox3f& b) {
            a.extend(b);
            return a;
        });
    const auto setup_done = Clock::now();

    const int max_depth = config.max_depth > 0 ? config.max_depth : auto_max_depth(n);
    const std::unique_ptr<TopNode> top =
        TopBuilder(triangles, config, max_depth)
            .build(std::move(items), tree.bounds, 0, reference_budget * double(n));
    const auto tree_done = Clock::now();

    const size_t subtrees = lay_out(*top, tree);
    const auto end = Clock::now();
    const double seconds = std::chrono::duration<double>(end - start).count();

    tree.stats = compute_stats(tree, config);
    tree.stats.triangles = n;
    tree.stats.build_seconds = seconds;
    tree.stats.setup_seconds = std::chrono::duration<double>(setup_done - start).count();
    tree.stats.tree_seconds = std::chrono::duration<double>(tree_done - setup_done).count();
    tree.stats.layout_seconds = std::chrono::duration<double>(end - tree_done).count();
    tree.stats.small_subtrees = subtrees;
    tree.stats.binned_nodes = subtrees - 1;  // a binary tree's inner nodes
    return tree;
}

}  // namespace rtt
