// O(N log N) SAH kd-tree build after Wald & Havran, "On building fast kd-trees for ray tracing,
// and on doing that in O(N log N)", IEEE Symposium on Interactive Ray Tracing 2006.
//
// The events of the subtree's triangles are sorted once. At each node one sweep per axis finds
// the best SAH split (kd_sah.cpp); the node's sorted event lists are then split in linear time:
// each triangle is classified left-only, right-only or both from the events of the split axis;
// left-only and right-only events keep their order in the children; triangles on both sides are
// clipped to each child box (perfect splits, kd_clip.cpp), and only their new events are sorted
// and merged in. Sorting O(sqrt N) straddling triangles per node keeps the build O(N log N).
//
// What the tree guarantees (the traversal in trace/trace_ray.h relies on it): every point of
// every triangle lies in the closed box of at least one leaf that references the triangle, and
// every leaf whose box interior the triangle meets references it. A triangle that only touches a
// split plane goes to the side it lies on; a triangle lying in the plane goes to the side the SAH
// picked (pside). Traversal visits both children of a plane the ray crosses within a margin, so
// a hit exactly on a split plane is always found.
//
// The levels above are built with binned SAH over all cores (kd_build.cpp); a subtree built
// here starts from events_of(its triangles). Large subtrees are built in parallel with oneTBB,
// and their largest nodes sweep and split their three axes in parallel. The tree does not
// depend on the thread count: every decision is made from the node's own data, and the
// children's node arrays are concatenated in one fixed order (below child first, pbrt's layout).
#include "kdtree/kd_sweep_build.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "geom/triangle.h"
#include "kdtree/kd_clip.h"
#include "kdtree/kd_events.h"
#include "kdtree/kd_sah.h"
#include "kdtree/kd_small_build.h"
#include "kdtree/kd_subtree.h"

namespace rtt::kd {
namespace {

enum Side : uint8_t { both, left_only, right_only };

/// Nodes with at least this many triangles, above this depth, build their two children in
/// parallel (2^8 tasks are plenty; each parallel level costs one copy of the above subtree).
constexpr size_t parallel_min_triangles = 4096;
constexpr int parallel_max_depth = 8;

}  // namespace

class SweepBuilder::Impl {
public:
    Impl(std::span<const TriangleVerts> triangles, const KdBuildConfig& config, int max_depth)
        : triangles_(triangles), config_(config), max_depth_(max_depth),
          small_(triangles, config, max_depth) {}

    /// Builds the subtree of a node (consuming its events) at the end of `out`. `budget` is the
    /// number of leaf references the subtree may hold (reference_budget, kd_build.cpp).
    void build(NodeEvents&& ev, const Bbox3f& box, int depth, double budget, Subtree& out) {
        const size_t n = ev.triangles;
        if (n <= small_max_triangles) {
            const std::vector<TriBox> items = items_of(ev);
            ev = NodeEvents{};
            small_.build(items, box, depth, budget, out);
            return;
        }
        SplitChoice split;
        if (n > size_t(config_.max_leaf_size) && depth < max_depth_) split = find_split(ev, box);
        if (!takes_split(split, n, budget, config_)) {
            make_leaf(ev, out);
            ev = NodeEvents{};  // release now, not when the parent returns
            return;
        }
        Bbox3f left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        NodeEvents left, right;
        split_events(std::move(ev), split, left_box, right_box, left, right);

        const double budget_left = child_budget(budget, split, true);
        const double budget_right = child_budget(budget, split, false);
        const size_t index = out.begin_inner();
        if (n >= parallel_min_triangles && depth < parallel_max_depth) {
            Subtree above;
            tbb::parallel_invoke(
                [&] { build(std::move(left), left_box, depth + 1, budget_left, out); },
                [&] { build(std::move(right), right_box, depth + 1, budget_right, above); });
            out.end_inner(index, split);
            out.append(above);
        } else {
            build(std::move(left), left_box, depth + 1, budget_left, out);
            out.end_inner(index, split);
            build(std::move(right), right_box, depth + 1, budget_right, out);
        }
    }

