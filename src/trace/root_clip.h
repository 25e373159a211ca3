// The first step of every SIMD kd-tree traversal (trace_packet.cpp, trace_frustum.cpp): each
// lane's [tmin, tmax] clipped to the tree's padded bounds and widened by the split margin, with
// the lane's t_scale, exactly as trace_ray's clip_to_box and scene_t_scale (trace_ray.h).
#pragma once

#include "rtt/math.h"
#include "simd/isa.h"
#include "simd/simd.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Per lane: t0, t1 = the clipped interval (empty when t0 > t1, or NaN-free as trace_ray's),
/// t_scale = the ray-parameter length of the scene seen from the origin. `box` is
/// padded_bounds(tree.bounds); inv = 1 / dir per component.
template <int K>
RTT_FORCEINLINE void clip_to_root(const Bbox3f& box, const vfloat<K> (&org)[3], const Vec3v<K>& dir,
                                  const vfloat<K> (&inv)[3], vfloat<K> tmin, vfloat<K> tmax,
                                  vfloat<K>& t0, vfloat<K>& t1, vfloat<K>& t_scale) {
    using vf = vfloat<K>;
    using vb = vbool<K>;
    t0 = tmin;
    t1 = tmax;
    vf dist(0.f);  // largest coordinate distance from the origin to the padded box
    for (int a = 0; a < 3; ++a) {
        const vf lo = vf(box.lo[a]) - org[a], hi = vf(box.hi[a]) - org[a];
        const vf tn = lo * inv[a];
        const vf tf = hi * inv[a];
        const vb swap = tn > tf;
        // A NaN slab distance never shrinks the interval: max/min return their second operand.
        t0 = max(select(swap, tf, tn), t0);
        t1 = min(select(swap, tn, tf), t1);
        dist = max(max(abs(lo), abs(hi)), dist);  // non-negative, no NaN: order is irrelevant
    }
    t_scale = dist / max(max(abs(dir.x), abs(dir.y)), abs(dir.z));
    // Widen what the box cut by the split margin, within [tmin, tmax] (trace_ray.h).
    t0 = select(t0 > tmin, max(t0 - (abs(t0) + t_scale) * vf(kd_margin), tmin), tmin);
    t1 = select(t1 < tmax, min(t1 + (abs(t1) + t_scale) * vf(kd_margin), tmax), tmax);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
