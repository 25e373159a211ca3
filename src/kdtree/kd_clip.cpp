// Clipping a triangle to a box, conservatively.
//
// Sutherland–Hodgman clipping of the triangle against the box's six planes, in double. The
// trap is rounding: an intersection point of an edge nearly parallel to a clip plane has an
// almost arbitrary position along that edge, so clipping exactly at the plane could drop a
// sliver of triangle that really lies inside the box. We therefore clip against the planes
// moved OUTWARD by e, a bound far above every double rounding error of the computation
// (e = 2^-36 * largest coordinate magnitude; the errors are ~2^-50 of it). A computed
// intersection point always has the clip coordinate within rounding of the moved plane (only
// its position along the edge is uncertain), so every point of T ∩ box, being at least e inside
// each moved plane, survives. The polygon's bounds are then widened by e (errors of the kept
// points), rounded outward to float, and finally intersected with bounds(T) ∩ box, which are
// exact: coordinates of kept vertices and of crossed box faces come out exactly, the rest at
// most about one float ulp loose. e is ~2^-12 float ulp of the largest coordinate, so the
// widening never costs more than that ulp.
#include "kdtree/kd_clip.h"

#include <algorithm>
#include <cmath>

#include "core/float_step.h"

namespace rtt {
namespace {

struct Vec3d {
    double c[3];
};

/// A convex polygon stays convex under clipping and gains at most one vertex per plane (the
/// 2-vertex "polygon" of a degenerate triangle likewise): 3 + 6 = 9 vertices at most. Rounding
/// cannot break this by much; past half the buffer we stop clipping (still conservative).
constexpr int max_vertices = 32;

/// The point of segment pq at x[axis] = plane (p and q on either side).
Vec3d crossing(const Vec3d& p, const Vec3d& q, int axis, double plane) {
    const double t = std::clamp((plane - p.c[axis]) / (q.c[axis] - p.c[axis]), 0.0, 1.0);
    Vec3d r;
    for (int a = 0; a < 3; ++a) r.c[a] = p.c[a] + t * (q.c[a] - p.c[a]);
    r.c[axis] = plane;
    return r;
}

/// Keeps the part of the closed polygon `in` with sign * (x[axis] - plane) >= 0.
int clip_polygon(const Vec3d* in, int n, Vec3d* out, int axis, double plane, double sign) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3d& p = in[i];
        const Vec3d& q = in[i + 1 == n ? 0 : i + 1];
        const bool p_in = sign * (p.c[axis] - plane) >= 0.0;
        const bool q_in = sign * (q.c[axis] - plane) >= 0.0;
        if (p_in) out[m++] = p;
        if (p_in != q_in) out[m++] = crossing(p, q, axis, plane);
    }
    return m;
}

float round_down(double x) {
    float f = float(x);
    if (double(f) > x) f = next_float_down(f);
    return f;
}

float round_up(double x) {
    float f = float(x);
    if (double(f) < x) f = next_float_up(f);
    return f;
}

/// A triangle as a polygon in double, clipped to planes moved outward by e.
struct Polygon {
    Vec3d v[2][max_vertices];
    int n = 3, cur = 0;

    explicit Polygon(const TriangleVerts& tri) {
        const Vec3f* p[3] = {&tri.v0, &tri.v1, &tri.v2};
        for (int i = 0; i < 3; ++i)
            for (int a = 0; a < 3; ++a) v[0][i].c[a] = (*p[i])[a];
    }
    const Vec3d* vertices() const { return v[cur]; }
    /// Keeps sign * (x[axis] - plane) >= 0; past half the buffer, stops clipping (conservative).
    void clip(int axis, double plane, double sign) {
        if (n == 0 || n > max_vertices / 2) return;
        n = clip_polygon(v[cur], n, v[1 - cur], axis, plane, sign);
        cur = 1 - cur;
    }
    /// Clips to the planes of `box` (moved out by e) that the triangle's bounds `tb` cross.
    void clip_to(const Bbox3f& box, const Bbox3f& tb, double e) {
        for (int a = 0; a < 3; ++a) {
            if (tb.lo[a] < box.lo[a]) clip(a, double(box.lo[a]) - e, 1.0);
            if (tb.hi[a] > box.hi[a]) clip(a, double(box.hi[a]) + e, -1.0);
        }
    }
};

/// e: far above every double rounding error of clipping coordinates of this magnitude.
double margin(const Bbox3f& tb, const Bbox3f& box) {
    float magnitude = 0.f;  // the max of floats is exact in float
    for (int a = 0; a < 3; ++a)
        magnitude = std::max({magnitude, std::fabs(tb.lo[a]), std::fabs(tb.hi[a]),
                              std::fabs(box.lo[a]), std::fabs(box.hi[a])});
    return double(magnitude) * 0x1p-36;  // exact, as ldexp, without the call
}

