#include "geom/triangle.h"

#include <gtest/gtest.h>

#include <random>

#include "trace/brute_force.h"

namespace rtt {
namespace {

TEST(Triangle, HitsInsideMissesOutside) {
    const TriangleVerts tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    float t = 0;
    EXPECT_TRUE(intersect_watertight(WatertightRay(Ray{{0.2f, 0.2f, 1}, {0, 0, -1}}), tri, t));
    EXPECT_FLOAT_EQ(t, 1.f);
    EXPECT_FALSE(intersect_watertight(WatertightRay(Ray{{0.8f, 0.8f, 1}, {0, 0, -1}}), tri, t));
    // Both facings are hit (no back-face culling).
    EXPECT_TRUE(intersect_watertight(WatertightRay(Ray{{0.2f, 0.2f, -1}, {0, 0, 1}}), tri, t));
}

TEST(Triangle, RespectsRayInterval) {
    const TriangleVerts tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    float t = 0;
    EXPECT_FALSE(
        intersect_watertight(WatertightRay(Ray{{0.2f, 0.2f, 1}, {0, 0, -1}, 0.f, 0.5f}), tri, t));
    EXPECT_FALSE(
        intersect_watertight(WatertightRay(Ray{{0.2f, 0.2f, 1}, {0, 0, -1}, 1.5f, 9.f}), tri, t));
}

// A ray through the shared edge or shared vertex of a closed fan must hit at least one triangle.
TEST(Triangle, SharedEdgesAndVerticesAreWatertight) {
    // A square pyramid far from the origin, made of 4 sides sharing the apex and edges.
    const Vec3f off{1000.5f, -733.25f, 512.125f};
    const Vec3f apex = off + Vec3f{0, 0, 1};
    const Vec3f base[4] = {off + Vec3f{-1, -1, 0}, off + Vec3f{1, -1, 0}, off + Vec3f{1, 1, 0},
                           off + Vec3f{-1, 1, 0}};
    std::vector<TriangleVerts> tris;
    for (int i = 0; i < 4; ++i) tris.push_back({base[i], base[(i + 1) % 4], apex});
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int misses = 0;
    for (int k = 0; k < 20000; ++k) {
        // Aim at the apex, or at a point exactly on an edge (apex-base corner), from above.
        const Vec3f org = off + Vec3f{u(rng) * 3, u(rng) * 3, 5.f + u(rng)};
        const float s = (u(rng) + 1) * 0.5f;
        const Vec3f target = k % 2 ? apex : apex + (base[k % 4] - apex) * s;
        const Hit h = trace_brute_force(tris, Ray{org, target - org});
        misses += !h.valid();
    }
    EXPECT_EQ(misses, 0);
}

TEST(Triangle, TiesGoToSmallerIndex) {
    const TriangleVerts tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<TriangleVerts> tris = {{{5, 5, 5}, {6, 5, 5}, {5, 6, 5}}, tri, tri};
    const Hit h = trace_brute_force(tris, Ray{{0.2f, 0.2f, 1}, {0, 0, -1}});
    EXPECT_EQ(h.tri, 1u);
}

}  // namespace
}  // namespace rtt
