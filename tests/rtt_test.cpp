// The RTT tracer against the reference tracer (and the brute-force oracle on small scenes),
// sample for sample: the same closest triangle and t (bit for bit) for primary and reflected
// rays, the same visibility bit for shadow segments. Tiles are built as the renderer builds them
// (render.h): 4K x 4K samples per 4x4-pixel tile over the padded image, all rays from the
// camera, shaft = true; shadow tiles from the hits, lights inside the scenes, every hit sample
// active or a pseudo-random part of them (spot lights). Every test also checks that RTT
// actually answered a good share of the rays, or agreement would prove nothing.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "geom/triangle.h"
#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"
#include "same_hit.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

using test::add_box;
using test::add_grid;
using test::add_sphere;
using test::scene_of;
using test::Tris;

void add_soup(Tris& out, size_t n, unsigned seed, Vec3f center, float extent, float size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (size_t i = 0; i < n; ++i) {
        const Vec3f c = center + Vec3f{u(rng), u(rng), u(rng)} * extent;
        out.push_back({c + Vec3f{u(rng), u(rng), u(rng)} * size,
                       c + Vec3f{u(rng), u(rng), u(rng)} * size,
                       c + Vec3f{u(rng), u(rng), u(rng)} * size});
    }
}

/// A furnished box room around `o` (10 x 4 x 8): walls, a table, a cabinet, spheres, a soup of
/// small triangles, coplanar overlapping panels and exact duplicates. Cameras and lights go
/// inside.
Tris room(Vec3f o) {
    Tris t;
    add_box(t, o + Vec3f{-5, 0, -4}, o + Vec3f{5, 4, 4}, 4);
    add_box(t, o + Vec3f{-1.5f, 0.8f, -1}, o + Vec3f{1.5f, 0.9f, 1}, 2);  // table top
    add_box(t, o + Vec3f{2, 0, -3}, o + Vec3f{3.5f, 2.5f, -2}, 3);        // cabinet
    add_sphere(t, o + Vec3f{0, 1.3f, 0}, 0.4f, 24, 12);
    add_sphere(t, o + Vec3f{-3, 0.5f, 2}, 0.5f, 12, 6);
    add_soup(t, 150, 5, o + Vec3f{-3, 2, -2.5f}, 0.8f, 0.15f);
    // Coplanar overlapping panels on the back wall plane, one exact duplicate, one in front.
    add_grid(t, o + Vec3f{-4, 1, -4}, {2, 0, 0}, {0, 1.5f, 0}, 1, 1);
    add_grid(t, o + Vec3f{-3.5f, 1.2f, -4}, {2, 0, 0}, {0, 1.5f, 0}, 2, 1);
    add_grid(t, o + Vec3f{-3.5f, 1.2f, -4}, {2, 0, 0}, {0, 1.5f, 0}, 2, 1);
    add_grid(t, o + Vec3f{-3.5f, 1.2f, -3.999f}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    return t;
}

/// The rays of primary tile (tx, ty) of a padded image, in the renderer's order.
std::vector<Ray> tile_rays(const CameraRays& cam, int tx, int ty) {
    const int k = cam.aa(), side = 4 * k;
    std::vector<Ray> rays;
    rays.reserve(size_t(side * side));
    for (int sy = 0; sy < side; ++sy)
        for (int sx = 0; sx < side; ++sx)
            rays.push_back(Ray{cam.origin(),
                               cam.direction(tx * 4 + sx / k, ty * 4 + sy / k, sx % k, sy % k), 0.f,
                               pos_inf});
    return rays;
}

struct Tally {
    uint64_t rays = 0, mismatches = 0, answered = 0, answered_misses = 0;
    uint64_t segments = 0, segment_mismatches = 0, segments_answered = 0;
    uint64_t bvh_rays = 0;  ///< Traced through RTT's BVH (RttStats::bvh_rays).

    double answered_fraction() const { return rays ? double(answered) / double(rays) : 0.0; }
    double segments_answered_fraction() const {
        return segments ? double(segments_answered) / double(segments) : 0.0;
    }
    void print(const char* what) const {
        std::printf(
            "[  rtt     ] %-24s rays %7llu mismatches %llu answered %5.1f%% | segments %7llu "
            "mismatches %llu "
            "answered %5.1f%%\n",
            what, (unsigned long long)rays, (unsigned long long)mismatches,
            100.0 * answered_fraction(), (unsigned long long)segments,
            (unsigned long long)segment_mismatches, 100.0 * segments_answered_fraction());
    }
};

/// Differential runs of camera views: RTT against `reference` on every primary ray, and on
/// every shadow segment to each light (all hit samples active, then a pseudo-random part).
struct Differ {
    const Scene& scene;
    const KdTree& tree;
    std::unique_ptr<Tracer> rtt;
    std::unique_ptr<Tracer> reference;

    Differ(const Scene& s, const KdTree& t, const char* reference_kind,
           const RttOptions& options = {})
        : scene(s),
          tree(t),
          rtt(make_rtt_tracer(s, t, options)),
          reference(make_tracer(reference_kind, s, t)) {}

    /// `region`: pixels per tile side as RenderOptions::region (4 = one 4x4-pixel tile; larger
    /// regions are cut by the padded image's edge, as the renderer cuts them).
    void run(const Camera& camera, int width, int height, int k, const std::vector<Vec3f>& lights,
             Tally& tally, int region = 4) {
        const CameraRays cam(camera, width, height, k);
        const int tiles_x = (width + 3) / 4, tiles_y = (height + 3) / 4, r = region / 4;
        std::mt19937 rng(unsigned(width * 7919 + height * 31 + k));
        for (int ty = 0; ty < tiles_y; ty += r)
            for (int tx = 0; tx < tiles_x; tx += r) {
                const int cols = std::min(r, tiles_x - tx), rows = std::min(r, tiles_y - ty);
                const int sw = 4 * k * cols, sh = 4 * k * rows, n = sw * sh;
                const size_t ns = size_t(n);
                std::vector<Hit> got(ns), want(ns);
                std::vector<SampleAnswer> answers(ns);
                std::vector<Vec3f> points(ns);
                std::vector<uint32_t> tris(ns);
                std::vector<uint8_t> active(ns), vis_got(ns), vis_want(ns);
                std::vector<Ray> rays(ns);
                if (r == 1)
                    rays = tile_rays(cam, tx, ty);
                else
                    cam.region_rays(tx, ty, cols, rows, rays);
                const int cell = r > 1 ? 4 * k : 0;
                const RayTile tile{sw, sh, rays, true, cell};
                TraceStats st;
                RttStats rs;
                rtt->intersect(tile, got, TraceContext{&st, &rs, answers});
                reference->intersect(tile, want);
                tally.rays += ns;
                EXPECT_EQ(st.rays, uint64_t(n));
                EXPECT_EQ(st.traced + rs.answered, st.rays);
                for (size_t i = 0; i < ns; ++i) {
                    if (!same_hit(got[i], want[i])) {
                        if (tally.mismatches < 5)
                            std::printf(
                                "primary mismatch tile (%d,%d) sample %zu: rtt %u %.9g, reference "
                                "%u %.9g (%s)\n",
                                tx, ty, i, got[i].tri, double(got[i].t), want[i].tri,
                                double(want[i].t),
                                answers[i] == SampleAnswer::traced ? "traced" : "answered");
                        ++tally.mismatches;
                    }
                    tally.answered += answers[i] != SampleAnswer::traced;
                    tally.answered_misses += answers[i] != SampleAnswer::traced && !got[i].valid();
                }
                for (size_t i = 0; i < ns; ++i) {
                    points[i] =
                        want[i].valid() ? rays[i].org + want[i].t * rays[i].dir : rays[i].org;
                    tris[i] = want[i].tri;
                }
                for (size_t l = 0; l < lights.size(); ++l)
                    for (int spot = 0; spot < 2; ++spot) {
                        for (size_t i = 0; i < ns; ++i)
                            active[i] = want[i].valid() && (spot == 0 || rng() % 4 != 0);
                        const SegmentTile seg{sw, sh, lights[l], points, tris, active, true, cell};
                        TraceStats ss;
                        RttStats rss;
                        rtt->occluded(seg, vis_got, TraceContext{&ss, &rss, answers});
                        reference->occluded(seg, vis_want);
                        EXPECT_EQ(ss.traced + rss.answered, ss.rays);
                        tally.bvh_rays += rss.bvh_rays;
                        for (size_t i = 0; i < ns; ++i) {
                            if (!active[i]) {
                                EXPECT_EQ(vis_got[i], 0);
                                continue;
                            }
                            ++tally.segments;
                            if (vis_got[i] != vis_want[i]) {
                                if (tally.segment_mismatches < 5)
                                    std::printf(
                                        "shadow mismatch tile (%d,%d) sample %zu light %zu: rtt %d "
                                        "reference %d (%s)\n",
                                        tx, ty, i, l, vis_got[i], vis_want[i],
                                        answers[i] == SampleAnswer::traced ? "traced" : "answered");
                                ++tally.segment_mismatches;
                            }
                            tally.segments_answered += answers[i] != SampleAnswer::traced;
                        }
                    }
            }
    }
};

TEST(Rtt, Registered) {
    bool found = false;
    for (const std::string& k : tracer_kinds()) found |= k == "rtt";
    EXPECT_TRUE(found);
}

// Random soups: RTT rarely applies (tiles meet many triangles), but what it answers must be the
// oracle's answer; cameras inside and outside the soup, resolutions not divisible by 4.
TEST(Rtt, RandomSoupsMatchBruteForce) {
    Tally tally;
    for (unsigned seed = 1; seed <= 3; ++seed) {
        Tris t;
        add_soup(t, 120, seed, {0, 0, 0}, 2.f, 0.7f);
        add_grid(t, {-3, -2.5f, -3}, {6, 0, 0}, {0, 0, 6}, 3, 3);  // a floor to land shadows on
        const Scene scene = scene_of(t);
        const KdTree tree = build_kdtree(scene);
        Differ d(scene, tree, "brute");
        const std::vector<Vec3f> lights = {{0.3f, 2.9f, 0.2f}};
        d.run(Camera{{5, 3, 6}, {0, -0.5f, 0}, {0, 1, 0}, 45}, 37, 29, 1, lights, tally);
        d.run(Camera{{0.1f, 0.2f, 0.3f}, {1, -1, 1}, {0, 1, 0}, 90}, 22, 17, 2, lights, tally);
    }
    tally.print("random soups");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    EXPECT_GT(tally.answered, 0u);
}

// The furnished room from inside, with K from 1 to 6, a grazing view of the floor, a wall seen
// edge-on, and the same room 1e4 away from the origin.
TEST(Rtt, RoomMatchesReferenceAndAnswersMostRays) {
    for (const Vec3f offset : {Vec3f{0, 0, 0}, Vec3f{1e4f, -1e4f, 1e4f}}) {
        const Scene scene = scene_of(room(offset));
        const KdTree tree = build_kdtree(scene);
        Differ d(scene, tree, "ray");
        Tally tally;
        const std::vector<Vec3f> lights = {offset + Vec3f{0, 3.5f, 0}, offset + Vec3f{-4, 3, 3}};
        const auto view = [&](Vec3f pos, Vec3f at, float fovy) {
            return Camera{offset + pos, offset + at, {0, 1, 0}, fovy};
        };
        d.run(view({4, 2, 3.5f}, {-2, 1, -3}, 60), 160, 120, 1, lights, tally);
        d.run(view({-4.5f, 3.5f, 3.5f}, {2, 0.5f, -2}, 75), 62, 45, 2, lights, tally);
        d.run(view({0, 0.05f, 3.9f}, {0, 0.02f, -4}, 50), 64, 48, 3, lights,
              tally);                                                              // grazing floor
        d.run(view({4.99f, 2, 3}, {4.99f, 2, -4}, 40), 32, 24, 4, lights, tally);  // wall edge-on
        d.run(view({1, 1.5f, 2}, {-1, 1, -2}, 30), 10, 9, 6, lights, tally);
        tally.print(offset.x == 0.f ? "room" : "room far from origin");
        EXPECT_EQ(tally.mismatches, 0u);
        EXPECT_EQ(tally.segment_mismatches, 0u);
        EXPECT_GT(tally.answered_fraction(), 0.5);
        EXPECT_GT(tally.segments_answered_fraction(), 0.3);
    }
}

// Triangles whose vertices and edges lie exactly on the rays of tile corners (and on inner
// samples), as floats: every such ray passes through a vertex or along a shared edge.
TEST(Rtt, TrianglesOnTileCornerRays) {
    const Camera camera{{0.25f, 0.5f, 5}, {0, 0, 0}, {0, 1, 0}, 50};
    const int w = 24, h = 16;
    const CameraRays cam(camera, w, h, 1);
    Tris t;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> depth(2.f, 6.f);
    // A fan of triangles around points on corner rays of several tiles, at random depths, and a
    // backdrop grid whose vertices sit on corner rays at one depth.
    for (int ty = 0; ty < h / 4; ++ty)
        for (int tx = 0; tx < w / 4; ++tx) {
            const auto at = [&](int x, int y, float s) {
                return cam.origin() + cam.direction(x, y, 0, 0) * s;
            };
            const float s = depth(rng);
            const Vec3f c = at(tx * 4, ty * 4, s);
            t.push_back({c, at(tx * 4 + 3, ty * 4, s), at(tx * 4 + 3, ty * 4 + 3, s)});
            t.push_back({c, at(tx * 4 + 3, ty * 4 + 3, s), at(tx * 4, ty * 4 + 3, s)});
            t.push_back({at(tx * 4 + 1, ty * 4 + 1, s * 0.9f), at(tx * 4 + 3, ty * 4 + 1, s * 0.9f),
                         at(tx * 4 + 1, ty * 4 + 3, s * 0.9f)});
        }
    add_grid(t, {-8, -8, -3}, {16, 0, 0}, {0, 16, 0}, 5, 5);
    const Scene scene = scene_of(t);
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "brute");
    Tally tally;
    // K = 1 and 2 answer only tiles whose corners stay coherent, which these split planes
    // through the corner rays rarely allow; K = 3 tiles go through the shaft walk and are
    // answered.
    d.run(camera, w, h, 1, {{1, 2, 4}}, tally);
    d.run(camera, w, h, 2, {{1, 2, 4}}, tally);
    d.run(camera, w, h, 3, {{1, 2, 4}}, tally);
    tally.print("triangles on corner rays");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    EXPECT_GT(tally.answered, 0u);
}

