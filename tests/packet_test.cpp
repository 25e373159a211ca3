// The packet tracers (trace_packet.h, triangle_simd.h) against the oracle and the reference
// tracer: same closest triangle, same t bit for bit, same shadow bits, sample for sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/isa.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "same_hit.h"
#include "trace/brute_force.h"
#include "trace/trace_packet.h"
#include "trace/trace_ray.h"

namespace rtt {
namespace {

// ---- whole tracers on scenes ----------------------------------------------------------------

struct Fixture {
    Scene scene;
    KdTree tree;
    TriangleArray triangles;
    std::vector<std::unique_ptr<Tracer>> packet_tracers;  // "packet", "packet8", "packet16"
    size_t oracle_stride = 1;  ///< Brute force for every n-th sample of a tile (big scenes: > 1).
    bool sound_tree = true;    ///< Every triangle in every leaf it meets (BlockerCache's premise).

    explicit Fixture(Scene s) : scene(std::move(s)) {
        tree = build_kdtree(scene);
        triangles = gather_triangles(scene);
        for (const std::string& kind : tracer_kinds())
            if (kind.starts_with("packet"))
                packet_tracers.push_back(make_tracer(kind, scene, tree));
    }
};

Scene mesh_scene(const std::vector<Vec3f>& vertices,
                 const std::vector<TriangleIndices>& triangles) {
    Scene scene;
    scene.add_mesh(vertices, triangles, scene.add_material(Material{}));
    return scene;
}

/// n random triangles of size ~`size` in [-1, 1]^3 around `center`, some degenerate.
Scene soup(int n, float size, const Vec3f& center, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int i = 0; i < n; ++i) {
        const Vec3f c = center + Vec3f{u(rng), u(rng), u(rng)};
        const auto base = uint32_t(v.size());
        for (int k = 0; k < 3; ++k) v.push_back(c + Vec3f{u(rng), u(rng), u(rng)} * size);
        if (i % 50 == 0) v.back() = v[base];                         // zero area
        if (i % 50 == 1) v.back() = (v[base] + v[base + 1]) * 0.5f;  // collinear
        t.push_back({base, base + 1, base + 2});
    }
    return mesh_scene(v, t);
}

/// Layers of n x n unit quads on z = 0, 1, ..., each quad as 2 triangles, plus an overlapping
/// copy of layer 0 (coplanar duplicates: ties broken by index), offset by `origin`.
Scene quad_grid(int n, int layers, const Vec3f& origin) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int l = 0; l <= layers; ++l) {
        const float z = float(l == layers ? 0 : l);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const auto b = uint32_t(v.size());
                v.push_back(origin + Vec3f{float(x), float(y), z});
                v.push_back(origin + Vec3f{float(x + 1), float(y), z});
                v.push_back(origin + Vec3f{float(x + 1), float(y + 1), z});
                v.push_back(origin + Vec3f{float(x), float(y + 1), z});
                t.push_back({b, b + 1, b + 2});
                t.push_back({b, b + 2, b + 3});
            }
    }
    return mesh_scene(v, t);
}

struct MeshData {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
};

/// A closed UV sphere with bumps (radius (1 +- bump) * scale), centred at `center`.
MeshData bumpy_sphere(int rings, int segments, float bump, const Vec3f& center, float scale = 1.f) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const float th = 3.14159265f * float(r) / float(rings);
            const float ph = 6.28318531f * float(s) / float(segments);
            const float rad = (1.f + bump * std::sin(7.f * th) * std::cos(5.f * ph)) * scale;
            v.push_back(center + Vec3f{std::sin(th) * std::cos(ph), std::cos(th),
                                       std::sin(th) * std::sin(ph)} *
                                     rad);
        }
    const auto at = [&](int r, int s) { return uint32_t(r * segments + s % segments); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            t.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
            t.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
        }
    return {v, t};
}

struct Tally {
    uint64_t rays = 0, hits = 0, segments = 0, visible = 0;
    uint64_t mismatches = 0;      ///< Packet tracers against the oracle.
    uint64_t ray_mismatches = 0;  ///< trace_ray / occluded_ray against the oracle.
    uint64_t vs_ray = 0;          ///< Packet tracers against trace_ray / occluded_ray.
    uint64_t cached = 0;          ///< Shadow lanes a BlockerCache decided (vs_ray counts them).
};

