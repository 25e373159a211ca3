// The reference tracer: one ray at a time, stack-based front-to-back kd-tree traversal.
//
// Traversal semantics every kd-tree tracer (single ray, packets, RTT corners) follows, so that
// each returns exactly the brute-force answer (closest (t, index) over all triangles with t in
// [tmin, tmax]) despite rounding in the split distances:
//
//  * The ray's parameter interval is clipped to the tree bounds padded by kd_box_pad relative
//    to their extent; a NaN slab distance (origin on a slab face, direction 0 along it) never
//    shrinks the interval. An end the box moved is then widened by the split margin below,
//    (|t| + s) * kd_margin, but not beyond [tmin, tmax]: the slab distances are rounded at the
//    origin's magnitude, which for a camera far from a small scene is far coarser than the
//    padding, and an entry distance a few ulps past a hit on the bounds would skip every
//    stacked node there (camera 11469 away from a box of size 2: kdtree_test's
//    FarCameraKeepsHitsOnTheTreeBounds).
//  * At an inner node, d = (split - org[axis]) * inv_dir[axis]. The child on the side the ray
//    comes from first is `below` when the direction component is +0 or positive and `above` when
//    its sign bit is set; it covers t <= d, the other covers t >= d. With the margin
//    m = kd_margin * (|d| + s), the first child gets [ta, min(tb, d + m)], the second
//    [max(ta, d - m), tb]; a child is visited when its interval is not empty (lo <= hi). A NaN d
//    (origin on the plane, direction parallel to it) visits both with [ta, tb]; an infinite d
//    from a zero direction component (origin off the plane) is exact and gets m = 0.
//    s = max over axes of |padded bound - org| / max|dir| is the ray-parameter length of the
//    scene seen from the origin. Why it is needed: the watertight test's hit distance has an
//    ABSOLUTE error of a few ulps of s (t comes out of differences of vertex depths, which are
//    up to s), not a relative one. With origins close to a surface (rays from inside, shadow
//    rays near their ends) coplanar triangles hit at the same true t can come out a few 1e-10
//    apart while t itself is 1e-3, and a purely relative margin would skip (or clip away at
//    tmin/tmax) the cell of the one brute force picks. kd_margin * s is ~2^8 such errors.
//  * Leaf triangles are tested against the ray's own [tmin, best.t] (inclusive, so equal-t ties
//    reach the index comparison), not the leaf's interval.
//  * A popped node whose interval starts after best.t is skipped (start == best.t is visited).
//  * Any-hit returns at the first triangle met in [tmin, tmax].
#pragma once

#include <span>

#include "geom/triangle.h"
#include "rtt/kdtree.h"
#include "rtt/math.h"

namespace rtt {

/// Relative margin on split distances (see above): far larger than their rounding error.
inline constexpr float kd_margin = 1.0f / 65536.0f;
/// Relative padding of the tree bounds for the initial clip.
inline constexpr float kd_box_pad = 1.0f / 65536.0f;

/// Bounds padded as traversal uses them.
Bbox3f padded_bounds(const Bbox3f& box);

/// The ray-parameter length of the scene seen from the ray's origin: the largest coordinate
/// distance from the origin to `box` over the largest direction component (the scale of the
/// split margins).
float scene_t_scale(const Bbox3f& box, const Ray& ray);

/// Closest hit of one ray through the tree.
Hit trace_ray(const KdTree& tree, std::span<const TriangleVerts> triangles, const Ray& ray);

/// True when any triangle meets the ray within [tmin, tmax].
bool occluded_ray(const KdTree& tree, std::span<const TriangleVerts> triangles, const Ray& ray);

}  // namespace rtt
