// The library's entry points for code that is not the renderer: scenes from arrays, arbitrary
// ray batches (intersect_rays, visible_rays) on every tracer kind, and their errors.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "agreement.h"
#include "geom/triangle.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"
#include "trace/ray_batches.h"
#include "trace/ray_order.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

/// Rays from random points around `box` towards random points inside it, with random
/// [tmin, tmax] (a third unbounded): misses, grazing rays and rays cut short all occur.
std::vector<Ray> random_rays(const Bbox3f& box, size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const Vec3f d = box.diagonal();
    const auto in_box = [&](float grow) {
        return box.lo - d * grow + Vec3f{u(rng), u(rng), u(rng)} * d * (1.f + 2.f * grow);
    };
    std::vector<Ray> rays(n);
    for (size_t i = 0; i < n; ++i) {
        const Vec3f org = in_box(0.5f);
        Vec3f dir = in_box(0.f) - org;
        if (dir == Vec3f{0.f}) dir = {1.f, 0.f, 0.f};
        const float tmin = u(rng) < 0.5f ? 0.f : 0.3f * u(rng);
        const float tmax = i % 3 == 0 ? pos_inf : tmin + 1.2f * u(rng);
        rays[i] = Ray{org, dir, tmin, tmax};
    }
    return rays;
}

Scene test_scene() {
    test::Tris tris;
    test::add_box(tris, {-1, -1, -1}, {1, 1, 1}, 6);
    test::add_sphere(tris, {0.2f, 0.1f, 0.f}, 0.6f, 24, 12);
    test::add_grid(tris, {-2, -1, -2}, {4, 0, 0}, {0, 0, 4}, 9, 9);
    return test::scene_of(tris);
}

/// The reference's closest hits, one ray after another in the caller's order.
std::vector<Hit> one_by_one(const Tracer& reference, std::span<const Ray> rays) {
    std::vector<Hit> hits(rays.size());
    for (size_t i = 0; i < rays.size(); ++i)
        reference.intersect_arbitrary(rays.subspan(i, 1), std::span(&hits[i], 1));
    return hits;
}

/// How many of intersect_rays' hits and visible_rays' answers of `tracer` differ from
/// `expected`, and the rays intersect_rays counted.
struct BatchMismatches {
    size_t closest = 0, visible = 0;
    uint64_t counted = 0;
};
BatchMismatches batch_mismatches(const Tracer& tracer, std::span<const Ray> rays,
                                 const std::vector<Hit>& expected) {
    std::vector<Hit> got(rays.size());
    std::vector<uint8_t> visible(rays.size());
    TraceStats stats;
    intersect_rays(tracer, rays, got, &stats);
    visible_rays(tracer, rays, visible);
    BatchMismatches m;
    for (size_t i = 0; i < rays.size(); ++i) {
        m.closest += !(got[i] == expected[i]);
        m.visible += visible[i] != !expected[i].valid();
    }
    m.counted = stats.rays;
    return m;
}

TEST(LibraryApi, IntersectRaysAgreesWithBruteForceOnEveryKind) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    // Not a multiple of any packet width or of the batch chunk.
    const std::vector<Ray> rays = random_rays(scene.bounds(), 3001, 7);
    std::vector<Hit> expected(rays.size());
    intersect_rays(*make_tracer("brute", scene, tree), rays, expected);
    size_t hits = 0;
    for (const Hit& h : expected) hits += h.valid();
    ASSERT_GT(hits, rays.size() / 4);
    ASSERT_LT(hits, rays.size());
    for (const std::string& kind : tracer_kinds()) {
        if (differential::tie_breaks_differ(kind)) continue;
        std::vector<Hit> got(rays.size());
        TraceStats stats;
        intersect_rays(*make_tracer(kind, scene, tree), rays, got, &stats);
        size_t mismatches = 0;
        for (size_t i = 0; i < rays.size(); ++i) mismatches += !(got[i] == expected[i]);
        EXPECT_EQ(mismatches, 0u) << kind;
        EXPECT_EQ(stats.rays, rays.size()) << kind;
    }
}

