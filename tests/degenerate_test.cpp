// Degenerate geometry and degenerate views: every tracer kind must render them without crashing
// and agree with brute force (with "ray" on the big mesh) on every sample: the closest triangle
// and t bit for bit, and every shadow bit. Batches are built as the renderer builds them
// (tests/agreement.h). Embree kinds are run too but not compared: Embree breaks exact ties
// (equal t on duplicated and coplanar triangles) its own way, so only "no crash" is asked of it.
// Each scene is also rendered once through render() with the default tracer.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "agreement.h"
#include "geom/triangle.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "rtt/tracer.h"
#include "test_env.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

using differential::AgreementView;
using test::add_box;
using test::add_grid;
using test::add_sphere;
using test::scene_of;
using test::Tris;

/// Runs every tracer kind over each view and requires exact agreement with `reference`; also
/// requires that the views see something (agreement on nothing but misses proves little).
void expect_agreement(const Scene& scene, const std::vector<AgreementView>& views,
                      const std::string& reference = "brute", double min_hit_fraction = 0.2) {
    const KdTree tree = build_kdtree(scene);
    for (size_t v = 0; v < views.size(); ++v) {
        SCOPED_TRACE("view " + std::to_string(v));
        const auto results = differential::compare_tracers(scene, tree, reference, views[v]);
        ASSERT_EQ(results.size(), tracer_kinds().size());
        const differential::Agreement& ref = results.at(reference);
        EXPECT_GE(double(ref.hits), min_hit_fraction * double(ref.samples))
            << "view sees too little";
        for (const auto& [kind, a] : results) {
            if (differential::tie_breaks_differ(kind)) continue;
            EXPECT_EQ(a.samples, ref.samples) << kind;
            EXPECT_EQ(a.hit_mismatches, 0u) << kind << ": " << a.first_mismatch;
            EXPECT_EQ(a.shadow_mismatches, 0u) << kind << ": " << a.first_mismatch;
        }
        // The whole renderer (shading, shadows, mirrors) on the same view must not misbehave.
        Scene lit = scene;
        for (const Vec3f& l : views[v].lights)
            lit.lights.push_back(make_point_light(l, scene.bounds(), views[v].lights.size()));
        RenderOptions opt;
        opt.camera = views[v].camera;
        opt.width = views[v].width;
        opt.height = views[v].height;
        opt.threads = 1;
        opt.hits_buffer = opt.shadow_buffer = true;
        const auto tracer = make_tracer("rtt", lit, tree);
        const RenderResult r = render(lit, *tracer, opt);
        EXPECT_EQ(r.hits.size(), size_t(opt.width) * size_t(opt.height));
    }
}

AgreementView view(Vec3f eye, Vec3f target, std::vector<Vec3f> lights, int width = 32,
                   int height = 24, int aa = 1, float fovy = 60.f, Vec3f up = {0, 1, 0}) {
    return AgreementView{Camera{eye, target, up, fovy}, width, height, aa, std::move(lights)};
}