// A camera inside a closed, finely tessellated box far from the origin (Embree's watertightness
// pattern): every ray hits, through shared edges and vertices.
TEST(Rtt, InsideClosedBoxFarFromOrigin) {
    const Vec3f o{1e4f, 2e4f, -3e4f};
    Tris t;
    add_box(t, o + Vec3f{-1, -1, -1}, o + Vec3f{1, 1, 1}, 7);
    add_sphere(t, o + Vec3f{0.4f, -0.3f, 0.2f}, 0.3f, 16, 8);
    const Scene scene = scene_of(t);
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "ray");
    Tally tally;
    d.run(Camera{o + Vec3f{-0.3f, 0.2f, 0.5f}, o + Vec3f{0.5f, -0.4f, -1}, {0, 1, 0}, 100}, 41, 33,
          1, {o + Vec3f{-0.5f, 0.9f, 0.1f}}, tally);
    d.run(Camera{o + Vec3f{0.9f, 0.9f, 0.9f}, o + Vec3f{-1, -1, -1}, {0, 1, 0}, 70}, 20, 20, 3,
          {o + Vec3f{0.5f, -0.9f, -0.5f}}, tally);
    tally.print("inside a far box");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    EXPECT_GT(tally.answered_fraction(), 0.3);
}

// A light exactly on a receiver plane (the floor): RTT must decline those shadow tiles.
TEST(Rtt, LightOnTheReceiverPlane) {
    Tris t;
    add_grid(t, {-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, 4, 4);
    add_box(t, {-1, 0, -1}, {1, 1, 1}, 2);
    const Scene scene = scene_of(t);
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "brute");
    Tally tally;
    d.run(Camera{{3, 3, 5}, {0, 0, 0}, {0, 1, 0}, 60}, 32, 24, 1, {{2.5f, 0.f, 2.f}, {0, 2.5f, 0}},
          tally);
    tally.print("light on the floor");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
}

