// The single ray/triangle routine every tracer calls: the watertight test of
// Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
//
// Why one routine: tracers must agree ray for ray, including on ties. Each tracer evaluates
// exactly these float operations in exactly this order (SIMD versions lane by lane), compiled
// without FMA contraction (-ffp-contract=off), so a triangle is hit or missed, and at which t,
// identically everywhere.
//
// The ray is sheared so that it becomes the +z axis; the triangle's 2D edge functions U, V, W
// around the origin decide the hit. Each is a difference of products taken with Kahan's fused
// multiply-subtracts (difference_of_products): within 1.5 ulps of the exact difference of the
// sheared floats, so its sign, and whether it is zero, are exact. A shared edge therefore has
// exactly opposite signs in the two triangles that share it, and a ray through an edge or
// vertex hits at least one of them: closed meshes are watertight. We accept U, V, W == 0; a ray
// exactly through an edge then hits both triangles and the tie at equal t goes to the smaller
// index. Plain float differences would also be watertight, but they cancel on a thin triangle
// met at a grazing angle and t, their weighted sum of depths, then misses the hit's true
// distance by more than the trees' margins (docs/design.md, "Assumptions").
//
// The fused operations are the one exception to -ffp-contract=off: a fused multiply-add is
// correctly rounded wherever it runs (an instruction, or std::fma in software), so it keeps
// every tracer's bits identical.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/large_arrays.h"
#include "core/platform.h"
#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

struct TriangleVerts {
    Vec3f v0, v1, v2;
};

/// A scene's vertex triples on huge pages: a tracer's copy of a large scene is tens of MB, and
/// as a plain vector each of its 4 KiB pages faulted anew for every tracer made
/// (docs/benchmarks.md, "First image").
using TriangleArray = large_vector<TriangleVerts>;

/// The vertices of the scene's triangle i.
inline TriangleVerts triangle_verts(const Scene& scene, size_t i) {
    const TriangleIndices& t = scene.triangles[i];
    return {scene.vertices[t[0]], scene.vertices[t[1]], scene.vertices[t[2]]};
}

/// Vertex triples of every triangle of the scene, in triangle-index order.
TriangleArray gather_triangles(const Scene& scene);

/// Per-ray constants of the watertight test: axis permutation and shear.
struct WatertightRay {
    Vec3f org;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0.f, sy = 0.f, sz = 1.f;
    float tmin = 0.f, tmax = pos_inf;

    WatertightRay() = default;
    /// The constants as made elsewhere (lane by lane in packets and batches).
    WatertightRay(const Vec3f& org_, int kx_, int ky_, int kz_, float sx_, float sy_, float sz_,
                  float tmin_, float tmax_)
        : org(org_),
          kx(kx_),
          ky(ky_),
          kz(kz_),
          sx(sx_),
          sy(sy_),
          sz(sz_),
          tmin(tmin_),
          tmax(tmax_) {}
    explicit WatertightRay(const Ray& ray) : org(ray.org), tmin(ray.tmin), tmax(ray.tmax) {
        kz = max_abs_axis(ray.dir);
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        if (ray.dir[kz] < 0.f) std::swap(kx, ky);  // keep the winding of the 2D edge functions
        sx = ray.dir[kx] / ray.dir[kz];
        sy = ray.dir[ky] / ray.dir[kz];
        sz = 1.f / ray.dir[kz];
    }
};

/// a * b - c with one rounding (the scalar form of simd's fused_mul_sub).
RTT_FORCEINLINE float fused_mul_sub(float a, float b, float c) {
    return std::fma(a, b, -c);
}

/// a * b - c * d within 1.5 ulps (Kahan: c * d's rounding error, recovered exactly by a fused
/// multiply-subtract, is taken back from the fused a * b - round(c * d)). For float and every
/// vfloat, in the same operations, so every form of the test gets the same bits.
template <typename F>
RTT_FORCEINLINE F difference_of_products(F a, F b, F c, F d) {
    const F cd = c * d;
    const F cd_error = fused_mul_sub(c, d, cd);  // c * d - cd, exactly
    return fused_mul_sub(a, b, cd) - cd_error;
}

/// Returns true and sets t when the ray hits the triangle at t in [tmin, tmax].
RTT_FORCEINLINE bool intersect_watertight(const WatertightRay& r, const TriangleVerts& tri,
                                          float& t) {
    const Vec3f a = tri.v0 - r.org;
    const Vec3f b = tri.v1 - r.org;
    const Vec3f c = tri.v2 - r.org;
    const float ax = a[r.kx] - r.sx * a[r.kz];
    const float ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz];
    const float by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz];
    const float cy = c[r.ky] - r.sy * c[r.kz];
    const float u = difference_of_products(cx, by, cy, bx);
    const float v = difference_of_products(ax, cy, ay, cx);
    const float w = difference_of_products(bx, ay, by, ax);
    if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
    const float det = (u + v) + w;
    if (det == 0.f) return false;
    const float az = r.sz * a[r.kz];
    const float bz = r.sz * b[r.kz];
    const float cz = r.sz * c[r.kz];
    const float tt = ((u * az + v * bz) + w * cz) / det;
    if (!(tt >= r.tmin && tt <= r.tmax)) return false;  // also rejects NaN
    t = tt;
    return true;
}

}  // namespace rtt
