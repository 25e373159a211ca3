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

#include <algorithm>
#include <chrono>
#include <cmath>
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

class TopBuilder {
public:
    TopBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config, int max_depth)
        : triangles_(triangles), config_(config), max_depth_(max_depth),
          sweep_(triangles, config, max_depth) {}

    /// Builds the subtree of the node `box` holding `items` (consumed) at the end of `out`.
    void build(std::vector<TriBox>&& items, const Bbox3f& box, int depth, double budget,
               Subtree& out) {
        const size_t n = items.size();
        SplitChoice split;
        if (n > sweep_min_triangles && n > size_t(config_.max_leaf_size) && depth < max_depth_)
            split = kd::find_binned_split(items, box, config_);
        if (!kd::takes_split(split, n, budget, config_)) {
            sweep_.build(items, box, depth, budget, out);
            return;
        }
        Bbox3f left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        std::vector<TriBox> left, right;
        partition(items, split, left_box, right_box, left, right);
        std::vector<TriBox>().swap(items);  // release now, not when the children return

        const double budget_left = kd::child_budget(budget, split, true);
        const double budget_right = kd::child_budget(budget, split, false);
        const size_t index = out.begin_inner();
        Subtree above;
        tbb::parallel_invoke(
            [&] { build(std::move(left), left_box, depth + 1, budget_left, out); },
            [&] { build(std::move(right), right_box, depth + 1, budget_right, above); });
        out.end_inner(index, split);
        out.append(above);
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
    kd::SweepBuilder sweep_;
};

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
    const auto start = std::chrono::steady_clock::now();
    const std::vector<TriangleVerts> triangles = gather_triangles(scene);
    const size_t n = triangles.size();

    KdTree tree;
    std::vector<TriBox> items(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) items[i] = {triangle_bounds(triangles[i]), uint32_t(i)};
    });
    for (const TriBox& t : items) tree.bounds.extend(t.box);

    const int max_depth = config.max_depth > 0 ? config.max_depth : auto_max_depth(n);
    TopBuilder builder(triangles, config, max_depth);
    Subtree out;
    builder.build(std::move(items), tree.bounds, 0, reference_budget * double(n), out);
    tree.nodes = std::move(out.nodes);
    tree.leaf_triangles = std::move(out.leaf_triangles);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    tree.stats = compute_stats(tree, config);
    tree.stats.triangles = n;
    tree.stats.build_seconds = seconds;
    return tree;
}

}  // namespace rtt