/// Every packet tracer against the oracle and trace_ray on one tile; then the tile's shadow
/// segments from `light` to its hit points (every 7th inactive). The oracle answers every
/// f.oracle_stride-th sample; trace_ray answers all.
void check_tile(const Fixture& f, const RayTile& tile, const Vec3f& light, Tally& tally) {
    const size_t n = tile.rays.size();
    const auto oracle = [&](size_t i) { return i % f.oracle_stride == 0; };
    std::vector<Hit> expected(n), reference(n), got(n);
    for (size_t i = 0; i < n; ++i) {
        reference[i] = trace_ray(f.tree, f.triangles, tile.rays[i]);
        expected[i] = oracle(i) ? trace_brute_force(f.triangles, tile.rays[i]) : reference[i];
        tally.ray_mismatches += !same_hit(reference[i], expected[i]);
        tally.hits += expected[i].valid();
    }
    tally.rays += n;
    for (const auto& tracer : f.packet_tracers) {
        std::fill(got.begin(), got.end(), Hit{-1.f, 12345u});
        tracer->intersect(tile, got);
        for (size_t i = 0; i < n; ++i) {
            tally.mismatches += oracle(i) && !same_hit(got[i], expected[i]);
            tally.vs_ray += !same_hit(got[i], reference[i]);
        }
    }

    std::vector<Vec3f> points(n);
    std::vector<uint32_t> tris(n);
    std::vector<uint8_t> active(n), want(n), reference_bits(n), visible(n);
    for (size_t i = 0; i < n; ++i) {
        const Ray& r = tile.rays[i];
        points[i] = r.org + r.dir * expected[i].t;
        tris[i] = expected[i].tri;
        active[i] = expected[i].valid() && i % 7 != 3;
        reference_bits[i] =
            active[i] && !occluded_ray(f.tree, f.triangles, shadow_ray(light, points[i]));
        want[i] = oracle(i) ? active[i] &&
                                  !occluded_brute_force(f.triangles, shadow_ray(light, points[i]))
                            : reference_bits[i];
        tally.ray_mismatches += reference_bits[i] != want[i];
        tally.segments += active[i];
        tally.visible += want[i];
    }
    const SegmentTile seg{tile.width, tile.height, light, points, tris, active};
    for (const auto& tracer : f.packet_tracers) {
        std::fill(visible.begin(), visible.end(), uint8_t(7));
        tracer->occluded(seg, visible);
        for (size_t i = 0; i < n; ++i) {
            tally.mismatches += oracle(i) && visible[i] != want[i];
            tally.vs_ray += visible[i] != reference_bits[i];
        }
    }
    if (!f.sound_tree) return;
    // Blockers of earlier packets first (trace/blocker_cache.h), from a cache that already
    // holds the tile's last blockers: every packet starts with it filled.
    PacketStats stats;
    BlockerCache blockers;
    for (int pass = 0; pass < 2; ++pass) {
        std::fill(visible.begin(), visible.end(), uint8_t(7));
        occluded_tile_packets<4>(f.tree, f.triangles, seg, visible, &stats, &blockers);
        for (size_t i = 0; i < n; ++i) {
            tally.mismatches += oracle(i) && visible[i] != want[i];
            tally.vs_ray += visible[i] != reference_bits[i];
        }
    }
    tally.cached += stats.cached;
}

/// Primary tiles of CONVENTIONS (4x4 pixels, aa x aa samples each: 4aa x 4aa rays).
void check_camera(const Fixture& f, const Camera& cam, int width, int height, int aa,
                  const Vec3f& light, Tally& tally) {
    const CameraRays cr(cam, width, height, aa);
    const int side = 4 * aa;
    std::vector<Ray> rays(size_t(side * side));
    for (int ty = 0; ty < height; ty += 4)
        for (int tx = 0; tx < width; tx += 4) {
            for (int r = 0; r < side; ++r)
                for (int c = 0; c < side; ++c)
                    rays[size_t(r * side + c)] =
                        Ray{cr.origin(), cr.direction(tx + c / aa, ty + r / aa, c % aa, r % aa)};
            check_tile(f, RayTile{side, side, rays, true}, light, tally);
        }
}

