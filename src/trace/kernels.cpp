// One ISA's kernel tracers by kind (compiled once per ISA, like every kernel).
#include "trace/kernels.h"

#include "relevant_triangles/rtt_tracer.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

std::unique_ptr<Tracer> make_kernel_tracer(std::string_view kind, const Scene& scene,
                                           const KdTree& tree, const RttOptions& options) {
    if (kind == "bvh") return make_bvh_tracer(scene);
    if (kind == "bvh-high") return make_bvh_tracer(scene, bvh_high_quality);
    if (kind == "rtt") return std::make_unique<rtt_detail::RttTracer>(scene, tree, options);
    if (kind == "frustum") return make_frustum_tracer(scene, tree);
    if (kind == "packet") return make_packet_tracer<4>(scene, tree);
#ifdef RTT_HAVE_SIMD8
    if (kind == "packet8") return make_packet_tracer<8>(scene, tree);
#endif
#ifdef RTT_HAVE_SIMD16
    if (kind == "packet16") return make_packet_tracer<16>(scene, tree);
#endif
    return nullptr;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
