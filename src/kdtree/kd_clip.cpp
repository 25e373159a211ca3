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

namespace rtt {
namespace {

struct Vec3d {
    double c[3];
};

/// A convex polygon stays convex under clipping and gains at most one vertex per plane (the
/// 2-vertex "polygon" of a degenerate triangle likewise): 3 + 6 = 9 vertices at most. Rounding
/// cannot break this by much; past half the buffer we stop clipping (still conservative).
constexpr int max_vertices = 32;

/// Keeps the part of the closed polygon `in` with sign * (x[axis] - plane) >= 0.
int clip_polygon(const Vec3d* in, int n, Vec3d* out, int axis, double plane, double sign) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3d& p = in[i];
        const Vec3d& q = in[i + 1 == n ? 0 : i + 1];
        const bool p_in = sign * (p.c[axis] - plane) >= 0.0;
        const bool q_in = sign * (q.c[axis] - plane) >= 0.0;
        if (p_in) out[m++] = p;
        if (p_in != q_in) {
            const double t = std::clamp((plane - p.c[axis]) / (q.c[axis] - p.c[axis]), 0.0, 1.0);
            Vec3d r;
            for (int a = 0; a < 3; ++a) r.c[a] = p.c[a] + t * (q.c[a] - p.c[a]);
            r.c[axis] = plane;
            out[m++] = r;
        }
    }
    return m;
}

float round_down(double x) {
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, neg_inf);
    return f;
}

float round_up(double x) {
    float f = float(x);
    if (double(f) < x) f = std::nextafter(f, pos_inf);
    return f;
}

}  // namespace

bool clip_triangle_to_box(const TriangleVerts& tri, const Bbox3f& box, Bbox3f& out) {
    const Bbox3f tb = triangle_bounds(tri);
    const Bbox3f exact{max(tb.lo, box.lo), min(tb.hi, box.hi)};  // bounds(T) ∩ box
    if (exact.empty()) return false;
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside &= tb.lo[a] >= box.lo[a] && tb.hi[a] <= box.hi[a];
    if (inside) {
        out = tb;
        return true;
    }

    float magnitude = 0.f;  // the max of floats is exact in float
    for (int a = 0; a < 3; ++a)
        magnitude = std::max({magnitude, std::fabs(tb.lo[a]), std::fabs(tb.hi[a]),
                              std::fabs(box.lo[a]), std::fabs(box.hi[a])});
    const double e = double(magnitude) * 0x1p-36;  // exact, as ldexp, without the call

    Vec3d buf[2][max_vertices];
    int n = 3;
    const Vec3f* v[3] = {&tri.v0, &tri.v1, &tri.v2};
    for (int i = 0; i < 3; ++i)
        for (int a = 0; a < 3; ++a) buf[0][i].c[a] = (*v[i])[a];
    int cur = 0;
    for (int a = 0; a < 3 && n > 0; ++a) {
        if (tb.lo[a] < box.lo[a] && n <= max_vertices / 2) {
            n = clip_polygon(buf[cur], n, buf[1 - cur], a, double(box.lo[a]) - e, 1.0);
            cur = 1 - cur;
        }
        if (tb.hi[a] > box.hi[a] && n > 0 && n <= max_vertices / 2) {
            n = clip_polygon(buf[cur], n, buf[1 - cur], a, double(box.hi[a]) + e, -1.0);
            cur = 1 - cur;
        }
    }
    if (n == 0) return false;

    for (int a = 0; a < 3; ++a) {
        double lo = buf[cur][0].c[a], hi = lo;
        for (int i = 1; i < n; ++i) {
            lo = std::min(lo, buf[cur][i].c[a]);
            hi = std::max(hi, buf[cur][i].c[a]);
        }
        const float flo = std::max(round_down(lo - e), exact.lo[a]);
        const float fhi = std::min(round_up(hi + e), exact.hi[a]);
        // Cannot happen with the bounds above; if it did, fall back to the exact outer bounds.
        out.lo[a] = flo <= fhi ? flo : exact.lo[a];
        out.hi[a] = flo <= fhi ? fhi : exact.hi[a];
    }
    return true;
}

}  // namespace rtt