// Shaft tiles of any grid size (here not multiples of the 8 or 16 lanes the inner rays go in,
// so the last block of a tile is partly past its end), primary and shadow, against brute force.
TEST(Rtt, GridsOfAnySizeMatchBruteForce) {
    const Scene scene = scene_of(room({0, 0, 0}));
    const KdTree tree = build_kdtree(scene);
    const auto rtt = make_tracer("rtt", scene, tree);
    const auto ref = make_tracer("brute", scene, tree);
    const CameraRays cam(Camera{{4, 2, 3.5f}, {-2, 1, -3}, {0, 1, 0}, 60}, 120, 90, 3);
    const Vec3f light{0, 3.5f, 0};
    uint64_t rays = 0, mismatches = 0, answered = 0, segments = 0, segments_answered = 0;
    for (const auto& [w, h] :
         {std::pair(5, 3), std::pair(6, 6), std::pair(9, 7), std::pair(13, 11), std::pair(19, 2)}) {
        const size_t n = size_t(w * h);
        std::vector<Hit> got(n), want(n);
        std::vector<SampleAnswer> how(n);
        std::vector<Vec3f> points(n);
        std::vector<uint32_t> tris(n);
        std::vector<uint8_t> active(n), vis_got(n), vis_want(n);
        for (int y0 = 0; y0 + h <= 270; y0 += h + 17)
            for (int x0 = 0; x0 + w <= 360; x0 += w + 23) {
                // Samples (x0 + x, y0 + y) of the image's 360 x 270 sample grid, row by row.
                std::vector<Ray> grid;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const int sx = x0 + x, sy = y0 + y;
                        grid.push_back(Ray{cam.origin(),
                                           cam.direction(sx / 3, sy / 3, sx % 3, sy % 3), 0.f,
                                           pos_inf});
                    }
                const RayTile tile{w, h, grid, true};
                rtt->intersect(tile, got, TraceContext{.answers = how});
                ref->intersect(tile, want);
                for (size_t i = 0; i < n; ++i) {
                    ++rays;
                    mismatches += !same_hit(got[i], want[i]);
                    answered += how[i] != SampleAnswer::traced;
                    active[i] = want[i].valid() && i % 5 != 2;
                    points[i] = active[i] ? grid[i].org + want[i].t * grid[i].dir : grid[i].org;
                    tris[i] = want[i].tri;
                }
                const SegmentTile seg{w, h, light, points, tris, active, true};
                rtt->occluded(seg, vis_got, TraceContext{.answers = how});
                ref->occluded(seg, vis_want);
                for (size_t i = 0; i < n; ++i) {
                    if (!active[i]) {
                        EXPECT_EQ(vis_got[i], 0);
                        continue;
                    }
                    ++segments;
                    mismatches += vis_got[i] != vis_want[i];
                    segments_answered += how[i] != SampleAnswer::traced;
                }
            }
    }
    std::printf(
        "[  rtt     ] grids of any size: rays %llu answered %llu, segments %llu answered "
        "%llu, mismatches %llu\n",
        (unsigned long long)rays, (unsigned long long)answered, (unsigned long long)segments,
        (unsigned long long)segments_answered, (unsigned long long)mismatches);
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(answered, rays / 4);
    EXPECT_GT(segments_answered, segments / 8);
}