// Kinds that say they never read the kd-tree give the same answers handed an empty one.
TEST(LibraryApi, KindsWithoutKdTreeAnswerWithAnEmptyOne) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene), none;
    const std::vector<Ray> rays = random_rays(scene.bounds(), 1001, 11);
    std::vector<Hit> expected(rays.size());
    intersect_rays(*make_tracer("brute", scene, tree), rays, expected);
    EXPECT_TRUE(tracer_uses_kdtree("rtt"));
    EXPECT_TRUE(tracer_uses_kdtree("packet"));
    EXPECT_FALSE(tracer_uses_kdtree("bvh"));
    EXPECT_THROW(tracer_uses_kdtree("no-such-kind"), Error);
    int without = 0;
    for (const std::string& kind : tracer_kinds()) {
        if (tracer_uses_kdtree(kind) || differential::tie_breaks_differ(kind)) continue;
        ++without;
        std::vector<Hit> got(rays.size());
        intersect_rays(*make_tracer(kind, scene, none), rays, got);
        size_t mismatches = 0;
        for (size_t i = 0; i < rays.size(); ++i) mismatches += !(got[i] == expected[i]);
        EXPECT_EQ(mismatches, 0u) << kind;
    }
    EXPECT_GE(without, 2);  // brute and bvh at least
}

TEST(LibraryApi, VisibleRaysEqualsOccludedSegments) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    const Vec3f light{0.3f, 3.f, 0.5f};
    // Hit points of random rays, as the renderer's shadow tiles hold them.
    std::vector<Ray> probes = random_rays(scene.bounds(), 2000, 11);
    std::vector<Hit> probe_hits(probes.size());
    for (Ray& r : probes) r.tmin = 0.f, r.tmax = pos_inf;
    const auto ray_tracer = make_tracer("ray", scene, tree);
    intersect_rays(*ray_tracer, probes, probe_hits);
    std::vector<Vec3f> points;
    std::vector<uint32_t> tris;
    for (size_t i = 0; i < probes.size(); ++i)
        if (probe_hits[i].valid()) {
            points.push_back(probes[i].org + probes[i].dir * probe_hits[i].t);
            tris.push_back(probe_hits[i].tri);
        }
    ASSERT_GT(points.size(), 200u);
    std::vector<Ray> segments;
    for (const Vec3f& p : points) segments.push_back(shadow_ray(light, p));
    const std::vector<uint8_t> active(points.size(), 1);
    const SegmentTile tile{int(points.size()), 1, light, points, tris, active, false};
    for (const std::string& kind : tracer_kinds()) {
        if (differential::tie_breaks_differ(kind)) continue;
        const auto tracer = make_tracer(kind, scene, tree);
        std::vector<uint8_t> expected(points.size()), got(points.size());
        tracer->occluded(tile, expected);
        visible_rays(*tracer, segments, got);
        size_t mismatches = 0, visible = 0;
        for (size_t i = 0; i < points.size(); ++i) {
            mismatches += expected[i] != got[i];
            visible += got[i];
        }
        EXPECT_EQ(mismatches, 0u) << kind;
        EXPECT_GT(visible, 0u) << kind;
        EXPECT_LT(visible, points.size()) << kind;
    }
}

TEST(LibraryApi, VisibleRaysAgreeWithClosestHits) {
    // Arbitrary rays, bounded and not: each kind's any-hit path (visible_arbitrary) answers
    // what the reference's closest hit says.
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    std::vector<Ray> rays = random_rays(scene.bounds(), 3000, 17);
    for (size_t i = 0; i < rays.size(); i += 2) rays[i].tmax = 0.5f;
    std::vector<Hit> closest(rays.size());
    intersect_rays(*make_tracer("ray", scene, tree), rays, closest);
    size_t blocked = 0;
    for (const Hit& h : closest) blocked += h.valid();
    ASSERT_GT(blocked, 100u);
    ASSERT_LT(blocked, rays.size() - 100u);
    for (const std::string& kind : tracer_kinds()) {
        std::vector<uint8_t> visible(rays.size());
        TraceStats stats;
        visible_rays(*make_tracer(kind, scene, tree), rays, visible, &stats);
        size_t mismatches = 0;
        for (size_t i = 0; i < rays.size(); ++i) mismatches += visible[i] != !closest[i].valid();
        EXPECT_EQ(mismatches, 0u) << kind;
        EXPECT_EQ(stats.rays, rays.size()) << kind;
    }
}

