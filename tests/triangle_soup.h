// Test geometry given as loose triangles: scenes made of them and the grids, boxes and spheres
// the differential tests are built from.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt::test {

using Tris = std::vector<TriangleVerts>;

/// One mesh with one default material; triangle i of the scene is tris[i].
inline Scene scene_of(const Tris& tris, const char* name = "test") {
    Scene s;
    s.name = name;
    const uint32_t mat = s.add_material(Material{});
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> idx;
    for (const TriangleVerts& t : tris) {
        const auto b = uint32_t(v.size());
        v.insert(v.end(), {t.v0, t.v1, t.v2});
        idx.push_back({b, b + 1, b + 2});
    }
    s.add_mesh(v, idx, mat);
    return s;
}

inline Tris translated(Tris tris, const Vec3f& by) {
    for (TriangleVerts& t : tris) t = {t.v0 + by, t.v1 + by, t.v2 + by};
    return tris;
}

/// nu x nv quads spanned by du, dv from o, two triangles each (shared edges and vertices).
inline void add_grid(Tris& out, Vec3f o, Vec3f du, Vec3f dv, int nu, int nv) {
    const auto at = [&](int a, int b) {
        return o + du * (float(a) / float(nu)) + dv * (float(b) / float(nv));
    };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            out.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            out.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
}

/// The 6 faces of the box [lo, hi], each an n x n grid: a closed mesh.
inline void add_box(Tris& out, Vec3f lo, Vec3f hi, int n) {
    const Vec3f e = hi - lo;
    add_grid(out, lo, {e.x, 0, 0}, {0, e.y, 0}, n, n);
    add_grid(out, {lo.x, lo.y, hi.z}, {e.x, 0, 0}, {0, e.y, 0}, n, n);
    add_grid(out, lo, {0, e.y, 0}, {0, 0, e.z}, n, n);
    add_grid(out, {hi.x, lo.y, lo.z}, {0, e.y, 0}, {0, 0, e.z}, n, n);
    add_grid(out, lo, {0, 0, e.z}, {e.x, 0, 0}, n, n);
    add_grid(out, {lo.x, hi.y, lo.z}, {0, 0, e.z}, {e.x, 0, 0}, n, n);
}

/// A closed UV sphere, nu segments by nv rings (the seam shares its vertices exactly; the
/// triangles touching the poles are zero-area).
inline void add_sphere(Tris& out, Vec3f c, float r, int nu, int nv) {
    const auto p = [&](int i, int j) {
        const float th = std::numbers::pi_v<float> * float(i) / float(nv);
        const float ph = 2.f * std::numbers::pi_v<float> * float(j % nu) / float(nu);
        return c +
               Vec3f{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)} * r;
    };
    for (int i = 0; i < nv; ++i)
        for (int j = 0; j < nu; ++j) {
            out.push_back({p(i, j), p(i, j + 1), p(i + 1, j + 1)});
            out.push_back({p(i, j), p(i + 1, j + 1), p(i + 1, j)});
        }
}

}  // namespace rtt::test