// The built-in room at two views: the scene of the paper's experiments.
TEST(Rtt, BuiltinRoomMatchesReference) {
    const Scene scene = make_builtin_scene("room");
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "ray");
    Tally tally;
    std::vector<Vec3f> lights;
    for (const Light& l : scene.lights) lights.push_back(l.position);
    lights.resize(std::min<size_t>(lights.size(), 2));
    d.run(*scene.camera, 256, 192, 1, lights, tally);
    Camera narrow = *scene.camera;
    narrow.fovy_deg = 25.f;
    d.run(narrow, 42, 30, 3, lights, tally);
    tally.print("builtin room");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    // At K = 1 (the 256x192 view) only tiles with coherent corners are answered
    // (primary_tiles.cpp).
    EXPECT_GT(tally.answered_fraction(), 0.12);
    EXPECT_GT(tally.segments_answered_fraction(), 0.2);
}

// Reflections through the renderer: a planar mirror wall (reflected shafts with a mirrored apex
// and per-ray tmin) and a curved mirror (packed, no shaft). Hit and shadow buffers and the
// image must be bit-identical to the reference tracer's.
TEST(Rtt, RenderWithMirrorsMatchesReference) {
    Scene scene = scene_of(room({0, 0, 0}));
    Material mirror;
    mirror.name = "mirror";
    mirror.mirror = 0.8f;
    const uint32_t m = scene.add_material(mirror);
    Tris wall, ball;
    add_grid(wall, {-4.9f, 0.5f, -3}, {0, 0, 6}, {0, 3, 0}, 3,
             2);                                     // planar mirror on the left wall
    add_sphere(ball, {2.5f, 1, 1.5f}, 0.5f, 16, 8);  // curved mirror
    for (const Tris* part : {&wall, &ball}) {
        std::vector<Vec3f> v;
        std::vector<TriangleIndices> idx;
        for (const TriangleVerts& t : *part) {
            const uint32_t b = uint32_t(v.size());
            v.insert(v.end(), {t.v0, t.v1, t.v2});
            idx.push_back({b, b + 1, b + 2});
        }
        scene.add_mesh(v, idx, m);
    }
    scene.lights.push_back(make_point_light({0, 3.5f, 0}, scene.bounds(), 2));
    scene.lights.push_back(make_point_light({3, 3, -3}, scene.bounds(), 2));
    const KdTree tree = build_kdtree(scene);
    const auto rtt = make_tracer("rtt", scene, tree);
    const auto ref = make_tracer("ray", scene, tree);
    // K = 3: tiles of 12x12 samples, whose corners may hit several planes (walk.h).
    for (const int aa : {1, 2, 3}) {
        SCOPED_TRACE("aa " + std::to_string(aa));
        RenderOptions opt;
        opt.camera = Camera{{3, 2, 3.5f}, {-4, 1.5f, -1}, {0, 1, 0}, 70};
        opt.width = 90;
        opt.height = 61;
        opt.aa = aa;
        opt.threads = 2;
        opt.hits_buffer = opt.shadow_buffer = true;
        const RenderResult a = render(scene, *rtt, opt);
        const RenderResult b = render(scene, *ref, opt);
        // Any region size (cut by the image's edge at 90x61) gives the same bytes.
        for (const int region : {8, 12, 16, 64}) {
            RenderOptions o = opt;
            o.region = region;
            const RenderResult c = render(scene, *rtt, o);
            EXPECT_EQ(a.hits, c.hits) << "region " << region;
            EXPECT_EQ(a.shadows, c.shadows) << "region " << region;
            ASSERT_EQ(a.pixels.size(), c.pixels.size());
            EXPECT_EQ(
                std::memcmp(a.pixels.data(), c.pixels.data(), a.pixels.size() * sizeof(Vec3f)), 0)
                << "region " << region;
            EXPECT_EQ(a.stats.secondary.trace.rays, c.stats.secondary.trace.rays);
        }
        uint64_t hit_mismatches = 0, shadow_mismatches = 0, pixel_mismatches = 0;
        for (size_t i = 0; i < a.hits.size(); ++i) hit_mismatches += a.hits[i] != b.hits[i];
        for (size_t i = 0; i < a.shadows.size(); ++i)
            shadow_mismatches += a.shadows[i] != b.shadows[i];
        for (size_t i = 0; i < a.pixels.size(); ++i)
            pixel_mismatches += !(a.pixels[i] == b.pixels[i]);
        std::printf(
            "[  rtt     ] mirrors, aa %d: secondary rays %llu answered %llu, mismatches hits %llu "
            "shadows %llu pixels %llu\n",
            aa, (unsigned long long)a.stats.secondary.trace.rays,
            (unsigned long long)a.stats.secondary.rtt.answered, (unsigned long long)hit_mismatches,
            (unsigned long long)shadow_mismatches, (unsigned long long)pixel_mismatches);
        EXPECT_EQ(hit_mismatches, 0u);
        EXPECT_EQ(shadow_mismatches, 0u);
        EXPECT_EQ(pixel_mismatches, 0u);
        if (aa >= 2) {  // reflected shafts answered by RTT (at K = 1 their corners rarely agree)
            EXPECT_GT(a.stats.secondary.rtt.answered, 0u);
        }
        EXPECT_GT(a.stats.primary.rtt.answered, 0u);
    }
}

