// Generated meshes for the kd-tree build, single-ray and packet benchmarks (bench_kdbuild,
// bench_ray, bench_packet): deterministic, any size, no files needed.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "rtt/scene.h"

namespace rtt::kdbench {

/// Adds a UV sphere of radius 1 +- 0.08 with bumps to `s`: rings x segments quads, 2 triangles
/// each (the pole rows are zero-area triangles, kept like any mesh would have them).
inline void add_bumpy_sphere(Scene& s, uint32_t material, int rings, int segments) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int r = 0; r <= rings; ++r)
        for (int k = 0; k < segments; ++k) {
            const float th = 3.14159265f * float(r) / float(rings);
            const float ph = 6.28318531f * float(k) / float(segments);
            const float rad = 1.f + 0.05f * std::sin(23.f * th) * std::cos(17.f * ph) +
                              0.03f * std::sin(61.f * ph + 3.f * th);
            v.push_back(
                Vec3f{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)} *
                rad);
        }
    const auto at = [&](int r, int k) { return uint32_t(r * segments + k % segments); };
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < segments; ++k) {
            t.push_back({at(r, k), at(r + 1, k), at(r + 1, k + 1)});
            t.push_back({at(r, k), at(r + 1, k + 1), at(r, k + 1)});
        }
    s.add_mesh(v, t, material);
}

/// The bumpy sphere alone.
inline Scene bumpy_sphere(int rings, int segments) {
    Scene s;
    s.name = "bumpy sphere";
    add_bumpy_sphere(s, s.add_material({}), rings, segments);
    return s;
}

/// A bumpy sphere with about n triangles (rings x 2 rings segments).
inline Scene bumpy_sphere_of(size_t n) {
    const int rings = int(std::lround(std::sqrt(double(n) / 4.0)));
    return bumpy_sphere(rings, 2 * rings);
}

/// n random small triangles (edges about 2 / cbrt(n) of the box) in the cube [-1, 1]^3.
inline Scene triangle_soup(size_t n, unsigned seed = 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1.f, 1.f);
    const float size = 2.f / std::cbrt(float(n));
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (size_t i = 0; i < n; ++i) {
        const Vec3f c{pos(rng), pos(rng), pos(rng)};
        const auto b = uint32_t(v.size());
        for (int k = 0; k < 3; ++k) v.push_back(c + Vec3f{pos(rng), pos(rng), pos(rng)} * size);
        t.push_back({b, b + 1, b + 2});
    }
    Scene s;
    s.name = "triangle soup";
    s.add_mesh(v, t, s.add_material({}));
    return s;
}

}  // namespace rtt::kdbench
