// The tracers built from the SIMD kernels, compiled once per ISA (simd/isa.h): registry.cpp
// reaches each ISA's through make_kernel_tracer.
#pragma once

#include <memory>
#include <string_view>

#include "bvh/bvh.h"
#include "rtt/kdtree.h"
#include "rtt/rtt_options.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// SIMD packets of K rays (trace_packet.cpp); K = 8 and 16 exist only where the ISA has them
/// (RTT_HAVE_SIMD8 / RTT_HAVE_SIMD16 in simd/simd.h).
template <int K>
std::unique_ptr<Tracer> make_packet_tracer(const Scene& scene, const KdTree& tree);

/// Shaft tiles with one origin as one large packet, one octant at a time (trace_frustum.h),
/// other tiles and shadows as the widest packets (trace_packet.cpp).
std::unique_ptr<Tracer> make_frustum_tracer(const Scene& scene, const KdTree& tree);

/// Single rays through a BVH of its own, bvh_width<> children per node (trace_bvh.h); the
/// kd-tree is not used. "bvh", or "bvh-high" with bvh_high_quality.
std::unique_ptr<Tracer> make_bvh_tracer(const Scene& scene, const BvhBuildOptions& options = {});

/// The tracer `kind` ("bvh", "bvh-high", "packet", "packet8", "packet16", "frustum" or "rtt") of
/// this ISA's kernels, or nullptr when this ISA has no such kind. `options` are RTT's (validated).
std::unique_ptr<Tracer> make_kernel_tracer(std::string_view kind, const Scene& scene,
                                           const KdTree& tree, const RttOptions& options);

}  // namespace RTT_ISA_NS
}  // namespace rtt