// Regions of several 4x4-pixel tiles (RayTile::cell): RTT tries a region as one shaft and
// traces it when the shaft gives no list. Every region size must give the reference's answers,
// regions cut by the image's edge included (sizes not divisible by the region), and regions
// above rtt_max_samples_per_tile (traced by packets).
TEST(Rtt, RegionsMatchReference) {
    const Scene scene = scene_of(room({0, 0, 0}));
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "ray");
    const std::vector<Vec3f> lights = {{0, 3.5f, 0}, {-4, 3, 3}};
    const Camera view{{4, 2, 3.5f}, {-2, 1, -3}, {0, 1, 0}, 60};
    const Camera grazing{{0, 0.05f, 3.9f}, {0, 0.02f, -4}, {0, 1, 0}, 50};
    double answered_k1[4] = {};
    int i = 0;
    for (const int region : {4, 16, 32, 64}) {
        Tally tally, k1;
        d.run(view, 150, 110, 1, lights, k1, region);
        d.run(view, 62, 45, 2, lights, tally, region);
        d.run(grazing, 64, 48, 3, lights, tally, region);
        const std::string what = "region " + std::to_string(region) + ", K = 1";
        k1.print(what.c_str());
        tally.print("                 K = 2, 3");
        EXPECT_EQ(k1.mismatches + tally.mismatches, 0u);
        EXPECT_EQ(k1.segment_mismatches + tally.segment_mismatches, 0u);
        if (region <= 16) {  // larger regions at K = 3 exceed rtt_max_samples_per_tile
            EXPECT_GT(tally.answered_fraction(), 0.5);
        }
        answered_k1[i++] = k1.answered_fraction();
    }
    // Larger regions answer more of the K = 1 rays: a shaft of a whole region answers the
    // inside of large planes that 4x4-pixel tiles leave to the fallback at their edges.
    EXPECT_GT(answered_k1[1], answered_k1[0]);
    EXPECT_GT(answered_k1[1], 0.5);
}

