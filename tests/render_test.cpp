#include "rtt/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <numbers>
#include <tuple>

#include "geom/triangle.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "trace/brute_force.h"

namespace rtt {
namespace {

void add_quad(Scene& s, Vec3f a, Vec3f b, Vec3f c, Vec3f d, uint32_t material) {
    const Vec3f v[] = {a, b, c, d};
    const TriangleIndices t[] = {{0, 1, 2}, {0, 2, 3}};
    s.add_mesh(v, t, material);
}

void add_box(Scene& s, Vec3f lo, Vec3f hi, uint32_t material) {
    std::vector<Vec3f> v;
    for (int i = 0; i < 8; ++i)
        v.push_back({i & 4 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 1 ? hi.z : lo.z});
    s.add_mesh(v,
               std::vector<TriangleIndices>{{0, 1, 3},
                                            {0, 3, 2},
                                            {4, 6, 7},
                                            {4, 7, 5},
                                            {0, 4, 5},
                                            {0, 5, 1},
                                            {2, 3, 7},
                                            {2, 7, 6},
                                            {0, 2, 6},
                                            {0, 6, 4},
                                            {1, 5, 7},
                                            {1, 7, 3}},
               material);
}

/// A UV sphere with vertex normals (a curved surface: shading normals, curved mirrors).
void add_sphere(Scene& s, Vec3f c, float r, int nu, int nv, uint32_t material) {
    std::vector<Vec3f> v, n;
    std::vector<TriangleIndices> t;
    for (int i = 0; i <= nv; ++i)
        for (int j = 0; j <= nu; ++j) {
            const float th = std::numbers::pi_v<float> * float(i) / float(nv);
            const float ph = 2.f * std::numbers::pi_v<float> * float(j) / float(nu);
            const Vec3f d{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
            v.push_back(c + d * r);
            n.push_back(d);
        }
    for (int i = 0; i < nv; ++i)
        for (int j = 0; j < nu; ++j) {
            const uint32_t a = uint32_t(i * (nu + 1) + j), b = a + 1, cc = a + uint32_t(nu + 1),
                           d = cc + 1;
            t.push_back({a, b, d});
            t.push_back({a, d, cc});
        }
    s.add_mesh(v, t, material, n);
}

/// A small room: floor, back wall with a planar mirror, boxes, a diffuse and a mirror sphere,
/// an omni and a spot light.
Scene make_test_scene(Vec3f offset = {}) {
    Scene s;
    s.name = "render-test";
    Material grey;
    const uint32_t diffuse = s.add_material(grey);
    Material red;
    red.diffuse = {0.8f, 0.2f, 0.2f};
    red.specular = Vec3f{0.4f};
    red.shininess = 20.f;
    const uint32_t shiny = s.add_material(red);
    Material mirror;
    mirror.diffuse = Vec3f{0.1f};
    mirror.mirror = 0.85f;
    const uint32_t mirror_id = s.add_material(mirror);
    add_quad(s, {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, diffuse);
    add_quad(s, {-4, 0, -4}, {4, 0, -4}, {4, 3, -4}, {-4, 3, -4}, diffuse);
    add_quad(s, {-2, 0.3f, -3.99f}, {2, 0.3f, -3.99f}, {2, 2.5f, -3.99f}, {-2, 2.5f, -3.99f},
             mirror_id);
    add_box(s, {-2, 0, -1}, {-1, 1.2f, 0}, shiny);
    add_box(s, {1, 0, 0.5f}, {1.8f, 0.6f, 1.5f}, diffuse);
    add_sphere(s, {0.3f, 0.8f, 0.2f}, 0.6f, 16, 10, shiny);
    add_sphere(s, {2.2f, 1.2f, -1.5f}, 0.5f, 12, 8, mirror_id);
    Light omni;
    omni.position = {1.5f, 2.8f, 2.f};
    omni.intensity = 12.f;
    s.lights.push_back(omni);
    Light spot;
    spot.kind = LightKind::spot;
    spot.position = {-1.f, 2.9f, 0.5f};
    spot.direction = {0.f, -1.f, -0.3f};
    spot.inner_angle_deg = 20.f;
    spot.outer_angle_deg = 35.f;
    spot.intensity = 10.f;
    s.lights.push_back(spot);
    for (Vec3f& v : s.vertices) v += offset;
    for (Light& l : s.lights) l.position += offset;
    validate(s);
    return s;
}

/// Triangles of the planar wall mirror in make_test_scene (after floor and wall quads).
constexpr uint32_t planar_mirror_triangles[2] = {4, 5};

Camera test_camera(Vec3f offset = {}) {
    return Camera{
        Vec3f{0.5f, 1.6f, 3.8f} + offset, Vec3f{0.f, 0.9f, -2.f} + offset, {0.f, 1.f, 0.f}, 60.f};
}

/// Scene and tracer kept together (the tracer refers to the scene). These tests are about the
/// renderer, so they use the brute-force oracle ("brute", which needs no kd-tree): a mismatch
/// here is the renderer's fault. Tracers are held to the oracle in their own tests and in
/// cli_test.cpp, through the renderer.
struct Fixture {
    Scene scene;
    KdTree tree;
    std::unique_ptr<Tracer> tracer;
    TriangleArray triangles;

    explicit Fixture(Scene s) : scene(std::move(s)) {
        tracer = make_tracer("brute", scene, tree);
        triangles = gather_triangles(scene);
    }
};

RenderOptions options(int w, int h, int aa) {
    RenderOptions o;
    o.camera = test_camera();
    o.width = w;
    o.height = h;
    o.aa = aa;
    o.threads = 2;
    return o;
}

size_t sample_index(int w, int k, int x, int y, int i, int j) {
    return ((size_t(y) * w + x) * k + j) * k + i;
}

/// Every sample of the hit buffer against brute force on CONVENTIONS' ray; returns mismatches.
uint64_t hit_mismatches(const Fixture& f, const RenderOptions& o, const RenderResult& r) {
    const CameraRays cam(o.camera, o.width, o.height, o.aa);
    uint64_t bad = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
            for (int j = 0; j < o.aa; ++j)
                for (int i = 0; i < o.aa; ++i) {
                    const Ray ray{cam.origin(), cam.direction(x, y, i, j)};
                    const Hit h = trace_brute_force(f.triangles, ray);
                    bad += r.hits[sample_index(o.width, o.aa, x, y, i, j)] != h.tri;
                }
    return bad;
}

TEST(Render, PaddedSizeMatchesBruteForceOnEverySample) {
    Scene unlit = make_test_scene();
    unlit.lights.clear();  // primary rays are the point here; skip the shadow segments
    const Fixture f(std::move(unlit));
    for (const auto& [w, h, k] : {std::tuple{642, 481, 1}, std::tuple{61, 45, 3}}) {
        RenderOptions o = options(w, h, k);
        o.hits_buffer = true;
        const RenderResult r = render(f.scene, *f.tracer, o);
        ASSERT_EQ(r.width, w);
        ASSERT_EQ(r.height, h);
        ASSERT_EQ(r.pixels.size(), size_t(w) * h);
        ASSERT_EQ(r.hits.size(), size_t(w) * h * k * k);
        EXPECT_EQ(hit_mismatches(f, o, r), 0u) << w << "x" << h << " K=" << k;
        // Every tile whole: ceil(w/4) x ceil(h/4) tiles of 4K x 4K primary rays, handed over
        // in regions of R x R pixels cut by the padded image's edge.
        const uint64_t tiles = uint64_t((w + 3) / 4) * uint64_t((h + 3) / 4);
        const int r4 = o.region_pixels() / 4;
        const uint64_t regions =
            uint64_t(((w + 3) / 4 + r4 - 1) / r4) * uint64_t(((h + 3) / 4 + r4 - 1) / r4);
        EXPECT_EQ(r.stats.primary.trace.tiles, regions);
        EXPECT_EQ(r.stats.primary.trace.rays, tiles * 16 * k * k);
        EXPECT_EQ(r.stats.rays_by_depth[0], tiles * 16 * k * k);
        if (k == 1) {
            // The cropped image lines up with the samples: background exactly where the ray missed.
            uint64_t bad = 0;
            for (size_t p = 0; p < r.pixels.size(); ++p)
                bad += (r.pixels[p] == f.scene.background) != (r.hits[p] == invalid_triangle);
            EXPECT_EQ(bad, 0u);
        }
    }
}

/// Records what the renderer hands to the tracer, and checks each batch's promises.
class SpyTracer final : public Tracer {
public:
    explicit SpyTracer(const Tracer& inner) : inner_(inner) {}
    std::string_view name() const override { return "spy"; }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (tile.rays.size() != size_t(tile.width) * size_t(tile.height)) ++bad_shapes;
        for (const Ray& r : tile.rays)
            if (!(r.tmin <= r.tmax) || !(r.tmin >= 0.f)) ++inactive_lanes;
        if (tile.shaft) {
            for (const Ray& r : tile.rays)
                if (!(r.org == tile.rays[0].org)) ++shaft_origin_mismatch;
        } else {
            ++packed_tiles;
            if (tile.height != 1) ++bad_shapes;
        }
        inner_.intersect(tile, hits, context);
        // A reflected shaft tile (tmin > 0) comes off the planar mirror; it must not find the
        // mirror itself again.
        if (tile.shaft && tile.rays[0].tmin > 0.f) {
            ++reflected_shaft_tiles;
            for (const Hit& h : hits)
                mirror_self_hits +=
                    h.tri == planar_mirror_triangles[0] || h.tri == planar_mirror_triangles[1];
        }
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        inner_.occluded(tile, visible, context);
    }

    mutable std::mutex mutex_;
    mutable uint64_t reflected_shaft_tiles = 0, packed_tiles = 0;
    mutable uint64_t bad_shapes = 0, inactive_lanes = 0, shaft_origin_mismatch = 0;
    mutable uint64_t mirror_self_hits = 0;

private:
    const Tracer& inner_;
};

TEST(Render, ReflectedBatchesHaveNoInactiveLanes) {
    // Near the origin and far from it (rounding of the mirrored eye grows with the distance).
    for (const Vec3f offset : {Vec3f{0.f}, Vec3f{4096.f, -1000.f, 3000.f}}) {
        SCOPED_TRACE(offset.x);
        const Fixture f(make_test_scene(offset));
        const SpyTracer spy(*f.tracer);
        RenderOptions o = options(96, 64, 2);
        o.camera = test_camera(offset);
        render(f.scene, spy, o);
        EXPECT_EQ(spy.bad_shapes, 0u);
        EXPECT_EQ(spy.inactive_lanes, 0u);
        EXPECT_EQ(spy.shaft_origin_mismatch, 0u);
        EXPECT_EQ(spy.mirror_self_hits, 0u);
        // The planar wall mirror gives reflected shaft tiles; the mirror sphere packed ones.
        EXPECT_GT(spy.reflected_shaft_tiles, 0u);
        EXPECT_GT(spy.packed_tiles, 0u);
    }
}

// All rays of a render (primary, shadow segments, planar-shaft and packed reflected rays)
// answered exactly: every exact tracer of this build gives the brute-force image bit for bit.
TEST(Render, EveryExactTracerGivesTheSameImage) {
    for (const Vec3f offset : {Vec3f{0.f}, Vec3f{4096.f, -1000.f, 3000.f}}) {
        const Fixture f(make_test_scene(offset));
        const KdTree tree = build_kdtree(f.scene);
        RenderOptions o = options(64, 48, 2);
        o.camera = test_camera(offset);
        o.hits_buffer = o.shadow_buffer = true;
        const RenderResult expected = render(f.scene, *f.tracer, o);
        for (const std::string& kind : tracer_kinds()) {
            if (kind.rfind("embree", 0) == 0) continue;  // Embree is not exact by contract
            SCOPED_TRACE(kind + " offset " + std::to_string(offset.x));
            const std::unique_ptr<Tracer> tracer = make_tracer(kind, f.scene, tree);
            const RenderResult r = render(f.scene, *tracer, o);
            EXPECT_EQ(r.hits, expected.hits);
            EXPECT_EQ(r.shadows, expected.shadows);
            EXPECT_EQ(r.stats.rays_by_depth, expected.stats.rays_by_depth);
            EXPECT_EQ(std::memcmp(r.pixels.data(), expected.pixels.data(),
                                  r.pixels.size() * sizeof(Vec3f)),
                      0);
        }
    }
}

TEST(Render, RttLooseRaysThroughTheBvhGiveTheSameImage) {
    // Reflections off the mirror sphere are tiles that are no shaft; once rtt's BVH is built
    // (here by a call with arbitrary rays) they and their shadow segments go through it.
    const Fixture f(make_test_scene());
    const KdTree tree = build_kdtree(f.scene);
    RenderOptions o = options(64, 48, 2);
    o.hits_buffer = o.shadow_buffer = true;
    // The first render's declined rays pay for the BVH late in the frame (RttTracer::bvh_pays),
    // so its last loose tiles may take it already; with one thread, always the same ones.
    o.threads = 1;
    const RenderResult expected = render(f.scene, *f.tracer, o);
    const std::unique_ptr<Tracer> rtt = make_tracer("rtt", f.scene, tree);
    const RenderResult before = render(f.scene, *rtt, o);
    const Ray probe{{0.f, 1.f, 3.f}, {0.f, 0.f, -1.f}};
    Hit hit;
    intersect_rays(*rtt, std::span(&probe, 1), std::span(&hit, 1));
    const RenderResult after = render(f.scene, *rtt, o);
    EXPECT_LT(before.stats.secondary.rtt.bvh_rays, after.stats.secondary.rtt.bvh_rays);
    EXPECT_GT(after.stats.secondary.rtt.bvh_rays, 0u);
    EXPECT_GT(after.stats.shadow.rtt.bvh_rays, 0u);
    for (const RenderResult* r : {&before, &after}) {
        EXPECT_EQ(r->hits, expected.hits);
        EXPECT_EQ(r->shadows, expected.shadows);
        EXPECT_EQ(
            std::memcmp(r->pixels.data(), expected.pixels.data(), r->pixels.size() * sizeof(Vec3f)),
            0);
    }
}

TEST(Render, ThreadCountDoesNotChangeAnything) {
    const Fixture f(make_test_scene());
    RenderOptions o = options(90, 70, 2);
    o.hits_buffer = o.shadow_buffer = true;
    const AnswerMaps maps{true, 1};
    o.threads = 1;
    const RenderResult a = render(f.scene, *f.tracer, o, maps);
    o.threads = 2;
    const RenderResult b = render(f.scene, *f.tracer, o, maps);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3f)), 0);
    EXPECT_EQ(a.hits, b.hits);
    EXPECT_EQ(a.shadows, b.shadows);
    EXPECT_EQ(a.primary_map, b.primary_map);
    EXPECT_EQ(a.shadow_map, b.shadow_map);
    EXPECT_EQ(a.stats.rays_by_depth, b.stats.rays_by_depth);
    EXPECT_EQ(a.stats.shadow.trace.rays, b.stats.shadow.trace.rays);
}

