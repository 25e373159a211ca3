// Perfect splits (Havran; Wald & Havran 2006, section 4.3): the bounds of the part of a
// triangle that lies inside a kd-tree cell, so that events and split candidates follow the
// triangle itself rather than its (larger) bounding box.
#pragma once

#include "geom/triangle.h"
#include "rtt/math.h"

namespace rtt {

/// Conservative bounds of T ∩ box, where T is the closed triangle (possibly degenerate: a
/// segment or a point) and `box` a closed, non-empty, finite box.
///
/// Returns false only when T misses the box: a triangle that touches it, even in one point of
/// its boundary, always returns true. On true, `out` contains every point of T ∩ box and lies
/// inside both `box` and T's own bounds; coordinates that are exact (a vertex inside the box, a
/// box face the triangle crosses) are returned exactly, the others are rounded outward, so an
/// axis-aligned triangle keeps a flat box.
bool clip_triangle_to_box(const TriangleVerts& tri, const Bbox3f& box, Bbox3f& out);

/// Bounds of the triangle's three vertices (exact).
inline Bbox3f triangle_bounds(const TriangleVerts& tri) {
    Bbox3f b;
    b.extend(tri.v0);
    b.extend(tri.v1);
    b.extend(tri.v2);
    return b;
}

}  // namespace rtt
