// What a benchmark may ask of the Embree tracers beyond the Tracer interface: the cost of the
// BVH they build for themselves (they ignore the kd-tree handed to make_tracer).
//
// Header-only on purpose: the Embree tracers exist only when CMake found Embree 3, and these
// queries must compile and link in every build. They answer through a dynamic_cast, so on a
// tracer of any other kind (or a build without Embree) they return "not applicable".
#pragma once

#include <cstddef>

#include "rtt/tracer.h"

namespace rtt {

/// Implemented by tracers that build their own acceleration structure (kinds "embree",
/// "embree1"). Both values are fixed once the tracer is constructed.
class OwnAccelerationInfo {
public:
    virtual ~OwnAccelerationInfo() = default;
    /// Wall-clock seconds of the BVH build (rtcCommitScene alone: no device creation, no copy
    /// of the vertex and index buffers). Embree builds on the calling thread's oneTBB arena, so
    /// a tbb::global_control that limits the renderer's threads limits this build too.
    virtual double build_seconds() const = 0;
    /// Bytes the Embree device held after the build (BVH plus its copy of the geometry), as
    /// reported by Embree's memory monitor.
    virtual size_t memory_bytes() const = 0;
};

/// Seconds the tracer's own BVH build took, or -1 when `tracer` builds none (every non-Embree
/// kind: their kd-tree build time is in KdStats::build_seconds).
inline double embree_build_seconds(const Tracer& tracer) {
    const auto* info = dynamic_cast<const OwnAccelerationInfo*>(&tracer);
    return info ? info->build_seconds() : -1.0;
}

/// Bytes held by the tracer's own acceleration structure, or 0 when it builds none.
inline size_t embree_memory_bytes(const Tracer& tracer) {
    const auto* info = dynamic_cast<const OwnAccelerationInfo*>(&tracer);
    return info ? info->memory_bytes() : 0;
}

}  // namespace rtt
