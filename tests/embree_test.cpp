// The Embree tracers against the brute-force oracle, on the same tiles of camera rays and
// shadow segments the renderer hands out. Skipped when this build has no Embree.
//
// Embree computes ray/triangle hits with its own arithmetic, so it may legitimately disagree
// with the watertight test where the answer hinges on rounding. Each disagreement is sorted:
//  * tie: both triangles are hit (by our test) at t within 1e-5 relative of each other
//    (shared edges and vertices, coplanar overlaps, crossing triangles), or the ray passes
//    within 1e-6 (relative to the vertices' distance from the origin) of an edge of one of the
//    two triangles: Embree found a hole or a hit on a rounding error (grazing);
//  * mismatch: anything else. Must be zero.
// Shadow bits are sorted alike: a tie when some triangle meets the segment only within those
// tolerances, or within 1e-5 of the segment's ends.
#include <gtest/gtest.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "rtt/camera.h"
#include "rtt/tracer.h"
#include "trace/brute_force.h"
#include "trace/trace_embree.h"

namespace rtt {
namespace {

constexpr double t_tolerance = 1e-5;     // relative, equal-t ties
constexpr double edge_tolerance = 1e-6;  // relative, rays grazing an edge or vertex

bool has_embree() {
    const std::vector<std::string> kinds = tracer_kinds();
    return std::find(kinds.begin(), kinds.end(), "embree") != kinds.end();
}

// ---- scenes --------------------------------------------------------------------------------

Scene random_soup(uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> centre(-1.f, 1.f), offset(-0.25f, 0.25f);
    Scene s;
    s.name = "soup";
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int i = 0; i < count; ++i) {
        const Vec3f c{centre(rng), centre(rng), centre(rng)};
        const uint32_t base = uint32_t(v.size());
        for (int k = 0; k < 3; ++k) v.push_back(c + Vec3f{offset(rng), offset(rng), offset(rng)});
        t.push_back({base, base + 1, base + 2});
    }
    s.add_mesh(v, t, s.add_material({}));
    return s;
}

/// UV sphere with pole fans (many triangles share each pole), placed away from the origin so
/// coordinates carry rounding.
void add_sphere(Scene& s, const Vec3f& centre, float r, int segments, int rings) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    v.push_back(centre + Vec3f{0.f, r, 0.f});
    for (int i = 1; i < rings; ++i) {
        const float phi = 3.14159265f * float(i) / float(rings);
        for (int j = 0; j < segments; ++j) {
            const float theta = 2.f * 3.14159265f * float(j) / float(segments);
            v.push_back(centre + Vec3f{r * std::sin(phi) * std::cos(theta), r * std::cos(phi),
                                       r * std::sin(phi) * std::sin(theta)});
        }
    }
    v.push_back(centre - Vec3f{0.f, r, 0.f});
    const auto ring = [&](int i, int j) {
        return uint32_t(1 + (i - 1) * segments + (j % segments));
    };
    for (int j = 0; j < segments; ++j) t.push_back({0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            t.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            t.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
    const uint32_t south = uint32_t(v.size() - 1);
    for (int j = 0; j < segments; ++j)
        t.push_back({south, ring(rings - 1, j), ring(rings - 1, j + 1)});
    s.add_mesh(v, t, s.add_material({}));
}

/// Axis-aligned grid of n x n cells on the plane `axis` = c, from lo to hi in the other axes.
void add_grid(Scene& s, int axis, float c, float lo, float hi, int n) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            Vec3f p;
            p[axis] = c;
            p[a1] = lo + (hi - lo) * float(i) / float(n);
            p[a2] = lo + (hi - lo) * float(j) / float(n);
            v.push_back(p);
        }
    const auto at = [&](int i, int j) { return uint32_t(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    s.add_mesh(v, t, s.add_material({}));
}

Scene sphere_scene() {
    Scene s;
    s.name = "sphere";
    add_sphere(s, Vec3f{100.5f, -20.25f, 33.f}, 3.f, 64, 40);
    return s;
}

/// Walls of grids with a sphere: shared edges and vertices everywhere, many hit edge-on.
Scene grid_scene() {
    Scene s;
    s.name = "grids";
    add_grid(s, 1, -1.f, -2.f, 2.f, 24);
    add_grid(s, 0, -2.f, -2.f, 2.f, 16);
    add_grid(s, 2, -2.f, -2.f, 2.f, 16);
    add_sphere(s, Vec3f{0.3f, 0.f, 0.2f}, 0.9f, 40, 24);
    return s;
}

/// Two copies of a grid on one plane, the second shifted by a third of a cell: every ray
/// hitting the overlap meets two triangles at exactly the same t (an artificial worst case).
Scene coplanar_scene() {
    Scene s;
    s.name = "coplanar";
    add_grid(s, 1, 0.f, -1.f, 1.f, 12);
    add_grid(s, 1, 0.f, -1.f + 2.f / 36.f, 1.f + 2.f / 36.f, 12);
    return s;
}

std::vector<Camera> cameras_for(const Scene& scene, uint32_t seed) {
    const Bbox3f box = scene.bounds();
    std::vector<Camera> cams = {default_camera_for(box)};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f), dist(0.4f, 2.5f);
    const float radius = 0.5f * length(box.diagonal());
    while (cams.size() < 4) {
        const Vec3f d{u(rng), u(rng), u(rng)};
        if (dot(d, d) > 1.f || dot(d, d) < 0.01f || std::fabs(normalize(d).y) > 0.95f) continue;
        const Vec3f target = box.center() + Vec3f{u(rng), u(rng), u(rng)} * (0.2f * radius);
        cams.push_back(Camera{box.center() + normalize(d) * (dist(rng) * radius), target,
                              Vec3f{0.f, 1.f, 0.f}, 55.f});
    }
    return cams;
}

// ---- classification ------------------------------------------------------------------------

/// True when the ray's line, at a parameter within [tmin, tmax], passes within
/// edge_tolerance * (distance of the edge's ends from the origin) of an edge of `tri`.
bool grazes(const Ray& ray, const TriangleVerts& tri) {
    const auto d3 = [](const Vec3f& p) { return std::array<double, 3>{p.x, p.y, p.z}; };
    const auto sub = [](auto a, auto b) {
        return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    };
    const auto cr = [](auto a, auto b) {
        return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                     a[0] * b[1] - a[1] * b[0]};
    };
    const auto dt = [](auto a, auto b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const auto o = d3(ray.org), d = d3(ray.dir);
    const Vec3f vs[3] = {tri.v0, tri.v1, tri.v2};
    for (int e = 0; e < 3; ++e) {
        const auto a = sub(d3(vs[e]), o), b = sub(d3(vs[(e + 1) % 3]), o);
        // Distance of a + s (b - a) from the line through 0 along d: |(a + s (b - a)) x d| / |d|.
        const auto w0 = cr(a, d), w1 = cr(sub(b, a), d);
        const double ww = dt(w1, w1);
        const double s = ww > 0 ? std::clamp(-dt(w0, w1) / ww, 0.0, 1.0) : 0.0;
        const std::array<double, 3> p{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                                      a[2] + s * (b[2] - a[2])};
        const std::array<double, 3> w{w0[0] + s * w1[0], w0[1] + s * w1[1], w0[2] + s * w1[2]};
        const double dist = std::sqrt(dt(w, w) / dt(d, d));
        const double scale = std::max(std::sqrt(dt(a, a)), std::sqrt(dt(b, b)));
        const double t = dt(p, d) / dt(d, d);
        const double slack = t_tolerance * std::max(std::fabs(t), 1.0);
        if (dist <= edge_tolerance * scale && t >= ray.tmin - slack &&
            t <= double(ray.tmax) + slack)
            return true;
    }
    return false;
}

/// Our test's t for one triangle, ignoring the ray's interval; NaN on a miss.
double watertight_t(const Ray& ray, const TriangleVerts& tri) {
    const WatertightRay wr(Ray{ray.org, ray.dir, neg_inf, pos_inf});
    float t;
    return intersect_watertight(wr, tri, t) ? double(t) : std::nan("");
}

bool near(double a, double b) {
    return std::fabs(a - b) <= t_tolerance * std::max(std::fabs(a), std::fabs(b));
}

/// Embree said `e`, the oracle `b` (either may be a miss): a tie, or a true mismatch?
bool is_tie(std::span<const TriangleVerts> tris, const Ray& ray, const Hit& e, const Hit& b) {
    if (e.valid() && b.valid() && near(watertight_t(ray, tris[e.tri]), b.t)) return true;
    return (e.valid() && grazes(ray, tris[e.tri])) || (b.valid() && grazes(ray, tris[b.tri]));
}

/// Shadow bits differ: does some triangle meet the segment only within the tolerances?
bool is_shadow_tie(std::span<const TriangleVerts> tris, const Ray& seg) {
    for (const TriangleVerts& tri : tris) {
        const double t = watertight_t(seg, tri);
        if (near(t, seg.tmin) || near(t, seg.tmax) || grazes(seg, tri)) return true;
    }
    return false;
}

struct Tally {
    uint64_t rays = 0, ties = 0, mismatches = 0, holes = 0;
    uint64_t segments = 0, shadow_ties = 0, shadow_mismatches = 0;
};

/// One tracer under test and its disagreements with the oracle so far.
struct Checked {
    std::unique_ptr<Tracer> tracer;
    Tally tally;
};

/// Traces one tile of rays (w x h, row-major) through every tracer and the oracle, then the
/// shadow segments from each light to the oracle's hit points, and tallies disagreements.
void compare_tile(std::vector<Checked>& checked, std::span<const TriangleVerts> tris, int w, int h,
                  std::span<const Ray> rays, bool shaft, std::span<const Vec3f> lights) {
    const size_t n = rays.size();
    std::vector<Hit> truth(n), hits(n);
    std::vector<Vec3f> points(n);
    std::vector<uint32_t> ids(n);
    std::vector<uint8_t> active(n), visible(n), want(n * lights.size());
    for (size_t i = 0; i < n; ++i) {
        truth[i] = trace_brute_force(tris, rays[i]);
        points[i] = rays[i].org + truth[i].t * rays[i].dir;
        ids[i] = truth[i].tri;
        active[i] = truth[i].valid();
        for (size_t l = 0; l < lights.size(); ++l)
            want[l * n + i] =
                active[i] && !occluded_brute_force(tris, shadow_ray(lights[l], points[i]));
    }
    for (Checked& c : checked) {
        Tally& tally = c.tally;
        c.tracer->intersect(RayTile{w, h, rays, shaft}, hits);
        for (size_t i = 0; i < n; ++i) {
            ++tally.rays;
            if (hits[i].tri == truth[i].tri) continue;
            ++(is_tie(tris, rays[i], hits[i], truth[i]) ? tally.ties : tally.mismatches);
            tally.holes += truth[i].valid() && !hits[i].valid();
        }
        for (size_t l = 0; l < lights.size(); ++l) {
            c.tracer->occluded(SegmentTile{w, h, lights[l], points, ids, active, shaft}, visible);
            for (size_t i = 0; i < n; ++i) {
                tally.segments += active[i];
                if (visible[i] == want[l * n + i]) continue;
                const bool tie = active[i] && is_shadow_tie(tris, shadow_ray(lights[l], points[i]));
                ++(tie ? tally.shadow_ties : tally.shadow_mismatches);
            }
        }
    }
}

/// Every Embree kind: its three ways of taking rays, with HIGH and MEDIUM builds.
constexpr const char* embree_kinds[] = {"embree",        "embree-stream",        "embree1",
                                        "embree-medium", "embree-stream-medium", "embree1-medium"};

/// Every Embree kind over `scene`.
std::vector<Checked> embree_tracers(const Scene& scene) {
    static const KdTree no_tree;  // the Embree tracers build their own BVH
    std::vector<Checked> checked;
    for (const char* kind : embree_kinds)
        checked.push_back({make_tracer(kind, scene, no_tree), {}});
    return checked;
}

/// Two lights outside the scene's box.
std::vector<Vec3f> lights_for(const Scene& scene) {
    const Bbox3f box = scene.bounds();
    return {box.hi + box.diagonal() * 0.5f, Vec3f{box.lo.x, box.hi.y, box.center().z} +
                                                Vec3f{-0.3f, 1.f, 0.2f} * length(box.diagonal())};
}

/// Prints each tracer's tally and requires no mismatch, ties at most `max_tie_fraction` of the
/// rays and of the segments.
void expect_agreement(const std::vector<Checked>& checked, const std::string& what,
                      double max_tie_fraction) {
    for (const Checked& c : checked) {
        const Tally& t = c.tally;
        std::printf(
            "[ %-8s ] %-9s rays %llu: ties %llu (holes %llu), mismatches %llu; "
            "segments %llu: ties %llu, mismatches %llu\n",
            std::string(c.tracer->name()).c_str(), what.c_str(), (unsigned long long)t.rays,
            (unsigned long long)t.ties, (unsigned long long)t.holes,
            (unsigned long long)t.mismatches, (unsigned long long)t.segments,
            (unsigned long long)t.shadow_ties, (unsigned long long)t.shadow_mismatches);
        EXPECT_GT(t.segments, t.rays / 4)
            << what;  // the scene fills the view: the test tests something
        EXPECT_EQ(t.mismatches, 0u) << c.tracer->name() << " " << what;
        EXPECT_EQ(t.shadow_mismatches, 0u) << c.tracer->name() << " " << what;
        EXPECT_LE(double(t.ties), max_tie_fraction * double(t.rays))
            << c.tracer->name() << " " << what;
        EXPECT_LE(double(t.shadow_ties), max_tie_fraction * double(t.segments))
            << c.tracer->name() << " " << what;
    }
}

/// Camera tiles of 4K x 4K samples (48 x 32 pixels, K = 1 and 2) from four cameras.
void check_scene(const Scene& scene, double max_tie_fraction) {
    const TriangleArray tris = gather_triangles(scene);
    const std::vector<Vec3f> lights = lights_for(scene);
    std::vector<Checked> checked = embree_tracers(scene);
    for (const Camera& cam : cameras_for(scene, 11))
        for (int k : {1, 2}) {
            const CameraRays camera(cam, 48, 32, k);
            const int side = 4 * k;
            std::vector<Ray> rays(side * side);
            for (int ty = 0; ty < camera.height(); ty += 4)
                for (int tx = 0; tx < camera.width(); tx += 4) {
                    for (int sy = 0; sy < side; ++sy)
                        for (int sx = 0; sx < side; ++sx)
                            rays[sy * side + sx] =
                                Ray{camera.origin(),
                                    camera.direction(tx + sx / k, ty + sy / k, sx % k, sy % k)};
                    compare_tile(checked, tris, side, side, rays, true, lights);
                }
        }
    expect_agreement(checked, scene.name, max_tie_fraction);
}

// ---- tests ---------------------------------------------------------------------------------

TEST(Embree, BuildInfoOnlyForEmbreeKinds) {
    const Scene scene = random_soup(1, 50);
    const KdTree no_tree;
    EXPECT_EQ(embree_build_seconds(*make_tracer("brute", scene, no_tree)), -1.0);
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    for (const char* kind : embree_kinds) {
        const std::unique_ptr<Tracer> t = make_tracer(kind, scene, no_tree);
        EXPECT_EQ(t->name(), kind);
        EXPECT_GE(embree_build_seconds(*t), 0.0);
        EXPECT_GT(embree_memory_bytes(*t), 50 * sizeof(TriangleIndices));
    }
}

// Partial 4x4 blocks (tile sides not multiples of 4) and inactive rays/segments.
TEST(Embree, PartialBlocksAndInactiveLanes) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    Scene scene;
    add_grid(scene, 2, 0.f, -1.f, 1.f, 2);  // 8 triangles on z = 0, no edge at x = +-0.5
    const KdTree no_tree;
    const TriangleArray tris = gather_triangles(scene);
    const int w = 7, h = 5;
    std::vector<Ray> rays;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            rays.push_back(
                Ray{{-0.9f + 0.27f * float(x), -0.85f + 0.31f * float(y), 2.f}, {0.f, 0.f, -1.f}});
    rays[3].tmax = -1.f;                                // inactive
    rays[10] = Ray{{5.f, 5.f, 2.f}, {0.f, 0.f, -1.f}};  // misses
    for (const char* kind : embree_kinds) {
        const std::unique_ptr<Tracer> t = make_tracer(kind, scene, no_tree);
        std::vector<Hit> hits(rays.size(), Hit{0.f, 12345});
        TraceStats stats;
        t->intersect(RayTile{w, h, rays, false}, hits, TraceContext{&stats});
        EXPECT_EQ(stats.tiles, 1u);
        EXPECT_EQ(stats.rays, rays.size());
        std::vector<Vec3f> points;
        std::vector<uint32_t> ids;
        std::vector<uint8_t> active;
        for (size_t i = 0; i < rays.size(); ++i) {
            const Hit want = trace_brute_force(tris, rays[i]);
            EXPECT_EQ(hits[i].tri, want.tri) << kind << " ray " << i;
            if (want.valid()) {
                EXPECT_NEAR(hits[i].t, want.t, 1e-6f);
            }
            points.push_back(rays[i].org + 2.f * rays[i].dir);  // on the plane
            ids.push_back(want.tri);
            active.push_back(i % 5 != 0);
        }
        points[1].z = 1.f;   // above the plane: visible from a light above
        points[2].z = -1.f;  // below: the segment from the light crosses the grid
        std::vector<uint8_t> visible(rays.size(), 7);
        t->occluded(SegmentTile{w, h, Vec3f{0.1f, 0.2f, 3.f}, points, ids, active, false}, visible,
                    TraceContext{&stats});
        EXPECT_EQ(stats.rays, rays.size() + size_t(std::count(active.begin(), active.end(), 1)));
        for (size_t i = 0; i < rays.size(); ++i)
            EXPECT_EQ(visible[i], active[i] && points[i].z >= 0.f) << kind << " segment " << i;
    }
}