TEST(Render, BandsInAnyOrderAssembleTheSameImage) {
    const Fixture f(make_test_scene());
    RenderOptions o = options(90, 70, 2);  // 18 tile rows, the last cut to 2 pixel rows
    o.hits_buffer = o.shadow_buffer = o.pixel_hits = true;
    const AnswerMaps maps{true, 1};
    const RenderResult whole = render(f.scene, *f.tracer, o, maps);
    // Bands of 1, 2, 3, 4 and 8 tile rows, handed out last first.
    std::vector<std::pair<int, int>> bands = {{0, 1}, {1, 2}, {3, 3}, {6, 4}, {10, 8}};
    RenderResult assembled = whole;
    for (auto* v : {&assembled.hits, &assembled.shadows}) std::fill(v->begin(), v->end(), 7u);
    std::fill(assembled.pixels.begin(), assembled.pixels.end(), Vec3f{-1.f});
    const size_t spp = size_t(o.aa * o.aa);
    const RenderStats stats = render_bands(
        f.scene, *f.tracer, o,
        [&](int& first, int& count) {
            if (bands.empty()) return false;
            std::tie(first, count) = bands.back();
            bands.pop_back();
            return true;
        },
        [&](RenderResult& band) {
            const size_t at = size_t(band.first_row) * size_t(o.width);
            std::copy(band.pixels.begin(), band.pixels.end(), assembled.pixels.begin() + long(at));
            std::copy(band.hits.begin(), band.hits.end(), assembled.hits.begin() + long(at * spp));
            std::copy(band.shadows.begin(), band.shadows.end(),
                      assembled.shadows.begin() + long(at * spp));
            std::copy(band.depth.begin(), band.depth.end(), assembled.depth.begin() + long(at));
            EXPECT_EQ(band.pixels.size(), size_t(band.rows) * size_t(o.width));
            EXPECT_EQ(band.primary_map.size(), band.pixels.size());
            EXPECT_EQ(band.shadow_map.size(), band.pixels.size());
        },
        maps);
    EXPECT_EQ(std::memcmp(assembled.pixels.data(), whole.pixels.data(),
                          whole.pixels.size() * sizeof(Vec3f)),
              0);
    EXPECT_EQ(assembled.hits, whole.hits);
    EXPECT_EQ(assembled.shadows, whole.shadows);
    EXPECT_EQ(
        std::memcmp(assembled.depth.data(), whole.depth.data(), whole.depth.size() * sizeof(float)),
        0);
    EXPECT_EQ(stats.rays_by_depth, whole.stats.rays_by_depth);
    EXPECT_EQ(stats.primary.trace.rays, whole.stats.primary.trace.rays);
    EXPECT_EQ(stats.shadow.rtt.answered, whole.stats.shadow.rtt.answered);
    // A band outside the image is refused.
    EXPECT_THROW(render_bands(
                     f.scene, *f.tracer, o,
                     [](int& first, int& count) {
                         first = 17, count = 2;
                         return true;
                     },
                     [](RenderResult&) {}),
                 Error);
}