// Regions on the hardest geometry: triangles on tile-corner rays, random soups.
TEST(Rtt, RegionsOnCornerRaysAndSoupsMatchBruteForce) {
    Tally tally;
    for (unsigned seed = 1; seed <= 2; ++seed) {
        Tris t;
        add_soup(t, 120, seed, {0, 0, 0}, 2.f, 0.7f);
        add_grid(t, {-3, -2.5f, -3}, {6, 0, 0}, {0, 0, 6}, 3, 3);
        const Scene scene = scene_of(t);
        const KdTree tree = build_kdtree(scene);
        Differ d(scene, tree, "brute");
        const std::vector<Vec3f> lights = {{0.3f, 2.9f, 0.2f}};
        for (const int region : {8, 16})
            d.run(Camera{{5, 3, 6}, {0, -0.5f, 0}, {0, 1, 0}, 45}, 37, 29, 1, lights, tally,
                  region);
        d.run(Camera{{0.1f, 0.2f, 0.3f}, {1, -1, 1}, {0, 1, 0}, 90}, 22, 17, 2, lights, tally, 8);
    }
    const Camera camera{{0.25f, 0.5f, 5}, {0, 0, 0}, {0, 1, 0}, 50};
    const CameraRays cam(camera, 24, 16, 1);
    Tris t;
    for (int ty = 0; ty < 4; ++ty)
        for (int tx = 0; tx < 6; ++tx) {
            const auto at = [&](int x, int y, float s) {
                return cam.origin() + cam.direction(x, y, 0, 0) * s;
            };
            const float s = 2.f + float((tx * 7 + ty * 3) % 5);
            t.push_back(
                {at(tx * 4, ty * 4, s), at(tx * 4 + 3, ty * 4, s), at(tx * 4 + 3, ty * 4 + 3, s)});
            t.push_back(
                {at(tx * 4, ty * 4, s), at(tx * 4 + 3, ty * 4 + 3, s), at(tx * 4, ty * 4 + 3, s)});
        }
    add_grid(t, {-8, -8, -3}, {16, 0, 0}, {0, 16, 0}, 5, 5);
    const Scene scene = scene_of(t);
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "brute");
    for (const int region : {8, 16}) {
        d.run(camera, 24, 16, 1, {{1, 2, 4}}, tally, region);
        d.run(camera, 24, 16, 2, {{1, 2, 4}}, tally, region);
    }
    tally.print("regions, soups and corners");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    EXPECT_GT(tally.answered, 0u);
}