// Rays that start on a triangle, at a vertex or just past it with tmin = 0: the triangle's
// box lies at or barely behind the origin, where only the box tests' widening (the BVH's
// far side in one fused operation, trace_bvh.h's far_margin) keeps it entered. Every kind
// gives the reference's answer, t = 0 hits included.
TEST(LibraryApi, RaysStartingOnTrianglesMatchTheReference) {
    test::Tris tris;
    test::add_sphere(tris, {0.3f, -0.2f, 0.1f}, 0.7f, 20, 10);
    test::add_grid(tris, {-1.5f, -1.f, -1.5f}, {3, 0, 0}, {0, 0, 3}, 7, 7);  // axis-aligned
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> u(0.f, 1.f), s(-1.f, 1.f);
    for (int i = 0; i < 60; ++i) {  // a soup of small triangles at random slants
        const Vec3f c{s(rng), s(rng), s(rng)};
        tris.push_back({c, c + Vec3f{s(rng), s(rng), s(rng)} * 0.3f,
                        c + Vec3f{s(rng), s(rng), s(rng)} * 0.3f});
    }
    const Scene scene = test::scene_of(tris);
    const KdTree tree = build_kdtree(scene);
    std::vector<Ray> rays;
    for (const TriangleVerts& t : tris) {
        for (int k = 0; k < 6; ++k) {
            float b1 = u(rng), b2 = u(rng);
            if (b1 + b2 > 1.f) b1 = 1.f - b1, b2 = 1.f - b2;
            // On the triangle, or at one of its vertices.
            const Vec3f on = k < 3 ? t.v0 + (t.v1 - t.v0) * b1 + (t.v2 - t.v0) * b2
                                   : (k == 3   ? t.v0
                                      : k == 4 ? t.v1
                                               : t.v2);
            Vec3f dir{s(rng), s(rng), s(rng)};
            if (dir == Vec3f{0.f}) dir = {0.f, 1.f, 0.f};
            rays.push_back(Ray{on, dir, 0.f, pos_inf});
            // Just past it: the triangle's box a hair behind the origin.
            rays.push_back(Ray{on + dir * 0x1p-20f, dir, 0.f, pos_inf});
        }
    }
    const std::vector<Hit> expected = one_by_one(*make_tracer("ray", scene, tree), rays);
    size_t at_zero = 0;
    for (const Hit& h : expected) at_zero += h.valid() && h.t == 0.f;
    ASSERT_GT(at_zero, rays.size() / 20);  // the case this test is for occurs
    for (const std::string& kind : tracer_kinds()) {
        if (differential::tie_breaks_differ(kind)) continue;
        const BatchMismatches m = batch_mismatches(*make_tracer(kind, scene, tree), rays, expected);
        EXPECT_EQ(m.closest, 0u) << kind;
        EXPECT_EQ(m.visible, 0u) << kind;
    }
}

// A batch of reorder_min_rays or more is traced grouped by octant and origin (ray_order.h):
// every ray still gets its own answer, closest hit and visibility, on every kind.
TEST(LibraryApi, ReorderedBatchesGiveEachRayItsOwnAnswer) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    const std::vector<Ray> rays = random_rays(scene.bounds(), reorder_min_rays + 3001, 23);
    ASSERT_FALSE(coherent_order(rays).empty());
    const std::vector<Hit> expected = one_by_one(*make_tracer("ray", scene, tree), rays);
    for (const std::string& kind : tracer_kinds()) {
        if (differential::tie_breaks_differ(kind)) continue;
        const BatchMismatches m = batch_mismatches(*make_tracer(kind, scene, tree), rays, expected);
        EXPECT_EQ(m.closest, 0u) << kind;
        EXPECT_EQ(m.visible, 0u) << kind;
        EXPECT_EQ(m.counted, rays.size()) << kind;
    }
}

// An any-hit batch is ordered or not after a probe that has already answered some of its
// chunks (ray_batches.h): either way every ray gets its own answer, counted once.
TEST(LibraryApi, ProbedAnyHitBatchesGiveEachRayItsOwnAnswer) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    // Not a multiple of the chunk, so the last chunk is short.
    const std::vector<Ray> rays = random_rays(scene.bounds(), 4 * reorder_min_rays + 517, 31);
    const std::vector<Hit> closest = one_by_one(*make_tracer("ray", scene, tree), rays);
    for (const char* kind : {"bvh", "rtt"}) {
        const auto tracer = make_tracer(kind, scene, tree);
        for (const double order_above : {0.0, double(INFINITY)}) {
            std::vector<uint8_t> visible(rays.size(), 2);
            TraceStats stats;
            visible_rays_probed(*tracer, rays, visible, &stats, order_above);
            size_t mismatches = 0;
            for (size_t i = 0; i < rays.size(); ++i)
                mismatches += visible[i] != !closest[i].valid();
            EXPECT_EQ(mismatches, 0u) << kind << " " << order_above;
            EXPECT_EQ(stats.rays, rays.size()) << kind << " " << order_above;
        }
    }
}