// Concurrent tiles give the same answers as serial ones (one device, many threads).
TEST(Embree, ConcurrentTilesAgree) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    const Scene scene = sphere_scene();
    const std::unique_ptr<Tracer> t = make_tracer("embree", scene, KdTree{});
    const CameraRays camera(default_camera_for(scene.bounds()), 128, 96, 1);
    const int tiles_x = 32, tiles = 32 * 24;
    std::vector<Ray> rays(tiles * 16);
    for (int i = 0; i < tiles; ++i)
        for (int s = 0; s < 16; ++s)
            rays[i * 16 + s] =
                Ray{camera.origin(),
                    camera.direction(i % tiles_x * 4 + s % 4, i / tiles_x * 4 + s / 4, 0, 0)};
    std::vector<Hit> serial(rays.size()), parallel(rays.size());
    const auto tile = [&](int i) {
        return RayTile{4, 4, std::span(rays).subspan(i * 16, 16), true};
    };
    for (int i = 0; i < tiles; ++i) t->intersect(tile(i), std::span(serial).subspan(i * 16, 16));
    tbb::parallel_for(
        0, tiles, [&](int i) { t->intersect(tile(i), std::span(parallel).subspan(i * 16, 16)); });
    EXPECT_EQ(serial, parallel);
    EXPECT_GT(std::count_if(serial.begin(), serial.end(), [](const Hit& h) { return h.valid(); }),
              1000);
}