// Objects against the background: regions whose corners miss are answered from a walk without
// an end (misses included), on silhouettes, all-miss regions and needles between the corners.
// Shadows on curved receivers: a finely tessellated sphere on a floor, a small blocker between
// it and the light, a light inside the scene's bounds and one outside, near the origin and far
// from it. Receivers on many planes, regions at every K: every segment must equal the
// reference's.
// Declined shadow regions through the kd-tree's packets (the BVH not built yet, or asked for)
// and through the BVH's.
TEST(Rtt, ShadowsOnCurvedReceiversMatchReference) {
    const RttOptions configs[] = {
        {},
        {.bvh_at_setup = true},
        {.bvh_at_setup = true, .shadow_fallback = ShadowFallback::kd_tree},
    };
    for (const Vec3f offset : {Vec3f{0, 0, 0}, Vec3f{3e3f, -2e3f, 1e3f}}) {
        Tris t;
        add_sphere(t, Vec3f{0, 0, 0} + offset, 1.f, 120, 60);
        add_grid(t, Vec3f{-3, -1, -3} + offset, {6, 0, 0}, {0, 0, 6}, 4, 4);
        add_box(t, Vec3f{0.5f, 1.6f, 0.2f} + offset, Vec3f{0.8f, 1.7f, 0.5f} + offset, 1);
        const Scene scene = scene_of(t);
        const KdTree tree = build_kdtree(scene);
        const Camera camera{Vec3f{0.4f, 1.2f, 3.2f} + offset, offset, {0, 1, 0}, 40};
        std::vector<uint64_t> bvh_rays;
        for (const RttOptions& options : configs) {
            Differ d(scene, tree, "ray", options);
            Tally tally;
            for (const Vec3f light : {Vec3f{1.5f, 3.f, 1.f}, Vec3f{-8.f, 12.f, 9.f}}) {
                d.run(camera, 64, 48, 1, {light + offset}, tally, 16);
                d.run(camera, 32, 24, 2, {light + offset}, tally, 8);
                d.run(camera, 24, 20, 4, {light + offset}, tally, 4);
            }
            tally.print(offset.x == 0.f ? "curved receivers" : "curved receivers, far");
            EXPECT_EQ(tally.mismatches, 0u);
            EXPECT_EQ(tally.segment_mismatches, 0u);
            bvh_rays.push_back(tally.bvh_rays);
        }
        EXPECT_EQ(bvh_rays[0], 0u);  // the BVH is built after 30 declined rays per triangle
        EXPECT_GT(bvh_rays[1], 0u);
        EXPECT_EQ(bvh_rays[2], 0u);
    }
}

TEST(Rtt, ObjectsAgainstBackgroundMatchBruteForce) {
    const Camera camera{{0.3f, 0.4f, 6}, {0, 0, 0}, {0, 1, 0}, 45};
    Tris t;
    add_sphere(t, {-0.6f, 0.2f, 0}, 0.9f, 20, 10);
    add_soup(t, 80, 3, {1.2f, -0.4f, 0.3f}, 0.6f, 0.2f);
    // Needles: long thin triangles crossing regions between their corner rays, at several
    // depths, some with vertices on sample rays (K = 1 pixel centres of a 33 x 27 image).
    const CameraRays cam(camera, 33, 27, 1);
    const auto at = [&](int x, int y, float d) {
        return cam.origin() + cam.direction(x, y, 0, 0) * d;
    };
    for (int i = 0; i < 6; ++i) {
        const int x = 1 + 5 * i, y = 2 + 4 * i;
        const float d = 3.f + 0.7f * float(i);
        const Vec3f a = at(x, y, d), b = at(std::min(x + 9, 32), y, d);
        t.push_back({a, b, a + (at(x, y + 1, d) - a) * 0x1p-12f});
        const Vec3f top = at(x + 1, 0, d + 0.5f);
        t.push_back({at(x, 26 - y / 2, d), top, top + Vec3f{1e-4f, 0, 0}});
    }
    const Scene scene = scene_of(t);
    const KdTree tree = build_kdtree(scene);
    Differ d(scene, tree, "brute");
    const std::vector<Vec3f> lights = {{2, 3, 4}};
    Tally tally;
    for (int k = 1; k <= 4; ++k)
        for (const int region : {4, 8, 16, 32}) {
            if (k * k * region * region > 4096) continue;  // rtt_max_samples_per_tile
            d.run(camera, 33, 27, k, lights, tally, region);
            d.run(Camera{{4, 1, 3}, {0.5f, 0, 0}, {0, 1, 0}, 70}, 21, 13, k, lights, tally, region);
        }
    tally.print("objects on background");
    EXPECT_EQ(tally.mismatches, 0u);
    EXPECT_EQ(tally.segment_mismatches, 0u);
    EXPECT_GT(tally.answered_misses, tally.rays / 10);
    // Far away: every region misses the scene, and is answered without tracing.
    Tally far;
    d.run(Camera{{0, 0, 6}, {0, 40, 0}, {0, 0, 1}, 30}, 30, 22, 2, {}, far, 16);
    EXPECT_EQ(far.mismatches, 0u);
    EXPECT_GT(far.answered_misses, far.rays / 2);
}