/// Bounds lo..hi of clipped points, widened by e, rounded outward and intersected with the
/// exact bounds(T) ∩ box.
Bbox3f rounded_bounds(const double (&lo)[3], const double (&hi)[3], double e, const Bbox3f& exact) {
    Bbox3f out;
    for (int a = 0; a < 3; ++a) {
        const float flo = std::max(round_down(lo[a] - e), exact.lo[a]);
        const float fhi = std::min(round_up(hi[a] + e), exact.hi[a]);
        // Cannot happen with the bounds above; if it did, fall back to the exact outer bounds.
        out.lo[a] = flo <= fhi ? flo : exact.lo[a];
        out.hi[a] = flo <= fhi ? fhi : exact.hi[a];
    }
    return out;
}

/// Bounds of the clipped polygon `v` (n > 0), as rounded_bounds.
Bbox3f polygon_bounds(const Vec3d* v, int n, double e, const Bbox3f& exact) {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = v[0].c[a], hi[a] = lo[a];
        for (int i = 1; i < n; ++i) {
            lo[a] = std::min(lo[a], v[i].c[a]);
            hi[a] = std::max(hi[a], v[i].c[a]);
        }
    }
    return rounded_bounds(lo, hi, e, exact);
}

bool inside(const Bbox3f& tb, const Bbox3f& box) {
    bool in = true;
    for (int a = 0; a < 3; ++a) in &= tb.lo[a] >= box.lo[a] && tb.hi[a] <= box.hi[a];
    return in;
}

}  // namespace

bool clip_triangle_to_box(const TriangleVerts& tri, const Bbox3f& box, Bbox3f& out) {
    const Bbox3f tb = triangle_bounds(tri);
    const Bbox3f exact{max(tb.lo, box.lo), min(tb.hi, box.hi)};  // bounds(T) ∩ box
    if (exact.empty()) return false;
    if (inside(tb, box)) {
        out = tb;
        return true;
    }
    const double e = margin(tb, box);
    Polygon poly(tri);
    poly.clip_to(box, tb, e);
    if (poly.n == 0) return false;
    out = polygon_bounds(poly.vertices(), poly.n, e, exact);
    return true;
}

ClippedSides clip_triangle_to_children(const TriangleVerts& tri, const Bbox3f& box, int axis,
                                       float pos) {
    ClippedSides sides;
    Bbox3f left_box = box, right_box = box;
    left_box.hi[axis] = pos;
    right_box.lo[axis] = pos;
    const Bbox3f tb = triangle_bounds(tri);
    const Bbox3f exact_left{max(tb.lo, left_box.lo), min(tb.hi, left_box.hi)};
    const Bbox3f exact_right{max(tb.lo, right_box.lo), min(tb.hi, right_box.hi)};
    const double e = margin(tb, box);
    Polygon poly(tri);
    if (!inside(tb, box)) poly.clip_to(box, tb, e);
    if (poly.n == 0 || poly.n > max_vertices / 2) {
        // No vertices, or (never in practice) too many to clip further: bounds of what is left.
        sides.left = poly.n > 0 && !exact_left.empty();
        sides.right = poly.n > 0 && !exact_right.empty();
        if (sides.left) sides.left_box = polygon_bounds(poly.vertices(), poly.n, e, exact_left);
        if (sides.right) sides.right_box = polygon_bounds(poly.vertices(), poly.n, e, exact_right);
        return sides;
    }
    // Both sides in one pass over the polygon's edges, the side polygons never built: the
    // vertices clip_polygon would keep or make (the same arithmetic) extend each side's bounds.
    // Left keeps x <= pos + e, right x >= pos - e (the planes moved outward, as above).
    const double plane[2] = {double(pos) + e, double(pos) - e};
    double lo[2][3], hi[2][3];
    for (int s = 0; s < 2; ++s)
        for (int a = 0; a < 3; ++a) lo[s][a] = pos_inf, hi[s][a] = neg_inf;
    const auto extend = [&](int s, const Vec3d& p) {
        for (int a = 0; a < 3; ++a) {
            lo[s][a] = std::min(lo[s][a], p.c[a]);
            hi[s][a] = std::max(hi[s][a], p.c[a]);
        }
    };
    const Vec3d* v = poly.vertices();
    for (int i = 0; i < poly.n; ++i) {
        const Vec3d& p = v[i];
        const Vec3d& q = v[i + 1 == poly.n ? 0 : i + 1];
        for (int s = 0; s < 2; ++s) {
            const double sign = s == 0 ? -1.0 : 1.0;
            const bool p_in = sign * (p.c[axis] - plane[s]) >= 0.0;
            const bool q_in = sign * (q.c[axis] - plane[s]) >= 0.0;
            if (p_in) extend(s, p);
            if (p_in != q_in) extend(s, crossing(p, q, axis, plane[s]));
        }
    }
    const auto finish = [&](int s, const Bbox3f& exact, Bbox3f& out) {
        if (exact.empty() || !(lo[s][0] <= hi[s][0])) return false;
        out = rounded_bounds(lo[s], hi[s], e, exact);
        return true;
    };
    sides.left = finish(0, exact_left, sides.left_box);
    sides.right = finish(1, exact_right, sides.right_box);
    return sides;
}

}  // namespace rtt
