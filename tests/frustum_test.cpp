// The frustum tracer (trace_frustum.h) against trace_ray and the brute-force oracle, ray for
// ray: same closest triangle, same t bit for bit. Regions of 4x4 and 16x16 pixels at K = 1 and
// K = 4 (16 .. 64 samples a side), as the renderer hands them (one origin, shaft = true), and
// tiles it must pass to the packet fallback (several origins, shaft = false).
#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "same_hit.h"
#include "trace/brute_force.h"
#include "trace/trace_frustum.h"
#include "trace/trace_ray.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

struct Fixture {
    Scene scene;
    KdTree tree;
    TriangleArray triangles;
    std::unique_ptr<Tracer> frustum;
    size_t oracle_stride = 1;  ///< Brute force for every n-th ray (big scenes: > 1).

    explicit Fixture(Scene s) : scene(std::move(s)) {
        tree = build_kdtree(scene);
        triangles = gather_triangles(scene);
        frustum = make_tracer("frustum", scene, tree);
    }
};

struct Tally {
    uint64_t rays = 0, hits = 0, segments = 0;
    uint64_t vs_ray = 0;    ///< frustum against trace_ray (hits and shadow bits).
    uint64_t vs_brute = 0;  ///< frustum against brute force (the sampled rays).
};

/// The frustum tracer on one tile against trace_ray and the oracle, then the tile's shadow
/// segments towards `light` against occluded_ray.
void check_tile(const Fixture& f, const RayTile& tile, const Vec3f& light, Tally& t) {
    const size_t n = tile.rays.size();
    std::vector<Hit> got(n, Hit{-1.f, 12345u});
    f.frustum->intersect(tile, got);
    std::vector<Vec3f> points(n);
    std::vector<uint32_t> tris(n);
    std::vector<uint8_t> active(n), visible(n, 7);
    for (size_t i = 0; i < n; ++i) {
        const Ray& r = tile.rays[i];
        const Hit want = trace_ray(f.tree, f.triangles, r);
        t.vs_ray += !same_hit(got[i], want);
        if (i % f.oracle_stride == 0)
            t.vs_brute += !same_hit(got[i], trace_brute_force(f.triangles, r));
        t.hits += want.valid();
        points[i] = r.org + r.dir * want.t;
        tris[i] = want.tri;
        active[i] = want.valid() && i % 7 != 3;
    }
    t.rays += n;
    f.frustum->occluded(
        SegmentTile{tile.width, tile.height, light, points, tris, active, tile.shaft}, visible);
    for (size_t i = 0; i < n; ++i) {
        const bool want =
            active[i] && !occluded_ray(f.tree, f.triangles, shadow_ray(light, points[i]));
        t.vs_ray += visible[i] != uint8_t(want);
        t.segments += active[i];
    }
}

/// Regions of `region` x `region` pixels with aa x aa samples (side region * aa), as the
/// renderer makes them (CameraRays::region_rays), one shaft tile each.
void check_camera(const Fixture& f, const Camera& cam, int width, int height, int aa, int region,
                  const Vec3f& light, Tally& t) {
    const CameraRays cr(cam, width, height, aa);
    const int side = region * aa;
    std::vector<Ray> rays(size_t(side * side));
    for (int ty = 0; ty < height; ty += region)
        for (int tx = 0; tx < width; tx += region) {
            cr.region_rays(tx / 4, ty / 4, region / 4, region / 4, rays);
            check_tile(f, RayTile{side, side, rays, true}, light, t);
        }
}

/// The views every scene is checked with: K = 1 and K = 4, regions of 4 and 16 pixels.
void check_views(const Fixture& f, const Camera& cam, int width, int height, const Vec3f& light,
                 Tally& t) {
    for (const int aa : {1, 4})
        for (const int region : {4, 16}) check_camera(f, cam, width, height, aa, region, light, t);
}