TEST(Embree, AgreesOnRandomSoups) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    for (uint32_t seed : {1u, 2u}) check_scene(random_soup(seed, 1500), 1e-3);
}

TEST(Embree, AgreesOnClosedSphere) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    check_scene(sphere_scene(), 1e-3);
}

TEST(Embree, AgreesOnGridWalls) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    check_scene(grid_scene(), 1e-3);
}

// Rays aimed exactly at the vertices and along the edges of a closed mesh: the hard cases for
// any ray/triangle test. Most land on a tie; none may be a mismatch.
TEST(Embree, RaysAimedAtEdgesAndVertices) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    const Scene scene = sphere_scene();
    const TriangleArray tris = gather_triangles(scene);
    const std::vector<Vec3f> lights = lights_for(scene);
    std::vector<Checked> checked = embree_tracers(scene);
    std::vector<Ray> rays;
    for (const Camera& cam : cameras_for(scene, 5)) {
        for (size_t t = 0; t < tris.size();
             t += 3) {  // every third triangle: 2 of its corners, 2 edge points
            const TriangleVerts& tri = tris[t];
            for (const Vec3f& target : {tri.v0, tri.v1, tri.v0 + (tri.v1 - tri.v0) * 0.5f,
                                        tri.v1 + (tri.v2 - tri.v1) * 0.25f})
                rays.push_back(Ray{cam.position, target - cam.position});
        }
    }
    rays.resize(rays.size() / 16 * 16);
    for (size_t i = 0; i < rays.size(); i += 16)
        compare_tile(checked, tris, 4, 4, std::span(rays).subspan(i, 16), false, lights);
    expect_agreement(checked, "aimed", 1.0);
}