// Regions (RenderOptions::region) of any size, also cut by the image's edge and by bands,
// give the same bytes as 4x4-pixel tiles, with every tracer.
TEST(Render, RegionSizeDoesNotChangeAnything) {
    const Fixture f(make_test_scene());
    RenderOptions o = options(90, 70, 2);
    o.hits_buffer = o.shadow_buffer = o.pixel_hits = true;
    o.region = 4;
    const RenderResult a = render(f.scene, *f.tracer, o);
    for (const int region : {0, 8, 12, 32, 256}) {
        o.region = region;
        const RenderResult b = render(f.scene, *f.tracer, o);
        EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3f)), 0)
            << "region " << region;
        EXPECT_EQ(a.hits, b.hits);
        EXPECT_EQ(a.shadows, b.shadows);
        EXPECT_EQ(a.first_triangle, b.first_triangle);
        EXPECT_EQ(a.stats.rays_by_depth, b.stats.rays_by_depth);
        EXPECT_EQ(a.stats.shadow.trace.rays, b.stats.shadow.trace.rays);
    }
    o.region = 3;
    EXPECT_THROW(render(f.scene, *f.tracer, o), Error);
    o.region = 260;
    EXPECT_THROW(render(f.scene, *f.tracer, o), Error);
    EXPECT_EQ(default_region(1), 32);
    EXPECT_EQ(default_region(2), 8);
    EXPECT_EQ(default_region(3), 8);
    EXPECT_EQ(default_region(6), 8);
    EXPECT_EQ(default_region(9), 4);
}

