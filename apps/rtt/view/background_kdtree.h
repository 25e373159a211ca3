// The kd-tree built on a thread of its own, so that the viewer's first frames need not wait for
// it: until it is ready they come from the `bvh` kind, whose BVH builds several times faster
// (docs/benchmarks.md, "First image"). The tracer the viewer will switch to is set up on the
// same thread (RTT's plane ids take a large part of a second on big scenes).
#pragma once

#include <future>
#include <memory>
#include <string>
#include <string_view>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt::view {

class BackgroundKdTree {
public:
    /// Starts building the kd-tree of `scene`, then a tracer of `kind` over it (a kind that
    /// reads the kd-tree). `scene` must outlive this object and keep its triangles unchanged.
    BackgroundKdTree(const Scene& scene, std::string kind);
    BackgroundKdTree(const BackgroundKdTree&) = delete;
    BackgroundKdTree& operator=(const BackgroundKdTree&) = delete;
    /// Waits for an unfinished build: the thread reads the scene.
    ~BackgroundKdTree();

    /// The tree once built (with its tracer), else nullptr; rethrows what the build threw.
    const KdTree* ready();
    /// The tree, waiting for it; rethrows what the build threw.
    const KdTree& wait();
    /// The tracer made over the tree when `kind` is the kind given: once, after ready() or
    /// wait() gave the tree (else nullptr).
    std::unique_ptr<Tracer> take_tracer(std::string_view kind) {
        return kind == kind_ ? std::move(tracer_) : nullptr;
    }

private:
    struct Built {
        std::unique_ptr<KdTree> tree;  // on the heap: the tracer refers to it
        std::unique_ptr<Tracer> tracer;
    };
    void take(Built built);

    std::string kind_;
    std::future<Built> building_;
    std::unique_ptr<KdTree> tree_;
    std::unique_ptr<Tracer> tracer_;
};

}  // namespace rtt::view