    const SmallBuilder& small() const { return small_; }

private:
    /// The bounds of a small node's triangles, read back from its events (n^2 look-ups on
    /// n <= small_max_triangles; no per-triangle table needed).
    static std::vector<TriBox> items_of(const NodeEvents& ev) {
        std::vector<TriBox> items;
        items.reserve(ev.triangles);
        for (const Event& e : ev.axis[0])
            if (e.type() != EventType::end) items.push_back({Bbox3f{}, e.tri()});
        for (int a = 0; a < 3; ++a)
            for (const Event& e : ev.axis[a]) {
                TriBox* t = items.data();
                while (t->tri != e.tri()) ++t;
                if (e.type() != EventType::end) t->box.lo[a] = e.pos;
                if (e.type() != EventType::start) t->box.hi[a] = e.pos;
            }
        return items;
    }

    /// The three axes' sweeps, in parallel in large nodes (the top of the tree).
    SplitChoice find_split(const NodeEvents& ev, const Bbox3f& box) const {
        if (ev.triangles < parallel_min_triangles) return kd::find_split(ev, box, config_);
        SplitChoice per_axis[3];
        tbb::parallel_for(0, 3, [&](int a) {
            per_axis[a] = find_split_on_axis(a, ev.axis[a], ev.triangles, box, config_);
        });
        return better(better(per_axis[0], per_axis[1]), per_axis[2]);
    }

    static void make_leaf(const NodeEvents& ev, Subtree& out) {
        const size_t first = out.leaf_triangles.size();
        for (const Event& e : ev.axis[0])
            if (e.type() != EventType::end) out.leaf_triangles.push_back(e.tri());
        out.add_leaf(first);
    }

    /// Per-thread working memory, reused from node to node. No node's split runs interleaved
    /// with another's on one thread (split_events waits only on its own, isolated tasks).
    struct Scratch {
        std::vector<uint8_t> side;  ///< Side of each triangle, indexed by triangle; only entries
                                    ///< of the current node's triangles are meaningful.
        std::vector<std::pair<uint32_t, Bbox3f>> clipped[2];  ///< Straddlers clipped per child.
        EventList fresh[2];                                   ///< Their events on one axis.
    };