TEST(Render, ImageDoesNotDependOnRequestedBuffers) {
    const Fixture f(make_test_scene());
    RenderOptions o = options(64, 48, 1);
    const RenderResult plain = render(f.scene, *f.tracer, o);
    o.hits_buffer = o.shadow_buffer = true;
    const RenderResult with = render(f.scene, *f.tracer, o);
    EXPECT_EQ(
        std::memcmp(plain.pixels.data(), with.pixels.data(), plain.pixels.size() * sizeof(Vec3f)),
        0);
    // Every hit sample gets a segment to every light once the buffer is asked for.
    EXPECT_GT(with.stats.shadow.trace.rays, plain.stats.shadow.trace.rays);
}

TEST(Render, ShadowBitsFollowConventions) {
    const Fixture f(make_test_scene());
    RenderOptions o = options(80, 60, 2);
    o.hits_buffer = o.shadow_buffer = true;
    const RenderResult r = render(f.scene, *f.tracer, o);
    const CameraRays cam(o.camera, o.width, o.height, o.aa);
    uint64_t bad = 0, reverse_disagree = 0, hits = 0, lit = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
            for (int j = 0; j < o.aa; ++j)
                for (int i = 0; i < o.aa; ++i) {
                    const size_t s = sample_index(o.width, o.aa, x, y, i, j);
                    const Ray ray{cam.origin(), cam.direction(x, y, i, j)};
                    const Hit h = trace_brute_force(f.triangles, ray);
                    ASSERT_EQ(h.tri, r.hits[s]);
                    if (!h.valid()) {
                        bad += r.shadows[s] != 0;
                        continue;
                    }
                    ++hits;
                    const Vec3f p = ray.org + h.t * ray.dir;
                    for (size_t l = 0; l < f.scene.lights.size(); ++l) {
                        const Vec3f light = f.scene.lights[l].position;
                        const bool visible =
                            !occluded_brute_force(f.triangles, shadow_ray(light, p));
                        const bool bit = (r.shadows[s] >> l) & 1u;
                        bad += bit != visible;
                        lit += bit;
                        const Ray from_p{p, light - p, shadow_epsilon, 1.f - shadow_epsilon};
                        reverse_disagree += !occluded_brute_force(f.triangles, from_p) != visible;
                    }
                    bad += (r.shadows[s] >> f.scene.lights.size()) != 0;  // no stray bits
                }
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(hits, 0u);
    EXPECT_GT(lit, 0u);
    // Information only: CONVENTIONS lets a tracer trace either direction; rounding may differ.
    RecordProperty("reverse_direction_disagreements", int(reverse_disagree));
    std::printf("shadow segments traced p->L disagree with L->p on %llu of %llu\n",
                (unsigned long long)reverse_disagree,
                (unsigned long long)(hits * f.scene.lights.size()));
}

