// One factory per tracer file that is compiled once (the SIMD kernels' are in kernels.h);
// registry.cpp maps kind names to them.
#pragma once

#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

std::unique_ptr<Tracer> make_brute_force_tracer(const Scene& scene, const KdTree& tree);
std::unique_ptr<Tracer> make_ray_tracer(const Scene& scene, const KdTree& tree);
#ifdef RTT_HAVE_EMBREE
/// Embree 3 (trace_embree.cpp): how its tracers hand it rays. They build their own BVH.
enum class EmbreeMode {
    packets,  ///< "embree": 4x4 blocks, rtcIntersect16/rtcOccluded16, coherent.
    stream,   ///< "embree-stream": one rtcIntersect1M/rtcOccluded1M per tile, coherent.
    single,   ///< "embree1": rtcIntersect1/rtcOccluded1 per ray.
};
/// The kind's name: the mode's, with "-medium" for Embree's MEDIUM build quality (else HIGH).
inline const char* embree_kind_name(EmbreeMode mode, bool medium) {
    switch (mode) {
        case EmbreeMode::packets:
            return medium ? "embree-medium" : "embree";
        case EmbreeMode::stream:
            return medium ? "embree-stream-medium" : "embree-stream";
        case EmbreeMode::single:
            break;
    }
    return medium ? "embree1-medium" : "embree1";
}
std::unique_ptr<Tracer> make_embree_tracer(const Scene& scene, EmbreeMode mode, bool medium);
#endif

}  // namespace rtt