    /// Wald & Havran 2006, section 5.3: distributes the node's events to the children in
    /// linear time, plus sorting the new events of the triangles that straddle the plane.
    void split_events(NodeEvents&& ev, const SplitChoice& split, const Bbox3f& left_box,
                      const Bbox3f& right_box, NodeEvents& left, NodeEvents& right) {
        Scratch& scratch = scratch_.local();
        std::vector<uint8_t>& side = scratch.side;
        if (side.size() < triangles_.size()) side.assign(triangles_.size(), both);

        const float p = split.pos;
        const EventList& split_axis = ev.axis[split.axis];
        for (const Event& e : split_axis) side[e.tri()] = both;
        for (const Event& e : split_axis) {
            switch (e.type()) {
                case EventType::end:
                    if (e.pos <= p) side[e.tri()] = left_only;
                    break;
                case EventType::start:
                    if (e.pos >= p) side[e.tri()] = right_only;
                    break;
                case EventType::planar:
                    side[e.tri()] = e.pos < p || (e.pos == p && split.planar_left) ? left_only : right_only;
                    break;
            }
        }

        // Straddling triangles: clip them to each child (perfect splits); a child they do not
        // touch drops them.
        // Plain references, not a structured binding: clang 14 cannot capture bindings in the
        // lambda below.
        auto& clipped_left = scratch.clipped[0];
        auto& clipped_right = scratch.clipped[1];
        clipped_left.clear();
        clipped_right.clear();
        size_t only_left = 0, only_right = 0;
        Bbox3f b;
        for (const Event& e : split_axis) {
            if (e.type() == EventType::end) continue;
            const uint32_t t = e.tri();
            if (side[t] == left_only) {
                ++only_left;
            } else if (side[t] == right_only) {
                ++only_right;
            } else {
                if (clip_triangle_to_box(triangles_[t], left_box, b)) clipped_left.emplace_back(t, b);
                if (clip_triangle_to_box(triangles_[t], right_box, b)) clipped_right.emplace_back(t, b);
            }
        }
        left.triangles = only_left + clipped_left.size();
        right.triangles = only_right + clipped_right.size();

        const auto split_on_axis = [&](int a, EventList (&fresh)[2]) {
            auto& [fresh_left, fresh_right] = fresh;
            events_on_axis(clipped_left, a, fresh_left);
            events_on_axis(clipped_right, a, fresh_right);
            EventList& l = left.axis[a];
            EventList& r = right.axis[a];
            l.reserve(2 * only_left + fresh_left.size());
            r.reserve(2 * only_right + fresh_right.size());
            // One pass: the parent's events, filtered by side, merged with the sorted new ones.
            auto fl = fresh_left.begin(), fr = fresh_right.begin();
            for (const Event& e : ev.axis[a]) {
                const uint8_t s = side[e.tri()];
                if (s == left_only) {
                    while (fl != fresh_left.end() && *fl < e) l.push_back(*fl++);
                    l.push_back(e);
                } else if (s == right_only) {
                    while (fr != fresh_right.end() && *fr < e) r.push_back(*fr++);
                    r.push_back(e);
                }
            }
            l.insert(l.end(), fl, fresh_left.end());
            r.insert(r.end(), fr, fresh_right.end());
            EventList().swap(ev.axis[a]);
        };
        if (ev.triangles < parallel_min_triangles) {
            for (int a = 0; a < 3; ++a) split_on_axis(a, scratch.fresh);
        } else {
            // The top of the tree: one task per axis. Isolated: while it waits, this thread
            // must not start another node's split, which would overwrite its scratch.
            tbb::this_task_arena::isolate([&] {
                tbb::parallel_for(0, 3, [&](int a) {
                    EventList fresh[2];
                    split_on_axis(a, fresh);
                });
            });
        }
    }

    /// The sorted events along axis `a` of triangles with the given bounds.
    static void events_on_axis(const std::vector<std::pair<uint32_t, Bbox3f>>& boxes, int a,
                               EventList& out) {
        out.clear();
        for (const auto& [t, box] : boxes) append_events(out, box.lo[a], box.hi[a], t);
        std::sort(out.begin(), out.end());
    }

    std::span<const TriangleVerts> triangles_;
    const KdBuildConfig& config_;
    int max_depth_;
    SmallBuilder small_;
    tbb::enumerable_thread_specific<Scratch> scratch_;
};

NodeEvents events_of(std::span<const TriBox> items) {
    NodeEvents ev;
    ev.triangles = items.size();
    const auto fill = [&](int a) {
        EventList& list = ev.axis[a];
        list.reserve(2 * items.size());
        for (const TriBox& t : items) append_events(list, t.box.lo[a], t.box.hi[a], t.tri);
        if (list.size() >= parallel_min_triangles)
            tbb::parallel_sort(list.begin(), list.end());
        else
            std::sort(list.begin(), list.end());
    };
    if (items.size() < parallel_min_triangles) {
        for (int a = 0; a < 3; ++a) fill(a);
    } else {
        tbb::parallel_for(0, 3, fill);
    }
    return ev;
}

SweepBuilder::SweepBuilder(std::span<const TriangleVerts> triangles, const KdBuildConfig& config,
                           int max_depth)
    : impl_(std::make_unique<Impl>(triangles, config, max_depth)) {}

SweepBuilder::~SweepBuilder() = default;

void SweepBuilder::build(std::span<const TriBox> items, const Bbox3f& box, int depth,
                         double budget, Subtree& out) {
    if (items.size() <= small_max_triangles)
        impl_->small().build(items, box, depth, budget, out);
    else
        impl_->build(events_of(items), box, depth, budget, out);
}

}  // namespace rtt::kd