/// Tiles of incoherent rays: random origins in `box`, directions of mixed signs, some
/// axis-parallel (split distances 0 * inf = NaN), origins on integer planes, finite intervals.
/// Odd-sized (5 x 3), and 4 wide (one packet wide from 8 lanes on: read as runs of consecutive
/// rays when the height is a multiple of the packet's, staged lane by lane otherwise).
void check_random(const Fixture& f, const Bbox3f& box, int tiles, unsigned seed, const Vec3f& light,
                  Tally& tally) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    constexpr int shapes[4][2] = {{5, 3}, {4, 4}, {4, 8}, {4, 6}};
    std::vector<Ray> rays;
    for (int k = 0; k < tiles; ++k) {
        const int w = shapes[k % 4][0], h = shapes[k % 4][1];
        rays.resize(size_t(w * h));
        for (Ray& r : rays) {
            const Vec3f d = box.diagonal();
            r.org = box.lo + Vec3f{u(rng) * d.x, u(rng) * d.y, u(rng) * d.z};
            if (rng() % 4 == 0)
                r.org = Vec3f{std::round(r.org.x), std::round(r.org.y), std::round(r.org.z)};
            r.dir = Vec3f{u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f};
            if (rng() % 4 == 0) r.dir[int(rng() % 3)] = rng() % 2 ? 0.f : -0.f;
            if (k % 8 >= 4)
                r.dir = Vec3f{std::fabs(r.dir.x), -std::fabs(r.dir.y),
                              r.dir.z * 0.01f + 0.3f};  // one octant
            r.tmin = rng() % 3 ? 0.f : u(rng);
            r.tmax = rng() % 3 ? pos_inf : u(rng) * 3.f;
        }
        check_tile(f, RayTile{w, h, rays, false}, light, tally);
    }
}

void report(const char* what, const Fixture& f, const Tally& t) {
    std::printf(
        "%s: %llu rays (%llu hits), %llu segments (%llu visible); mismatches against brute force: "
        "%zu packet tracers %llu, trace_ray %llu; packet tracers against trace_ray: %llu; "
        "shadow lanes decided by cached blockers: %llu\n",
        what, (unsigned long long)t.rays, (unsigned long long)t.hits,
        (unsigned long long)t.segments, (unsigned long long)t.visible, f.packet_tracers.size(),
        (unsigned long long)t.mismatches, (unsigned long long)t.ray_mismatches,
        (unsigned long long)t.vs_ray, (unsigned long long)t.cached);
    EXPECT_EQ(t.mismatches, 0u);
    EXPECT_EQ(t.ray_mismatches, 0u);
    EXPECT_EQ(t.vs_ray, 0u);
    EXPECT_GT(t.hits, t.rays / 10);  // the scene is actually in view
    EXPECT_GT(t.visible, 0u);
    EXPECT_GT(t.segments, t.visible);  // some shadows
    if (f.sound_tree) {
        EXPECT_GT(t.cached, 0u) << "no lane was decided by a cached blocker";
    }
}

TEST(PacketTracer, RegisteredForEachBuiltWidth) {
    const Fixture f(soup(10, 0.3f, Vec3f{0.f}, 1));
    ASSERT_GE(f.packet_tracers.size(), 1u);
    EXPECT_EQ(f.packet_tracers[0]->name(), "packet");
    const Isa isa = active_isa();  // packet8 from AVX2 on, packet16 with AVX-512
    EXPECT_EQ(f.packet_tracers.size(), 1u + (isa >= Isa::avx2) + (isa >= Isa::avx512));
}

TEST(PacketTracer, BlockerCacheKeepsTheLatestFirst) {
    BlockerCache c;
    const auto tri = [](float x) { return TriangleVerts{{x, 0, 0}, {x, 1, 0}, {x, 0, 1}}; };
    const auto ids = [&] { return std::vector<uint32_t>(c.id, c.id + c.count); };
    for (uint32_t i = 1; i <= 3; ++i) c.note(i, tri(float(i)));
    EXPECT_EQ(ids(), (std::vector<uint32_t>{3, 2, 1}));
    c.note(1, tri(1.f));  // moves to the front, nothing dropped
    EXPECT_EQ(ids(), (std::vector<uint32_t>{1, 3, 2}));
    for (uint32_t i = 4; i <= 6; ++i) c.note(i, tri(float(i)));  // full: the oldest go
    ASSERT_EQ(BlockerCache::size, 4);
    EXPECT_EQ(ids(), (std::vector<uint32_t>{6, 5, 4, 1}));
    for (int k = 0; k < c.count; ++k) EXPECT_EQ(c.tri[k].v0.x, float(c.id[k]));
}