void report(const char* what, const Tally& t) {
    std::printf(
        "%s: %llu rays (%llu hits), %llu segments; frustum mismatches: %llu against "
        "trace_ray, %llu against brute force\n",
        what, (unsigned long long)t.rays, (unsigned long long)t.hits,
        (unsigned long long)t.segments, (unsigned long long)t.vs_ray,
        (unsigned long long)t.vs_brute);
    EXPECT_EQ(t.vs_ray, 0u);
    EXPECT_EQ(t.vs_brute, 0u);
}

/// n random triangles of size ~`size` in [-1, 1]^3 around `center`.
Scene soup(int n, float size, const Vec3f& center, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    test::Tris tris;
    for (int i = 0; i < n; ++i) {
        const Vec3f c = center + Vec3f{u(rng), u(rng), u(rng)};
        const auto v = [&] { return c + Vec3f{u(rng), u(rng), u(rng)} * size; };
        tris.push_back({v(), v(), v()});
    }
    return test::scene_of(tris);
}

TEST(FrustumTracer, IsRegistered) {
    const auto kinds = tracer_kinds();
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), "frustum"), kinds.end());
    const Fixture f(soup(10, 0.3f, Vec3f{0.f}, 1));
    EXPECT_EQ(f.frustum->name(), "frustum");
}

