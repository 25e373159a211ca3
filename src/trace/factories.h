// One factory per tracer file; registry.cpp maps kind names to them.
#pragma once

#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

std::unique_ptr<Tracer> make_brute_force_tracer(const Scene& scene, const KdTree& tree);
std::unique_ptr<Tracer> make_ray_tracer(const Scene& scene, const KdTree& tree);

}  // namespace rtt
