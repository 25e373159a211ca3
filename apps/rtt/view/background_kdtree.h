// The kd-tree built on a thread of its own, so that the viewer's first frames need not wait for
// it: until it is ready they come from the `bvh` kind, whose BVH builds several times faster
// (docs/benchmarks.md, "First image").
#pragma once

#include <future>
#include <optional>

#include "rtt/kdtree.h"
#include "rtt/scene.h"

namespace rtt::view {

class BackgroundKdTree {
public:
    /// Starts building the kd-tree of `scene` (which must outlive this object and keep its
    /// triangles unchanged until the tree is built).
    explicit BackgroundKdTree(const Scene& scene);
    BackgroundKdTree(const BackgroundKdTree&) = delete;
    BackgroundKdTree& operator=(const BackgroundKdTree&) = delete;
    /// Waits for an unfinished build: the thread reads the scene.
    ~BackgroundKdTree();

    /// The tree once built, else nullptr; rethrows what the build threw.
    const KdTree* ready();
    /// The tree, waiting for it; rethrows what the build threw.
    const KdTree& wait();

private:
    std::future<KdTree> building_;
    std::optional<KdTree> tree_;
};

}  // namespace rtt::view
