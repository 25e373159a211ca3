// Single rays through the 4-wide BVH (trace_bvh.cpp), for tests and callers holding a Bvh4.
#pragma once

#include "bvh/bvh.h"

namespace rtt {

/// The closest hit of `ray` (trace_ray's, bit for bit).
Hit trace_bvh(const Bvh4& bvh, const Ray& ray);

/// Whether some triangle meets `ray` in [tmin, tmax] (occluded_ray's answer).
bool occluded_bvh(const Bvh4& bvh, const Ray& ray);

}  // namespace rtt