TEST(PacketTracer, RandomSoupMatchesBruteForce) {
    const Fixture f(soup(3000, 0.15f, Vec3f{0.f}, 21));
    Tally t;
    check_camera(f, Camera{{2.5f, 1.5f, 3.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 50.f}, 32, 24, 2,
                 {3, 4, -2}, t);
    check_random(f, Bbox3f{{-2, -2, -2}, {2, 2, 2}}, 150, 22, {0.f, 3.f, 0.f}, t);
    report("soup", f, t);
}

TEST(PacketTracer, CoplanarQuadGridsMatchBruteForce) {
    // Axis-aligned, coplanar and duplicated triangles; the camera looks straight down the
    // z axis (directions with zero x/y components at the centre) and then edge-on.
    for (const Vec3f origin : {Vec3f{0.f}, Vec3f{4096.f, -1536.5f, 2048.f}}) {
        const Fixture f(quad_grid(12, 3, origin));
        Tally t;
        check_camera(f,
                     Camera{origin + Vec3f{6.f, 6.f, 9.f},
                            origin + Vec3f{6.f, 6.f, 0.f},
                            {0.f, 1.f, 0.f},
                            70.f},
                     24, 24, 1, origin + Vec3f{3.f, 7.f, 5.5f}, t);
        check_camera(f,
                     Camera{origin + Vec3f{-4.f, 6.f, 1.f},
                            origin + Vec3f{6.f, 6.f, 1.f},
                            {0.f, 0.f, 1.f},
                            60.f},
                     16, 16, 3, origin + Vec3f{6.f, 3.f, 2.5f}, t);
        check_random(f, Bbox3f{origin + Vec3f{-1.f}, origin + Vec3f{13.f, 13.f, 4.f}}, 150, 23,
                     origin + Vec3f{6.f, 6.f, 3.5f}, t);
        report(origin.x == 0.f ? "quad grid" : "quad grid far from origin", f, t);
    }
}

TEST(PacketTracer, MeshSeenEdgeOnMatchesBruteForce) {
    // A bumpy sphere flattened to a disc in y = 0 (a mesh of overlapping coplanar triangles),
    // a small sphere above it casting a shadow; cameras in the disc's plane, grazing it, and
    // above it.
    MeshData disc = bumpy_sphere(24, 48, 0.2f, Vec3f{0.f});
    for (Vec3f& v : disc.v) v.y = 0.f;
    const MeshData ball = bumpy_sphere(8, 16, 0.f, Vec3f{0.f, 0.5f, 0.f}, 0.3f);
    Scene s = mesh_scene(disc.v, disc.t);
    s.add_mesh(ball.v, ball.t, 0);
    const Fixture f(std::move(s));
    Tally t;
    const Vec3f light{0.1f, 2.f, 0.2f};
    check_camera(f, Camera{{0.3f, 0.f, 4.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 40.f}, 32, 16, 2,
                 light, t);
    check_camera(f, Camera{{0.3f, 0.01f, 4.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 40.f}, 16, 16, 2,
                 light, t);
    check_camera(f, Camera{{0.3f, 2.5f, 3.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 40.f}, 32, 32, 2,
                 light, t);
    report("edge-on", f, t);
}

TEST(PacketTracer, ClosedSphereFarFromOriginIsWatertight) {
    // Embree's pattern: rays from inside a closed mesh far from the origin must all hit it.
    const Vec3f c{20000.f, -12000.f, 7000.f};
    const MeshData sphere = bumpy_sphere(40, 80, 0.1f, c);
    const Fixture f(mesh_scene(sphere.v, sphere.t));
    Tally t;
    check_camera(
        f, Camera{c + Vec3f{0.1f, 0.2f, 0.3f}, c + Vec3f{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 120.f},
        32, 16, 2, c + Vec3f{0.f, 0.5f, 0.f}, t);
    EXPECT_EQ(t.hits, t.rays);  // no ray slipped out between triangles
    check_camera(f, Camera{c + Vec3f{0.f, 0.f, 2.5f}, c, {0.f, 1.f, 0.f}, 60.f}, 16, 16, 2,
                 c + Vec3f{2.f, 2.f, 2.f}, t);
    report("sphere far from origin", f, t);
}

/// A deliberately broken kd-tree: median splits of triangle centroids, each triangle in the one
/// leaf holding its centroid, so triangles that straddle a split are missing on one side.
void build_centroid_tree(KdTree& tree, std::span<const TriangleVerts> tris,
                         std::vector<uint32_t> ids, int depth) {
    const uint32_t index = uint32_t(tree.nodes.size());
    tree.nodes.emplace_back();
    const auto centroid = [&](uint32_t i) {
        return (tris[i].v0 + tris[i].v1 + tris[i].v2) * (1.f / 3.f);
    };
    if (ids.size() <= 2 || depth == 12) {
        tree.nodes[index].set_leaf(uint32_t(tree.leaf_triangles.size()), uint32_t(ids.size()));
        tree.leaf_triangles.insert(tree.leaf_triangles.end(), ids.begin(), ids.end());
        return;
    }
    const int axis = depth % 3;
    std::sort(ids.begin(), ids.end(),
              [&](uint32_t a, uint32_t b) { return centroid(a)[axis] < centroid(b)[axis]; });
    const size_t half = ids.size() / 2;
    const float split = centroid(ids[half])[axis];
    build_centroid_tree(tree, tris, {ids.begin(), ids.begin() + long(half)}, depth + 1);
    const auto above = uint32_t(tree.nodes.size());
    build_centroid_tree(tree, tris, {ids.begin() + long(half), ids.end()}, depth + 1);
    tree.nodes[index].set_inner(axis, split, above);
}

TEST(PacketTracer, SameNodesAsTraceRayEvenOnABrokenTree) {
    // Each lane must visit the scalar ray's nodes in the scalar order: then a tree that lost
    // triangles gives wrong answers, but the same wrong answers in every tracer.
    Fixture f(soup(2000, 0.2f, Vec3f{0.f}, 31));
    f.tree = KdTree{};
    f.tree.bounds = f.scene.bounds();
    std::vector<uint32_t> all(f.triangles.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    build_centroid_tree(f.tree, f.triangles, all, 0);
    f.sound_tree = false;
    f.packet_tracers.clear();
    for (const std::string& kind : tracer_kinds())
        if (kind.starts_with("packet"))
            f.packet_tracers.push_back(make_tracer(kind, f.scene, f.tree));
    Tally t;
    check_camera(f, Camera{{2.5f, 1.5f, 3.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 50.f}, 32, 24, 2,
                 {3, 4, -2}, t);
    check_random(f, Bbox3f{{-2, -2, -2}, {2, 2, 2}}, 150, 32, {0.f, 3.f, 0.f}, t);
    std::printf(
        "broken tree: %llu rays, trace_ray wrong on %llu; packet tracers against trace_ray: %llu\n",
        (unsigned long long)t.rays, (unsigned long long)t.ray_mismatches,
        (unsigned long long)t.vs_ray);
    EXPECT_GT(t.ray_mismatches, 0u);  // the tree really is broken
    EXPECT_EQ(t.vs_ray, 0u);
}

TEST(PacketTracer, BuiltinScenesMatchReference) {
    // The three built-in scenes from their own camera and from the default diagonal one, with
    // two of their lights; the oracle checks every 97th sample (the scenes are large).
    for (const BuiltinSceneInfo& info : builtin_scenes()) {
        Fixture f(make_builtin_scene(info.name));
        f.oracle_stride = 97;
        ASSERT_TRUE(f.scene.camera.has_value());
        ASSERT_GE(f.scene.lights.size(), 2u);
        Tally t;
        check_camera(f, *f.scene.camera, 48, 32, 2, f.scene.lights[0].position, t);
        check_camera(f, default_camera_for(f.scene.bounds()), 32, 24, 1, f.scene.lights[1].position,
                     t);
        report(info.name.c_str(), f, t);
    }
}

}  // namespace
}  // namespace rtt
