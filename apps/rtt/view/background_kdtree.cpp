#include "view/background_kdtree.h"

#include <chrono>

namespace rtt::view {

BackgroundKdTree::BackgroundKdTree(const Scene& scene)
    : building_(std::async(std::launch::async, [&scene] { return build_kdtree(scene); })) {}

BackgroundKdTree::~BackgroundKdTree() {
    if (building_.valid()) building_.wait();
}

const KdTree* BackgroundKdTree::ready() {
    if (!tree_ && building_.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
        tree_.emplace(building_.get());
    return tree_ ? &*tree_ : nullptr;
}

const KdTree& BackgroundKdTree::wait() {
    if (!tree_) tree_.emplace(building_.get());
    return *tree_;
}

}  // namespace rtt::view
