#include "view/background_kdtree.h"

#include <chrono>
#include <utility>

namespace rtt::view {

BackgroundKdTree::BackgroundKdTree(const Scene& scene, std::string kind)
    : kind_(std::move(kind)), building_(std::async(std::launch::async, [&scene, this] {
          Built b;
          b.tree = std::make_unique<KdTree>(build_kdtree(scene));
          b.tracer = make_tracer(kind_, scene, *b.tree);
          return b;
      })) {}

BackgroundKdTree::~BackgroundKdTree() {
    if (building_.valid()) building_.wait();
}

void BackgroundKdTree::take(Built built) {
    tree_ = std::move(built.tree);
    tracer_ = std::move(built.tracer);
}

const KdTree* BackgroundKdTree::ready() {
    if (!tree_ && building_.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
        take(building_.get());
    return tree_.get();
}

const KdTree& BackgroundKdTree::wait() {
    if (!tree_) take(building_.get());
    return *tree_;
}

}  // namespace rtt::view
