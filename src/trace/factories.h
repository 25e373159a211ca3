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
/// Shaft tiles with one origin as one large packet, one octant at a time (trace_frustum.h),
/// other tiles and shadows as the widest packets (trace_packet.cpp).
std::unique_ptr<Tracer> make_frustum_tracer(const Scene& scene, const KdTree& tree);
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
