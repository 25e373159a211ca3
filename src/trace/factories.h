// One factory per tracer file; registry.cpp maps kind names to them.
#pragma once

#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

std::unique_ptr<Tracer> make_brute_force_tracer(const Scene& scene, const KdTree& tree);
std::unique_ptr<Tracer> make_ray_tracer(const Scene& scene, const KdTree& tree);
/// SIMD packets of K rays (trace_packet.cpp); K = 8 and 16 exist only in builds whose compiler
/// targets AVX2 / AVX-512 (RTT_HAVE_SIMD8 / RTT_HAVE_SIMD16 in simd/simd.h).
template <int K>
std::unique_ptr<Tracer> make_packet_tracer(const Scene& scene, const KdTree& tree);
#ifdef RTT_HAVE_EMBREE
/// Embree 3 (trace_embree.cpp): "embree" traces 4x4 blocks with rtcIntersect16/rtcOccluded16,
/// "embree1" one ray at a time. Both ignore `tree` and build their own BVH.
std::unique_ptr<Tracer> make_embree_tracer(const Scene& scene, const KdTree& tree);
std::unique_ptr<Tracer> make_embree1_tracer(const Scene& scene, const KdTree& tree);
#endif

}  // namespace rtt