// Tiles traced concurrently (the tracer keeps its scratch per thread): same answers as one by one.
TEST(Rtt, ConcurrentTilesAgree) {
    const Scene scene = scene_of(room({0, 0, 0}));
    const KdTree tree = build_kdtree(scene);
    const auto rtt = make_tracer("rtt", scene, tree);
    const CameraRays cam(Camera{{4, 2, 3.5f}, {-2, 1, -3}, {0, 1, 0}, 60}, 96, 64, 2);
    const int tiles_x = 24, tiles = 24 * 16, side = 8;
    std::vector<std::vector<Hit>> serial(tiles, std::vector<Hit>(side * side)), parallel = serial;
    std::vector<std::vector<Ray>> rays(tiles);
    for (int i = 0; i < tiles; ++i) rays[size_t(i)] = tile_rays(cam, i % tiles_x, i / tiles_x);
    for (int i = 0; i < tiles; ++i)
        rtt->intersect(RayTile{side, side, rays[size_t(i)], true}, serial[size_t(i)]);
    tbb::parallel_for(0, tiles, [&](int i) {
        rtt->intersect(RayTile{side, side, rays[size_t(i)], true}, parallel[size_t(i)]);
    });
    uint64_t mismatches = 0;
    for (int i = 0; i < tiles; ++i)
        for (int s = 0; s < side * side; ++s)
            mismatches += !same_hit(serial[size_t(i)][size_t(s)], parallel[size_t(i)][size_t(s)]);
    EXPECT_EQ(mismatches, 0u);
}

// Tiles that are not shafts (packed reflections) or not whole grids go through the fallback.
// Every tile handed to RTT with something to answer is answered from a list or declined for one
// reason (TraceStats::declined_*), and the reasons are the ones the scene calls for.
TEST(Rtt, DeclinedTilesAddUpWithAnsweredOnes) {
    const Scene scene = make_builtin_scene("room");
    const KdTree tree = build_kdtree(scene);
    for (const char* kind : {"rtt", "rtt-paper"}) {
        const auto tracer = make_tracer(kind, scene, tree);
        for (const int aa : {1, 2, 4}) {
            RenderOptions o;
            o.width = 160;
            o.height = 120;
            o.aa = aa;
            o.threads = 2;
            const RenderStats s = render(scene, *tracer, o).stats;
            SCOPED_TRACE(std::string(kind) + ", K = " + std::to_string(aa));
            // Camera and mirror tiles always have rays to answer.
            for (const KindStats* k : {&s.primary, &s.secondary})
                EXPECT_EQ(k->trace.tiles, k->rtt.rtt_tiles + k->rtt.declined());
            // A shadow job whose samples all lack a segment is neither.
            const RttStats& sh = s.shadow.rtt;
            EXPECT_LE(sh.rtt_tiles + sh.declined(), s.shadow.trace.tiles);
            EXPECT_GT(sh.rtt_tiles + sh.declined(), s.shadow.trace.tiles * 9 / 10);
            // The room's silhouettes put receivers on several planes; at K = 1 its furniture
            // makes some camera regions too costly or too incoherent to answer.
            EXPECT_GT(sh.declined_end, 0u);
            if (aa == 1) {
                EXPECT_GT(s.primary.rtt.declined(), 0u);
            }
            // The fallback's time (declined tiles, refused rays) is measured where it runs,
            // inside the tracer's time.
            for (const KindStats* k : {&s.primary, &s.shadow}) {
                if (k->rtt.declined() > 0) {
                    EXPECT_GT(k->rtt.fallback_ns, 0u);
                }
                EXPECT_LE(k->rtt.fallback_seconds(), k->seconds);
            }
        }
    }
}

TEST(Rtt, NonShaftTilesAreTraced) {
    const Scene scene = scene_of(room({0, 0, 0}));
    const KdTree tree = build_kdtree(scene);
    const auto rtt = make_tracer("rtt", scene, tree);
    const auto ref = make_tracer("brute", scene, tree);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<Ray> rays;
    for (int i = 0; i < 37; ++i)
        rays.push_back(
            Ray{{u(rng) * 4, 2 + u(rng), u(rng) * 3}, {u(rng), u(rng), u(rng)}, 0.01f, pos_inf});
    std::vector<Hit> a(rays.size()), b(rays.size());
    std::vector<SampleAnswer> answers(rays.size(), SampleAnswer::answered_list);
    TraceStats st;
    RttStats rs;
    rtt->intersect(RayTile{37, 1, rays, false}, a, TraceContext{&st, &rs, answers});
    ref->intersect(RayTile{37, 1, rays, false}, b);
    uint64_t mismatches = 0, answered = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        mismatches += !same_hit(a[i], b[i]);
        answered += answers[i] != SampleAnswer::traced;
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(answered, 0u);
    EXPECT_EQ(st.traced, rays.size());
    EXPECT_EQ(rs.declined_shaft, 1u);
    EXPECT_EQ(rs.declined(), 1u);
}

}  // namespace
}  // namespace rtt
