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

/// What clip_triangle_to_children returns: for each child, whether T meets it, and the bounds.
struct ClippedSides {
    bool left = false, right = false;
    Bbox3f left_box, right_box;
};

/// clip_triangle_to_box for both children of `box` split at `pos` along `axis` (below child
/// "left"), with the same guarantees; T is clipped to `box` once, then to each side of the
/// plane, which is what a split costs most of the time.
ClippedSides clip_triangle_to_children(const TriangleVerts& tri, const Bbox3f& box, int axis,
                                       float pos);

/// Bounds of the triangle's three vertices (exact).
inline Bbox3f triangle_bounds(const TriangleVerts& tri) {
    Bbox3f b;
    b.extend(tri.v0);
    b.extend(tri.v1);
    b.extend(tri.v2);
    return b;
}

}  // namespace rtt