/// Two facing parallel mirrors: every reflected ray bounces until the depth limit.
Scene make_mirror_corridor() {
    Scene s;
    s.name = "corridor";
    const uint32_t floor = s.add_material(Material{});
    Material m;
    m.diffuse = Vec3f{0.2f, 0.3f, 0.2f};
    m.mirror = 0.9f;
    const uint32_t mirror = s.add_material(m);
    add_quad(s, {-2, 0, -10}, {-2, 0, 10}, {2, 0, 10}, {2, 0, -10}, floor);
    add_quad(s, {-2, 0, -10}, {-2, 3, -10}, {-2, 3, 10}, {-2, 0, 10}, mirror);
    add_quad(s, {2, 0, -10}, {2, 0, 10}, {2, 3, 10}, {2, 3, -10}, mirror);
    add_box(s, {-0.3f, 0, -2}, {0.3f, 1.2f, -1.4f}, floor);
    Light l;
    l.position = {0, 2.8f, 0};
    l.intensity = 6.f;
    s.lights.push_back(l);
    validate(s);
    return s;
}

TEST(Render, MirrorDepthLimit) {
    const Fixture f(make_mirror_corridor());
    RenderOptions o = options(64, 48, 1);
    o.camera = Camera{{0.f, 1.5f, 4.f}, {-1.f, 1.2f, 0.f}, {0, 1, 0}, 70.f};
    std::vector<RenderResult> r;
    for (int depth : {0, 1, 4}) {
        o.max_depth = depth;
        r.push_back(render(f.scene, *f.tracer, o));
        const std::vector<uint64_t>& by_depth = r.back().stats.rays_by_depth;
        ASSERT_EQ(by_depth.size(), size_t(depth) + 1);
        for (int d = 1; d <= depth; ++d) EXPECT_GT(by_depth[size_t(d)], 0u) << "depth " << d;
        uint64_t secondary = 0;
        for (int d = 1; d <= depth; ++d) secondary += by_depth[size_t(d)];
        EXPECT_EQ(r.back().stats.secondary.trace.rays, secondary);
    }
    EXPECT_EQ(r[0].stats.secondary.trace.rays, 0u);
    // The first bounce is the same whatever the limit; deeper limits trace more and look different.
    EXPECT_EQ(r[1].stats.rays_by_depth[1], r[2].stats.rays_by_depth[1]);
    EXPECT_NE(
        std::memcmp(r[1].pixels.data(), r[2].pixels.data(), r[1].pixels.size() * sizeof(Vec3f)), 0);
    EXPECT_NE(
        std::memcmp(r[0].pixels.data(), r[1].pixels.data(), r[0].pixels.size() * sizeof(Vec3f)), 0);
}