TEST(Degenerate, ZeroAreaAndNeedleTriangles) {
    Tris t;
    add_grid(t, {-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, 4, 4);  // floor
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    for (int i = 0; i < 400; ++i) {
        const Vec3f a{u(rng), 1.f + 0.5f * u(rng), u(rng)}, b{u(rng), 1.f + 0.5f * u(rng), u(rng)};
        switch (i % 5) {
            case 0:
                t.push_back({a, a, a});
                break;  // a point
            case 1:
                t.push_back({a, b, (a + b) * 0.5f});
                break;  // collinear
            case 2:
                t.push_back({a, b, b});
                break;  // two equal vertices
            case 3:
                t.push_back({a, b, a + Vec3f{0, 1e-7f, 0}});
                break;  // needle
            default:
                t.push_back({a, a + Vec3f{1e-6f, 0, 0}, b});
                break;  // needle
        }
    }
    // Zero-area triangles lying exactly on the floor's edges and vertices, where rays of the
    // axis-aligned view below pass.
    t.push_back({{-4, 0, 0}, {4, 0, 0}, {0, 0, 0}});
    t.push_back({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
    const Scene s = scene_of(t);
    expect_agreement(
        s, {view({0, 3, 6}, {0, 0.5f, 0}, {{0, 4, 0}, {3, 1, 3}}, 32, 24, 2),
            view({0, 1, 5}, {0, 1, 0}, {{0, 1, 5}}),
            view({0.001f, 6, 0.001f}, {0, 0, 0}, {{0, 5, 0}}, 32, 32, 1, 90.f, {0, 0, -1})});
}

TEST(Degenerate, DuplicatedTriangles) {
    Tris sphere;
    add_sphere(sphere, {0, 0, 0}, 1.f, 24, 12);
    Tris t;
    // Each triangle three times: twice in a row, once with the opposite winding at the end.
    for (const TriangleVerts& tri : sphere) {
        t.push_back(tri);
        t.push_back(tri);
    }
    for (const TriangleVerts& tri : sphere) t.push_back({tri.v0, tri.v2, tri.v1});
    add_grid(t, {-3, -1, -3}, {6, 0, 0}, {0, 0, 6}, 3, 3);
    add_grid(t, {-3, -1, -3}, {6, 0, 0}, {0, 0, 6}, 3, 3);  // the floor twice
    const Scene s = scene_of(t);
    expect_agreement(s, {view({2, 1.5f, 3}, {0, 0, 0}, {{0, 3, 0}, {-2, 0, 2}}, 32, 24, 2),
                         view({0, 0, 0.5f}, {0, 0, -1}, {{0, 0, 0.5f}, {0.2f, 0.2f, 0}}, 24, 24)});
}

TEST(Degenerate, AllTrianglesCoplanar) {
    Tris t;
    add_grid(t, {-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, 12, 12);
    // Overlapping coplanar panels on the same plane, some with shared and crossing edges.
    add_grid(t, {-2, 0, -2}, {4, 0, 0}, {0, 0, 4}, 3, 3);
    add_grid(t, {-1.5f, 0, -3}, {2, 0, 0}, {0, 0, 5}, 1, 2);
    add_grid(t, {-3, 0, -1}, {6, 0, 1}, {0, 0, 2}, 2, 1);
    const Scene s = scene_of(t);
    expect_agreement(s, {view({1, 3, 5}, {0, 0, 0}, {{0, 2, 0}, {2, 0.5f, -1}}, 32, 24, 2),
                         view({0.3f, 8, 0.1f}, {0, 0, 0}, {{0, 1, 0}}, 24, 24, 1, 60.f, {0, 0, -1}),
                         // Lights in the plane: every segment runs along it.
                         view({-2, 2, 4}, {0, 0, 0}, {{0, 0, 0}, {5, 0, 5}, {-1.5f, 0, -3}})});
    // The camera in the plane of every triangle: all rays graze it (edge-on). Most miss, but
    // whatever is hit must be the same for everyone.
    expect_agreement(s,
                     {view({-6, 0, 0}, {0, 0, 0}, {{0, 1, 0}}),
                      view({0, 0, 0}, {1, 0, 0.5f}, {{0, 1, 0}, {0, 0, 0}})},
                     "brute", 0.0);
}

TEST(Degenerate, SizesFromMicrometresToThousandsOfKilometres) {
    Tris t;
    // A 1e6 floor, 1e-6 triangles near the origin, and everything between, a decade apart.
    add_grid(t, {-1e6f, 0, -1e6f}, {2e6f, 0, 0}, {0, 0, 2e6f}, 1, 1);
    for (int e = -6; e <= 5; ++e) {
        const float s = std::pow(10.f, float(e));
        const Vec3f c{float(e) * 0.1f, 2e-6f + s, -3.f * s};
        t.push_back({c, c + Vec3f{s, 0, 0}, c + Vec3f{0, s, 0}});
        add_box(t, c + Vec3f{2 * s, 0, 0}, c + Vec3f{3 * s, s, s}, 1);
    }
    const Scene s = scene_of(t);
    expect_agreement(s,
                     {view({0, 5e-6f, 1e-5f}, {0, 2e-6f, -2e-6f}, {{1e-6f, 1e-5f, 0}}),
                      view({0, 1, 4}, {0, 0.5f, 0}, {{0, 3, 0}, {1e5f, 1e5f, 0}}),
                      view({3e5f, 2e5f, 6e5f}, {0, 0, 0}, {{0, 1e5f, 0}}, 32, 24, 1, 60.f)},
                     "brute", 0.1);
}

TEST(Degenerate, SingleTriangle) {
    const Scene s = scene_of({{{-1, 0, -1}, {1, 0, -1}, {0, 0, 1}}});
    expect_agreement(s,
                     {view({0, 2, 2}, {0, 0, 0}, {{0, 1, 0}}, 16, 16, 2, 45.f),
                      view({0, -2, 0.01f}, {0, 0, 0}, {{0, -1, 0}, {0, 1, 0}}, 16, 16, 1, 45.f)});
    // Camera on the triangle's plane (inside it, and outside beyond an edge), and on a vertex.
    expect_agreement(s,
                     {view({0, 0, 0}, {0, 1, 0}, {{0, 0, 0}}, 16, 16, 1, 170.f, {1, 0, 0}),
                      view({0, 0, -3}, {0, 0, 0}, {{0, 1, 0}}),
                      view({-1, 0, -1}, {0, -1, 0}, {{0, 1, 0}}, 16, 16, 1, 170.f, {1, 0, 0})},
                     "brute", 0.0);
}

TEST(Degenerate, MillionIdenticalTrianglesInSeconds) {
    // Nothing separates identical triangles: the tree must give up splitting early, and every
    // tracer must still find the smallest index among a million ties.
    const auto start = std::chrono::steady_clock::now();
    const Scene s =
        scene_of(Tris(1'000'000, TriangleVerts{{-10, 0, -10}, {10, 0, -10}, {0, 0, 10}}));
    const KdTree tree = build_kdtree(s);
    const double build =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(build, 10.0 * test_env::time_slack);
    EXPECT_LE(tree.nodes.size(), 64u);
    const auto results = differential::compare_tracers(
        s, tree, "ray", view({0, 2, 2}, {0, 0, 0}, {{0, 3, 0}}, 4, 4, 1, 30.f));
    for (const auto& [kind, a] : results) {
        if (differential::tie_breaks_differ(kind)) continue;
        EXPECT_EQ(a.hits, 16u) << kind;
        EXPECT_EQ(a.hit_mismatches, 0u) << kind << ": " << a.first_mismatch;
        EXPECT_EQ(a.shadow_mismatches, 0u) << kind << ": " << a.first_mismatch;
    }
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ degenerate ] 1M identical triangles: build %.2f s, build + %zu tracers %.2f s\n",
                build, results.size(), total);
    EXPECT_LT(total, 60.0 * test_env::time_slack);
}

TEST(Degenerate, CameraInsideClosedMeshes) {
    Tris t;
    add_box(t, {-5, -5, -5}, {5, 5, 5}, 4);
    add_sphere(t, {1, 0, 0}, 2.f, 24, 12);
    const Scene s = scene_of(t);
    expect_agreement(s,
                     {// Inside the sphere (inside the box): every ray hits the sphere.
                      view({1.5f, 0.3f, 0.2f}, {0, 0, -1}, {{1, 0, 0}, {4, 4, 4}}, 32, 24, 2, 90.f),
                      // Between the sphere and the box, lights inside and outside everything.
                      view({-4, 3, 4}, {1, 0, 0}, {{-4, 4, -4}, {9, 9, 9}}, 32, 24, 1, 100.f)},
                     "brute", 0.99);
}

TEST(Degenerate, LightsOnSurfacesAndAtTheCamera) {
    Tris t;
    add_box(t, {-5, 0, -5}, {5, 4, 5}, 3);
    add_box(t, {-1, 0, -1}, {1, 1, 1}, 2);
    const Scene s = scene_of(t);
    const Vec3f eye{3, 2, 4};
    expect_agreement(s,
                     {// On a face, on an edge and on a vertex of the inner box; on a wall.
                      view(eye, {0, 0.5f, 0}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {-5, 2, 0}}),
                      // Exactly at the camera (segments are the primary rays reversed),
                      // and at the camera while the camera sits on the floor.
                      view(eye, {0, 0.5f, 0}, {eye}, 32, 24, 2)},
                     "brute", 0.99);
    // The camera (and a light) on the floor: the floor is seen edge-on.
    expect_agreement(s, {view({3, 0, 4}, {0, 0.5f, 0}, {{3, 0, 4}, {0, 1, 0}})}, "brute", 0.5);
}

}  // namespace
}  // namespace rtt
