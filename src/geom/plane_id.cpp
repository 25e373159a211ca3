#include "geom/plane_id.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "core/large_arrays.h"

namespace rtt {
namespace {

// ---- exact arithmetic on float inputs (Shewchuk, "Adaptive Precision Floating-Point Arithmetic
// and Fast Robust Geometric Predicates", 1997) ------------------------------------------------

/// a - b of two floats as an exact unevaluated sum hi + lo of doubles (Two-Diff).
struct Exact2 {
    double hi, lo;
};
Exact2 exact_diff(float a, float b) {
    const double x = double(a), y = double(b);
    const double hi = x - y;
    const double x_virt = hi + y;
    const double y_virt = x_virt - hi;
    return {hi, (x - x_virt) + (y_virt - y)};
}

/// Two-Product: a * b == p + e exactly (the error term of a correctly rounded product is
/// itself a double, computed exactly by the fused multiply-add).
void two_product(double a, double b, double& p, double& e) {
    p = a * b;
    e = std::fma(a, b, -p);
}

/// A nonoverlapping expansion with components of increasing magnitude, grown one double at a
/// time (Grow-Expansion with zero elimination, Shewchuk's Theorem 10): its sign is the sign of
/// its largest component.
class Expansion {
public:
    void add(double b) {
        double q = b;
        int m = 0;
        for (int i = 0; i < n_; ++i) {
            const double x = q + e_[i];
            const double b_virt = x - q;
            const double a_virt = x - b_virt;
            const double err = (q - a_virt) + (e_[i] - b_virt);  // Two-Sum
            if (err != 0.0) e_[m++] = err;
            q = x;
        }
        if (q != 0.0) e_[m++] = q;
        n_ = m;
    }
    int sign() const { return n_ == 0 ? 0 : (e_[n_ - 1] > 0.0 ? 1 : -1); }

private:
    std::array<double, 256> e_;  // one component per add() at most: 6 * 8 * 4 = 192 adds
    int n_ = 0;
};

/// Adds s * x * y * z exactly: the 2 x 2 x 2 products of the parts, each split into 4 doubles.
void add_product3(Expansion& e, double s, const Exact2& x, const Exact2& y, const Exact2& z) {
    const double xs[2] = {x.hi, x.lo}, ys[2] = {y.hi, y.lo}, zs[2] = {z.hi, z.lo};
    for (double a : xs) {
        if (a == 0.0) continue;
        for (double b : ys) {
            if (b == 0.0) continue;
            double p, q;
            two_product(s * a, b, p, q);  // s = +-1: exact
            for (double c : zs) {
                if (c == 0.0) continue;
                double r0, r1, r2, r3;
                two_product(p, c, r0, r1);
                two_product(q, c, r2, r3);
                e.add(r1);
                e.add(r3);
                e.add(r2);
                e.add(r0);
            }
        }
    }
}

/// Adds s * x * y exactly.
void add_product2(Expansion& e, double s, const Exact2& x, const Exact2& y) {
    const double xs[2] = {x.hi, x.lo}, ys[2] = {y.hi, y.lo};
    for (double a : xs)
        for (double b : ys) {
            double p, q;
            two_product(s * a, b, p, q);
            e.add(q);
            e.add(p);
        }
}

/// Exact sign of the 2D orientation of the points (p, q, r) projected on axes (i, j).
int orient2d_sign(const Vec3f& p, const Vec3f& q, const Vec3f& r, int i, int j) {
    const Exact2 ux = exact_diff(q[i], p[i]), uy = exact_diff(q[j], p[j]);
    const Exact2 vx = exact_diff(r[i], p[i]), vy = exact_diff(r[j], p[j]);
    // Filter: the determinant of the rounded differences in double errs by less than 3 eps *
    // permanent for exact inputs (Shewchuk's ccwerrboundA) plus 2 eps * permanent for the
    // rounding of the differences (eps = 2^-53); 1e-15 * permanent is a safe bound.
    const double l = ux.hi * vy.hi, r2 = uy.hi * vx.hi, det = l - r2;
    const double bound = 1e-15 * (std::fabs(l) + std::fabs(r2));
    if (det > bound) return 1;
    if (det < -bound) return -1;
    Expansion e;
    add_product2(e, 1.0, ux, vy);
    add_product2(e, -1.0, uy, vx);
    return e.sign();
}

}  // namespace

int orient3d_sign(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
    const Exact2 ax = exact_diff(a.x, d.x), ay = exact_diff(a.y, d.y), az = exact_diff(a.z, d.z);
    const Exact2 bx = exact_diff(b.x, d.x), by = exact_diff(b.y, d.y), bz = exact_diff(b.z, d.z);
    const Exact2 cx = exact_diff(c.x, d.x), cy = exact_diff(c.y, d.y), cz = exact_diff(c.z, d.z);
    // Filter: the determinant of the rounded differences in double. Its error is below
    // 7 eps * permanent for exact inputs (Shewchuk's o3derrboundA) plus 3 eps * permanent for the
    // rounding of the differences (eps = 2^-53); 4e-15 * permanent is a safe bound.
    const double m1 = by.hi * cz.hi - bz.hi * cy.hi;
    const double m2 = cy.hi * az.hi - cz.hi * ay.hi;
    const double m3 = ay.hi * bz.hi - az.hi * by.hi;
    const double det = ax.hi * m1 + bx.hi * m2 + cx.hi * m3;
    const double permanent =
        std::fabs(ax.hi) * (std::fabs(by.hi * cz.hi) + std::fabs(bz.hi * cy.hi)) +
        std::fabs(bx.hi) * (std::fabs(cy.hi * az.hi) + std::fabs(cz.hi * ay.hi)) +
        std::fabs(cx.hi) * (std::fabs(ay.hi * bz.hi) + std::fabs(az.hi * by.hi));
    const double bound = 4e-15 * permanent;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    Expansion e;
    add_product3(e, 1.0, ax, by, cz);
    add_product3(e, -1.0, ax, bz, cy);
    add_product3(e, 1.0, bx, cy, az);
    add_product3(e, -1.0, bx, cz, ay);
    add_product3(e, 1.0, cx, ay, bz);
    add_product3(e, -1.0, cx, az, by);
    return e.sign();
}

bool collinear(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    // Collinear iff the cross product (b - a) x (c - a) vanishes, i.e. all three projections
    // onto the coordinate planes are degenerate.
    return orient2d_sign(a, b, c, 1, 2) == 0 && orient2d_sign(a, b, c, 2, 0) == 0 &&
           orient2d_sign(a, b, c, 0, 1) == 0;
}

namespace {

/// A triangle, the cell of its approximate plane packed in two words (kind in the top bits of
/// `hi`: 1 for an axis-aligned plane x[a] == c, exact and needing no verification; 2 for a
/// quantized normalized (n, d); 3 for a cell of one triangle), and its index: sorted, the cells
/// come out contiguous and each in index order. Small keys sort several times faster than the
/// unpacked ones.
struct KeyedTriangle {
    uint64_t hi, lo;  // degenerate triangles: degenerate_key in both, sorted last
    uint32_t triangle;
    bool same_cell(const KeyedTriangle& o) const { return hi == o.hi && lo == o.lo; }
    bool axis_aligned() const { return (hi >> 62) == 1; }
    bool operator<(const KeyedTriangle& o) const {
        if (hi != o.hi) return hi < o.hi;
        if (lo != o.lo) return lo < o.lo;
        return triangle < o.triangle;
    }
};

constexpr uint64_t degenerate_key = ~uint64_t(0);

bool same_point(const Vec3f& a, const Vec3f& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/// The keyed cell of triangle `i`, or false when it is degenerate (collinear or coincident
/// vertices, decided exactly); `scale` is the largest |coordinate|.
bool plane_key(const TriangleVerts& t, uint32_t i, double scale, KeyedTriangle& out) {
    constexpr double cells = 1048576.0;  // 2^20 cells per unit: far coarser than rounding
    out.triangle = i;
    for (int a = 0; a < 3; ++a)
        if (t.v0[a] == t.v1[a] && t.v1[a] == t.v2[a]) {
            // Three equal coordinates: degenerate only if the other two axes' projection is.
            if (collinear(t.v0, t.v1, t.v2)) return false;
            out.hi = (uint64_t(1) << 62) | uint64_t(a);
            out.lo = std::bit_cast<uint32_t>(t.v0[a] + 0.f);  // -0 -> +0
            return true;
        }
    const double e1[3] = {double(t.v1.x) - t.v0.x, double(t.v1.y) - t.v0.y,
                          double(t.v1.z) - t.v0.z};
    const double e2[3] = {double(t.v2.x) - t.v0.x, double(t.v2.y) - t.v0.y,
                          double(t.v2.z) - t.v0.z};
    const double p[3][2] = {{e1[1] * e2[2], e1[2] * e2[1]},
                            {e1[2] * e2[0], e1[0] * e2[2]},
                            {e1[0] * e2[1], e1[1] * e2[0]}};
    double n[3];
    bool spans = false;
    for (int k = 0; k < 3; ++k) {
        n[k] = p[k][0] - p[k][1];
        // A rounded component errs by less than 5 eps (eps = 2^-53) times the sum of its two
        // products' magnitudes (the differences' rounding and the products'): one beyond 1e-14
        // of that sum proves the triangle spans a plane. Near zero on every axis, the exact
        // test decides.
        spans |= std::fabs(n[k]) > 1e-14 * (std::fabs(p[k][0]) + std::fabs(p[k][1]));
    }
    if (!spans && collinear(t.v0, t.v1, t.v2)) return false;
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0)) {  // spans a plane, but its rounded normal vanished: a cell of its own
        out.hi = (uint64_t(3) << 62) | i;
        out.lo = 0;
        return true;
    }
    const int big = std::fabs(n[0]) >= std::fabs(n[1])
                        ? (std::fabs(n[0]) >= std::fabs(n[2]) ? 0 : 2)
                        : (std::fabs(n[1]) >= std::fabs(n[2]) ? 1 : 2);
    const double s = (n[big] < 0.0 ? -1.0 : 1.0) / len;
    for (double& c : n) c *= s;
    const double d = n[0] * t.v0.x + n[1] * t.v0.y + n[2] * t.v0.z;
    // |n_k| <= 1 and |d| <= sqrt(3) scale: every cell index lies within +-2^21, stored offset
    // by 2^22 in 23 bits (clamped against rounding at the ends).
    const auto cell = [&](double x) {
        return uint64_t(std::clamp(x * cells, -4194304.0, 4194303.0) + 4194304.0);
    };
    out.hi = (uint64_t(2) << 62) | (cell(n[0]) << 23) | cell(n[1]);
    out.lo = (cell(n[2]) << 23) | cell(d / scale);
    return true;
}

/// Every vertex of `t` lies exactly on the plane of the (non-degenerate) triangle `r`.
bool on_plane_of(const TriangleVerts& r, const TriangleVerts& t) {
    for (const Vec3f& v : {t.v0, t.v1, t.v2}) {
        if (same_point(v, r.v0) || same_point(v, r.v1) || same_point(v, r.v2)) continue;
        if (orient3d_sign(r.v0, r.v1, r.v2, v) != 0) return false;
    }
    return true;
}

}  // namespace