// The classifier itself: a ray through a triangle's interior claimed to hit another triangle
// (or nothing) is a mismatch, not a tie.
TEST(Embree, TieClassifierIsStrict) {
    const std::vector<TriangleVerts> tris = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                             {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}},
                                             {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    const Ray through{{0.25f, 0.25f, 3.f}, {0.f, 0.f, -1.f}};
    const Hit truth = trace_brute_force(tris, through);
    ASSERT_EQ(truth.tri, 1u);
    EXPECT_FALSE(is_tie(tris, through, Hit{}, truth));
    EXPECT_FALSE(is_tie(tris, through, Hit{3.f, 0}, truth));
    EXPECT_TRUE(is_tie(tris, Ray{{0.25f, 0.25f, -3.f}, {0.f, 0.f, 1.f}}, Hit{3.f, 2},
                       Hit{3.f, 0}));                     // coplanar copies
    const Ray edge{{0.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f}};  // through the hypotenuse
    EXPECT_TRUE(is_tie(tris, edge, Hit{}, Hit{2.f, 1}));
    EXPECT_FALSE(
        is_shadow_tie(tris, Ray{{0.25f, 0.25f, 3.f}, {0.f, 0.f, -3.f}, 1e-4f, 1.f - 1e-4f}));
    EXPECT_TRUE(is_shadow_tie(tris, Ray{{0.5f, 0.5f, 3.f}, {0.f, 0.f, -4.f}, 1e-4f, 1.f - 1e-4f}));
}

// Every ray on the overlap is an exact tie, so ties are many; mismatches must still be 0.
TEST(Embree, CoplanarOverlapsAreOnlyTies) {
    if (!has_embree()) GTEST_SKIP() << "built without Embree";
    check_scene(coplanar_scene(), 1.0);
}

}  // namespace
}  // namespace rtt