TEST(Render, FigureFiveMapsHaveOneValuePerPixel) {
    const Fixture f(make_test_scene());
    const RenderResult r = render(f.scene, *f.tracer, options(40, 30, 1), AnswerMaps{true, 0});
    ASSERT_EQ(r.primary_map.size(), 40u * 30u);
    ASSERT_EQ(r.shadow_map.size(), 40u * 30u);
    // The brute-force tracer traces every ray: both maps are black.
    for (uint8_t v : r.primary_map) EXPECT_EQ(v, 0);
    for (uint8_t v : r.shadow_map) EXPECT_EQ(v, 0);
}

TEST(Render, RejectsOptionsOutOfRange) {
    const Fixture f(make_test_scene());
    auto rejects = [&](auto change) {
        RenderOptions o = options(8, 8, 1);
        change(o);
        EXPECT_THROW(render(f.scene, *f.tracer, o), Error);
    };
    rejects([](RenderOptions& o) { o.width = 0; });
    rejects([](RenderOptions& o) { o.height = max_image_side + 1; });
    rejects([](RenderOptions& o) { o.aa = 0; });
    rejects([](RenderOptions& o) { o.aa = max_aa + 1; });
    rejects([](RenderOptions& o) { o.width = o.height = max_image_side, o.aa = 16; });
    rejects([](RenderOptions& o) { o.max_depth = -1; });
    rejects([](RenderOptions& o) { o.threads = -1; });
    rejects([](RenderOptions& o) { o.threads = max_render_threads + 1; });
    rejects([](RenderOptions& o) { o.camera.target = o.camera.position; });
    // Answer maps of a light the scene lacks, or of shadows that are off.
    EXPECT_THROW(render(f.scene, *f.tracer, options(8, 8, 1), AnswerMaps{false, 2}), Error);
    RenderOptions unshadowed = options(8, 8, 1);
    unshadowed.shadows = false;
    EXPECT_THROW(render(f.scene, *f.tracer, unshadowed, AnswerMaps{false, 0}), Error);
    EXPECT_NO_THROW(render(f.scene, *f.tracer, unshadowed, AnswerMaps{true, -1}));
}

TEST(Render, PointLightIntensityScalesWithTheScene) {
    Bbox3f box;
    box.extend({0, 0, 0});
    box.extend({3, 4, 0});  // diagonal 5
    const Light one = make_point_light({1, 1, 1}, box, 1);
    EXPECT_EQ(one.kind, LightKind::omni);
    EXPECT_FLOAT_EQ(one.intensity, 12.5f);
    EXPECT_FLOAT_EQ(make_point_light({1, 1, 1}, box, 5).intensity, 2.5f);
}

}  // namespace
}  // namespace rtt