PlaneIds compute_plane_ids(std::span<const TriangleVerts> triangles) {
    PlaneIds out;
    out.id.assign(triangles.size(), no_plane);
    double scale = 0.0;
    for (const TriangleVerts& t : triangles)
        for (const Vec3f& v : {t.v0, t.v1, t.v2})
            scale = std::max(
                {scale, double(std::fabs(v.x)), double(std::fabs(v.y)), double(std::fabs(v.z))});
    if (!(scale > 0.0)) scale = 1.0;

    // Cells bucketed by a hash of their key, then sorted within each bucket: a hash map of
    // per-cell lists cost a malloc and a free per plane, one sort of all the triangles twice
    // the buckets' time (docs/design.md, "Plane identity").
    large_vector<KeyedTriangle> keyed(triangles.size());
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(triangles.size()), 4096),
                      [&](const tbb::blocked_range<uint32_t>& r) {
                          for (uint32_t i = r.begin(); i < r.end(); ++i)
                              if (!plane_key(triangles[i], i, scale, keyed[i]))
                                  keyed[i] = {degenerate_key, degenerate_key, i};
                      });
    // About 16 triangles per bucket; a cell lies in one bucket, in index order after the sort
    // (the order is total), and cells are independent: the ids do not depend on the buckets.
    const int bits = std::clamp(int(std::bit_width(triangles.size() / 16)), 4, 16);
    const auto bucket_of = [bits](const KeyedTriangle& k) {
        uint64_t h = k.hi * 0x9E3779B97F4A7C15ull ^ (k.lo + 0x632BE59BD9B4E019ull);
        h ^= h >> 29;
        h *= 0xBF58476D1CE4E5B9ull;
        return uint32_t(h >> (64 - bits));
    };
    std::vector<uint32_t> first((size_t(1) << bits) + 1, 0);
    for (const KeyedTriangle& k : keyed)
        if (k.hi != degenerate_key) ++first[bucket_of(k) + 1];
    for (size_t b = 1; b < first.size(); ++b) first[b] += first[b - 1];
    large_vector<KeyedTriangle> bucketed(first.back());
    {
        std::vector<uint32_t> at(first.begin(), first.end() - 1);
        for (const KeyedTriangle& k : keyed)
            if (k.hi != degenerate_key) bucketed[at[bucket_of(k)]++] = k;
    }
    keyed = large_vector<KeyedTriangle>();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, first.size() - 1, 64),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t b = r.begin(); b < r.end(); ++b)
                              std::sort(bucketed.begin() + first[b],
                                        bucketed.begin() + first[b + 1]);
                      });
    keyed = std::move(bucketed);

    // Within a cell, in index order: each triangle joins the first of the cell's planes it lies
    // on exactly, or founds a new one (its representative: the plane's smallest index).
    large_vector<uint32_t> representative_of(triangles.size(), no_plane);
    std::vector<uint32_t> planes;  // representatives of the current cell's planes
    for (size_t g = 0; g < keyed.size();) {
        size_t end = g + 1;
        while (end < keyed.size() && keyed[end].same_cell(keyed[g])) ++end;
        planes.clear();
        for (size_t j = g; j < end; ++j) {
            const uint32_t t = keyed[j].triangle;
            for (uint32_t r : planes)
                if (keyed[g].axis_aligned() || on_plane_of(triangles[r], triangles[t])) {
                    representative_of[t] = r;
                    break;
                }
            if (representative_of[t] == no_plane) {
                planes.push_back(t);
                representative_of[t] = t;
            }
        }
        g = end;
    }
    // Ids in order of the representatives' indices; a representative precedes its members.
    for (uint32_t i = 0; i < triangles.size(); ++i) {
        const uint32_t r = representative_of[i];
        if (r == i) {
            out.id[i] = uint32_t(out.representative.size());
            out.representative.push_back(i);
        } else if (r != no_plane) {
            out.id[i] = out.id[r];
        }
    }
    return out;
}

}  // namespace rtt
