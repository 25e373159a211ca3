// The oracle: every triangle against every ray, no acceleration structure. Tests hold every
// other tracer to its answers.
#pragma once

#include <span>

#include "geom/triangle.h"
#include "rtt/math.h"

namespace rtt {

/// Closest hit over all triangles (ties at equal t: smaller index).
Hit trace_brute_force(std::span<const TriangleVerts> triangles, const Ray& ray);

/// True when any triangle meets the ray within [tmin, tmax].
bool occluded_brute_force(std::span<const TriangleVerts> triangles, const Ray& ray);

}  // namespace rtt