TEST(LibraryApi, CoherentOrderGroupsByOctantThenOrigin) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<Ray> rays(reorder_min_rays);
    for (Ray& r : rays) r = Ray{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    EXPECT_TRUE(coherent_order(std::span(rays).first(reorder_min_rays - 1)).empty());
    const auto is_permutation = [](const large_vector<uint32_t>& order) {
        std::vector<uint32_t> sorted(order.begin(), order.end());
        std::sort(sorted.begin(), sorted.end());
        for (size_t i = 0; i < sorted.size(); ++i)
            if (sorted[i] != i) return false;
        return true;
    };
    // Origins whose extent overflows float: that axis is one cell, and nothing overflows.
    std::vector<Ray> far = rays;
    far[7].org.x = -3e38f;
    far[8].org.x = 3e38f;
    const auto far_order = coherent_order(far);
    EXPECT_EQ(far_order.size(), far.size());
    EXPECT_TRUE(is_permutation(far_order));
    const auto order = coherent_order(rays);
    ASSERT_EQ(order.size(), rays.size());
    EXPECT_TRUE(is_permutation(order));
    {  // A batch the sort splits into parts (one per thread): the same order in four as in one.
        std::vector<Ray> many(4 * 65536 + 7);
        for (Ray& r : many) r = Ray{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
        large_vector<uint32_t> four, one;
        tbb::task_arena(4).execute([&] { four = coherent_order(many); });
        tbb::task_arena(1).execute([&] { one = coherent_order(many); });
        EXPECT_TRUE(is_permutation(four));
        EXPECT_TRUE(four == one);
    }
    // Rays that already come in their origins' order are traced as they come: all from one
    // point (a camera's), or sorted along x.
    std::vector<Ray> camera = rays, along_x = rays;
    for (Ray& r : camera) r.org = {0.5f, 0.5f, 0.5f};
    EXPECT_TRUE(coherent_order(camera).empty());
    std::sort(along_x.begin(), along_x.end(),
              [](const Ray& a, const Ray& b) { return a.org.x < b.org.x; });
    for (size_t i = 0; i < along_x.size(); ++i) along_x[i].org.y = along_x[i].org.z = 0.f;
    EXPECT_TRUE(coherent_order(along_x).empty());
    const auto octant = [](const Ray& r) {
        return int(r.dir.x < 0.f) | int(r.dir.y < 0.f) << 1 | int(r.dir.z < 0.f) << 2;
    };
    size_t octant_changes = 0;
    for (size_t i = 1; i < order.size(); ++i) {
        EXPECT_LE(octant(rays[order[i - 1]]), octant(rays[order[i]]));
        octant_changes += octant(rays[order[i - 1]]) != octant(rays[order[i]]);
    }
    EXPECT_EQ(octant_changes, 7u);
    // Neighbours in the order start closer together than neighbours in the caller's order.
    double apart_in_order = 0, apart_as_given = 0;
    for (size_t i = 10; i < order.size(); ++i) {
        apart_in_order += length(rays[order[i]].org - rays[order[i - 1]].org);
        apart_as_given += length(rays[i].org - rays[i - 1].org);
    }
    EXPECT_LT(apart_in_order * 4, apart_as_given);
}

TEST(LibraryApi, RayBatchesRefuseBadInput) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    const auto tracer = make_tracer("packet", scene, tree);
    std::vector<Hit> hits(2);
    std::vector<uint8_t> visible(2);
    const Ray good{{0, 0, 5}, {0, 0, -1}, 0.f, pos_inf};
    const auto refused = [&](Ray bad) {
        const std::vector<Ray> rays = {good, bad};
        bool intersect_threw = false, visible_threw = false;
        try {
            intersect_rays(*tracer, rays, hits);
        } catch (const Error&) {
            intersect_threw = true;
        }
        try {
            visible_rays(*tracer, rays, visible);
        } catch (const Error&) {
            visible_threw = true;
        }
        return intersect_threw && visible_threw;
    };
    EXPECT_TRUE(refused({{0, 0, 5}, {0, 0, 0}, 0.f, pos_inf}));
    EXPECT_TRUE(refused({{0, NAN, 5}, {0, 0, -1}, 0.f, pos_inf}));
    EXPECT_TRUE(refused({{0, 0, 5}, {0, pos_inf, -1}, 0.f, pos_inf}));
    EXPECT_TRUE(refused({{0, 0, 5}, {0, 0, -1}, 2.f, 1.f}));
    EXPECT_TRUE(refused({{0, 0, 5}, {0, 0, -1}, NAN, 1.f}));
    EXPECT_FALSE(refused(good));
    const std::vector<Ray> three(3, good);
    EXPECT_THROW(intersect_rays(*tracer, three, hits), Error);
    EXPECT_THROW(visible_rays(*tracer, three, visible), Error);
    intersect_rays(*tracer, {}, std::span<Hit>{});  // an empty batch is fine
}