TEST(FrustumTracer, RandomSoupsMatchTraceRay) {
    for (const unsigned seed : {41u, 42u, 43u}) {
        const Fixture f(soup(2000, 0.2f, Vec3f{0.f}, seed));
        Tally t;
        check_views(f, Camera{{2.5f, 1.5f, 3.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 50.f}, 32, 32,
                    {3.f, 4.f, -2.f}, t);
        // From inside the soup, looking along -z: rays of every octant.
        check_camera(f, Camera{{0.1f, 0.2f, 0.3f}, {0.1f, 0.2f, -1.f}, {0.f, 1.f, 0.f}, 120.f}, 32,
                     32, 2, 16, {0.f, 3.f, 0.f}, t);
        report("soup", t);
        EXPECT_GT(t.hits, t.rays / 4);
    }
}

TEST(FrustumTracer, GridsThroughEdgesVerticesAndSplitPlanes) {
    // Unit quads on integer planes, coplanar duplicates (ties broken by index); the camera sits
    // on integer coordinates (split planes) and looks straight down z, so central rays have
    // zero x / y components and pass through vertices and shared edges; then edge-on.
    for (const Vec3f origin : {Vec3f{0.f}, Vec3f{4096.f, -1536.5f, 2048.f}}) {
        test::Tris tris;
        for (int z = 0; z < 3; ++z)
            test::add_grid(tris, origin + Vec3f{0.f, 0.f, float(z)}, {12.f, 0.f, 0.f},
                           {0.f, 12.f, 0.f}, 12, 12);
        test::add_grid(tris, origin, {12.f, 0.f, 0.f}, {0.f, 12.f, 0.f}, 12, 12);  // duplicate
        const Fixture f(test::scene_of(tris));
        Tally t;
        check_views(f,
                    Camera{origin + Vec3f{6.f, 6.f, 9.f},
                           origin + Vec3f{6.f, 6.f, 0.f},
                           {0.f, 1.f, 0.f},
                           70.f},
                    32, 32, origin + Vec3f{3.f, 7.f, 5.5f}, t);
        check_views(f,
                    Camera{origin + Vec3f{-4.f, 6.f, 1.f},
                           origin + Vec3f{6.f, 6.f, 1.f},
                           {0.f, 0.f, 1.f},
                           60.f},
                    16, 16, origin + Vec3f{6.f, 3.f, 2.5f}, t);
        report(origin.x == 0.f ? "grid" : "grid far from origin", t);
        EXPECT_GT(t.hits, t.rays / 4);
    }
}

TEST(FrustumTracer, ClosedSphereFarFromOriginIsWatertight) {
    const Vec3f c{20000.f, -12000.f, 7000.f};
    test::Tris tris;
    test::add_sphere(tris, c, 1.f, 80, 40);
    const Fixture f(test::scene_of(tris));
    Tally t;
    check_views(
        f, Camera{c + Vec3f{0.1f, 0.2f, 0.3f}, c + Vec3f{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 120.f},
        32, 32, c + Vec3f{0.f, 0.5f, 0.f}, t);
    EXPECT_EQ(t.hits, t.rays);  // no ray slipped out between triangles
    check_views(f, Camera{c + Vec3f{0.f, 0.f, 2.5f}, c, {0.f, 1.f, 0.f}, 60.f}, 16, 16,
                c + Vec3f{2.f, 2.f, 2.f}, t);
    report("sphere far from origin", t);
}

TEST(FrustumTracer, EmptyRegionsMissEverything) {
    const Fixture f(soup(500, 0.2f, Vec3f{0.f}, 7));
    Tally t;
    check_views(f, Camera{{0.f, 0.f, 5.f}, {0.f, 0.f, 10.f}, {0.f, 1.f, 0.f}, 40.f}, 32, 32,
                {0.f, 3.f, 0.f}, t);
    report("looking away", t);
    EXPECT_EQ(t.hits, 0u);
}

TEST(FrustumTracer, TilesWithoutOneOriginGoToPackets) {
    // Random origins and directions (some axis-parallel), finite intervals, shaft = false; and
    // the same rays marked as a shaft, which trace_frustum() must refuse.
    const Fixture f(soup(1000, 0.2f, Vec3f{0.f}, 11));
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    Tally t;
    std::vector<Ray> rays(64);
    std::vector<Hit> hits(64);
    for (int k = 0; k < 100; ++k) {
        for (Ray& r : rays) {
            r.org = Vec3f{u(rng), u(rng), u(rng)};
            r.dir = Vec3f{u(rng), u(rng), u(rng)};
            if (rng() % 4 == 0) r.dir[int(rng() % 3)] = 0.f;
            r.tmin = rng() % 3 ? 0.f : std::fabs(u(rng));
            r.tmax = rng() % 3 ? pos_inf : std::fabs(u(rng)) * 3.f;
        }
        EXPECT_FALSE(trace_frustum(f.tree, f.triangles, rays, 8, 8, hits));
        check_tile(f, RayTile{8, 8, rays, k % 2 == 0}, {0.f, 3.f, 0.f}, t);
    }
    report("random rays", t);
}

TEST(FrustumTracer, SharedOriginWithPerRayIntervals) {
    // One origin, random directions of every octant in one tile, random tmin / tmax per ray:
    // rays end early, some start late.
    const Fixture f(soup(1500, 0.2f, Vec3f{0.f}, 13));
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    Tally t;
    std::vector<Ray> rays(256);
    for (int k = 0; k < 40; ++k) {
        const Vec3f org{u(rng) * 1.5f, u(rng) * 1.5f, u(rng) * 1.5f};
        for (Ray& r : rays) {
            r.org = org;
            r.dir = Vec3f{u(rng), u(rng), u(rng)};
            if (rng() % 8 == 0) r.dir[int(rng() % 3)] = rng() % 2 ? 0.f : -0.f;
            r.tmin = rng() % 3 ? 0.f : std::fabs(u(rng)) * 0.5f;
            r.tmax = rng() % 3 ? pos_inf : std::fabs(u(rng)) * 2.f;
        }
        check_tile(f, RayTile{16, 16, rays, true}, {0.f, 3.f, 0.f}, t);
    }
    report("one origin, random rays", t);
    EXPECT_GT(t.hits, 0u);
}

TEST(FrustumTracer, BuiltinScenesMatchTraceRay) {
    for (const BuiltinSceneInfo& info : builtin_scenes()) {
        Fixture f(make_builtin_scene(info.name));
        f.oracle_stride = 97;
        ASSERT_TRUE(f.scene.camera.has_value());
        Tally t;
        check_views(f, *f.scene.camera, 48, 32, f.scene.lights[0].position, t);
        check_camera(f, default_camera_for(f.scene.bounds()), 32, 32, 1, 16,
                     f.scene.lights[1].position, t);
        report(info.name.c_str(), t);
        EXPECT_GT(t.hits, t.rays / 10);
    }
}

}  // namespace
}  // namespace rtt