TEST(LibraryApi, RttOptionsChangeTheWorkNeverTheAnswers) {
    const Scene scene = test_scene();
    const KdTree tree = build_kdtree(scene);
    const auto reference = make_tracer("ray", scene, tree);
    const RttOptions configs[] = {
        {},
        {.rules = RttRules::paper},
        {.walk_budget_base = 1, .walk_budget_per_sample = 0},
        {.walk_budget_base = 100000, .walk_budget_per_sample = 100},
        {.deferred_budget_base = 1},
        {.lean_max_samples = 0},
        {.lean_max_samples = rtt_max_samples_per_tile},
        // declined tiles through the BVH from the start (these tiles' rays lie sparsely)
        {.walk_budget_base = 1, .walk_budget_per_sample = 0, .bvh_at_setup = true},
    };
    const Camera camera{{3.f, 2.f, 4.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 55.f};
    std::vector<uint64_t> answered, through_bvh;
    for (const RttOptions& options : configs) {
        const auto rtt = make_rtt_tracer(scene, tree, options);
        RttStats stats;
        size_t mismatches = 0;
        for (int aa : {1, 2, 4}) {
            const CameraRays rays(camera, 96, 64, aa);
            for (int ty = 0; ty < 16; ++ty)
                for (int tx = 0; tx < 24; ++tx) {
                    const std::vector<Ray> tile = differential::primary_tile(rays, tx, ty);
                    const int side = 4 * aa;
                    std::vector<Hit> got(tile.size()), want(tile.size());
                    rtt->intersect(RayTile{side, side, tile, true}, got,
                                   TraceContext{.rtt = &stats});
                    reference->intersect(RayTile{side, side, tile, true}, want);
                    for (size_t i = 0; i < tile.size(); ++i) mismatches += !(got[i] == want[i]);
                }
        }
        EXPECT_EQ(mismatches, 0u);
        answered.push_back(stats.answered);
        through_bvh.push_back(stats.bvh_rays);
    }
    EXPECT_GT(answered[0], 0u);
    EXPECT_GT(through_bvh.back(), 0u);
    EXPECT_LT(answered[2], answered[0]);  // a one-node walk answers less
    EXPECT_THROW(make_rtt_tracer(scene, tree, {.walk_budget_base = 0}), Error);
    EXPECT_THROW(make_rtt_tracer(scene, tree, {.lean_max_samples = -1}), Error);
    EXPECT_THROW(make_rtt_tracer(scene, tree, {.deferred_budget_base = 0}), Error);
}

TEST(LibraryApi, SceneFromMeshIsValidated) {
    const std::vector<Vec3f> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Scene ok = Scene::from_mesh(v, std::vector<TriangleIndices>{{0, 1, 2}}, "tri");
    EXPECT_EQ(ok.triangle_count(), 1u);
    EXPECT_EQ(ok.name, "tri");
    EXPECT_EQ(Scene::from_mesh(v, {}).triangle_count(), 0u);  // empty: renders background
    EXPECT_THROW(Scene::from_mesh(v, std::vector<TriangleIndices>{{0, 1, 3}}), Error);
    const std::vector<Vec3f> nan = {{0, 0, 0}, {1, NAN, 0}, {0, 1, 0}};
    EXPECT_THROW(Scene::from_mesh(nan, std::vector<TriangleIndices>{{0, 1, 2}}), Error);
}

}  // namespace
}  // namespace rtt
