// RTT's geometric building blocks: the shaft's conservative rejection tests (a rejected triangle
// is never hit by any ray the shaft accepts, whatever the float test's rounding), the whole-tile
// occluder test, the per-ray check, the region used for shaft culling, and exact plane identity.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "geom/plane_id.h"
#include "geom/triangle.h"
#include "relevant_triangles/conservative_tests.h"
#include "relevant_triangles/region.h"
#include "rtt/camera.h"
#include "rtt/tracer.h"

namespace rtt {
namespace {

/// A dense tile (side x side samples) of a random pinhole camera, made as the renderer makes
/// primary rays, optionally turned into reflected-like rays (common apex elsewhere, per-ray tmin)
/// or shadow-like segments (from a light to points on a plane).
struct DenseTile {
    std::vector<Ray> rays;
    int side = 0;
    Ray corners[4];
};

DenseTile camera_tile(std::mt19937& rng, int k) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const Vec3f pos{u(rng) * 5, u(rng) * 5, u(rng) * 5};
    const Camera cam{
        pos, pos + Vec3f{u(rng), u(rng), u(rng)}, {0, 1, 0}, 30.f + 60.f * (u(rng) + 1.f)};
    const int w = 64, h = 48;
    const CameraRays rays(cam, w, h, k);
    const int tx = int(rng() % (w / 4)), ty = int(rng() % (h / 4));
    DenseTile t;
    t.side = 4 * k;
    for (int sy = 0; sy < t.side; ++sy)
        for (int sx = 0; sx < t.side; ++sx)
            t.rays.push_back(Ray{rays.origin(),
                                 rays.direction(tx * 4 + sx / k, ty * 4 + sy / k, sx % k, sy % k),
                                 0.f, pos_inf});
    return t;
}

void take_corners(DenseTile& t) {
    for (int i = 0; i < 4; ++i) t.corners[i] = t.rays[size_t(corner_sample(t.side, t.side, i))];
}

/// Shadow-like: segments from a light to the points where the tile's rays meet a plane.
DenseTile shadow_tile(std::mt19937& rng, int k) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    DenseTile cam = camera_tile(rng, k);
    const Vec3f o = cam.rays[0].org;
    const Vec3f light = o + Vec3f{u(rng), u(rng), u(rng)} * 4.f;
    const Vec3f n = normalize(Vec3f{u(rng), u(rng), u(rng)});
    const float d = dot(n, o + cam.rays[cam.rays.size() / 2].dir * (2.f + 3.f * (u(rng) + 1.f)));
    DenseTile t;
    t.side = cam.side;
    for (const Ray& r : cam.rays) {
        const float hit = (d - dot(n, o)) / dot(n, r.dir);
        t.rays.push_back(shadow_ray(light, r.org + hit * r.dir));
    }
    return t;
}

/// Reflected-like: a common mirrored apex, directions reflected about a plane, tmin on it.
DenseTile mirror_tile(std::mt19937& rng, int k) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    DenseTile cam = camera_tile(rng, k);
    Vec3f n{u(rng), u(rng), u(rng)};
    n = normalize(n);
    const Vec3f e = cam.rays[0].org;
    const Vec3f at = e + cam.rays[size_t(cam.rays.size() / 2)].dir * 3.f;
    const float d = dot(n, at);
    const Vec3f mirrored = e - n * (2.f * (dot(n, e) - d));
    DenseTile t;
    t.side = cam.side;
    for (const Ray& r : cam.rays) {
        const float t_hit = (d - dot(n, e)) / dot(n, r.dir);
        const Vec3f dir = r.dir - n * (2.f * dot(r.dir, n));
        t.rays.push_back(Ray{mirrored, dir, std::max(t_hit, 0.f) * (1.f + 1e-4f), pos_inf});
    }
    return t;
}

/// A triangle near the shaft: vertices at random depths along random rays of the tile, pushed
/// sideways by a few tile widths, so many sit across the shaft's boundary planes.
TriangleVerts near_triangle(std::mt19937& rng, const DenseTile& t) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const Ray& a = t.rays[size_t(rng() % t.rays.size())];
    const Vec3f spread = t.rays.back().dir - t.rays.front().dir;
    const float width = length(spread);
    const auto vertex = [&] {
        const Ray& r = t.rays[size_t(rng() % t.rays.size())];
        const float s = (r.tmax < 10.f ? 1.f : 4.f) * (0.5f + 0.5f * (u(rng) + 1.f));
        return r.org + r.dir * s + Vec3f{u(rng), u(rng), u(rng)} * (width * 2.5f * s);
    };
    TriangleVerts tri{vertex(), vertex(), vertex()};
    if (rng() % 8 == 0)
        tri.v2 = a.org + a.dir * (a.tmax < 10.f ? 0.7f : 3.f);  // through an inner ray
    if (rng() % 16 == 0) tri.v2 = tri.v1;                       // degenerate
    return tri;
}

struct Counts {
    uint64_t rejected = 0, violations = 0, blockers = 0, blocker_misses = 0, checked_rays = 0;
};

void check_tile(std::mt19937& rng, DenseTile& t, int triangles, Counts& c) {
    take_corners(t);
    Shaft s;
    if (!make_shaft(t.corners, s)) return;
    std::vector<WatertightRay> accepted;
    for (const Ray& r : t.rays)
        if (shaft_accepts(s, r)) accepted.emplace_back(r);
    c.checked_rays += accepted.size();
    const vfloat4 lane_tmax = vfloat4::load(s.tmax);
    for (int k = 0; k < triangles; ++k) {
        const TriangleVerts tri = near_triangle(rng, t);
        const CornerVerdict v = test_corners<Query::any_hit>(s, tri, lane_tmax);
        if (!v.relevant) {
            ++c.rejected;
            for (const WatertightRay& w : accepted) {
                float tt;
                c.violations += intersect_watertight(w, tri, tt);
            }
        }
        if (v.blocks_all) {
            ++c.blockers;
            for (const WatertightRay& w : accepted) {
                float tt;
                c.blocker_misses += !intersect_watertight(w, tri, tt);
            }
        }
    }
}

TEST(Shaft, RejectedTrianglesAreNeverHitByAcceptedRays) {
    std::mt19937 rng(21);
    Counts primary, mirrored, shadows;
    for (int tile = 0; tile < 200; ++tile) {
        DenseTile a = camera_tile(rng, 1 + tile % 6);
        check_tile(rng, a, 60, primary);
        DenseTile b = mirror_tile(rng, 2);
        check_tile(rng, b, 60, mirrored);
        DenseTile c = shadow_tile(rng, 2);
        check_tile(rng, c, 60, shadows);
    }
    for (const Counts* c : {&primary, &mirrored, &shadows}) {
        EXPECT_EQ(c->violations, 0u);
        EXPECT_EQ(c->blocker_misses, 0u);
        EXPECT_GT(c->rejected, 1000u);  // the tests do reject: the check is not vacuous
        EXPECT_GT(c->checked_rays, 5000u);
    }
    EXPECT_GT(shadows.blockers, 0u);
    std::printf(
        "[  shaft   ] rejected %llu / %llu / %llu triangles, 0 hit by %llu / %llu / %llu accepted "
        "rays; "
        "%llu whole-tile occluders\n",
        (unsigned long long)primary.rejected, (unsigned long long)mirrored.rejected,
        (unsigned long long)shadows.rejected, (unsigned long long)primary.checked_rays,
        (unsigned long long)mirrored.checked_rays, (unsigned long long)shadows.checked_rays,
        (unsigned long long)shadows.blockers);
}

// The check must accept every ray of a renderer tile (border samples round a few ulps outside
// the corners' slope quad; the tolerance covers them), or RTT would trace them needlessly.
TEST(Shaft, AcceptsEveryRayOfCameraTiles) {
    std::mt19937 rng(22);
    uint64_t shafts = 0, rays = 0, refused = 0;
    for (int tile = 0; tile < 400; ++tile) {
        DenseTile t = camera_tile(rng, 1 + tile % 6);
        take_corners(t);
        Shaft s;
        if (!make_shaft(t.corners, s)) continue;
        ++shafts;
        for (const Ray& r : t.rays) {
            ++rays;
            refused += !shaft_accepts(s, r);
        }
    }
    EXPECT_GT(shafts, 300u);
    EXPECT_EQ(refused, 0u) << "of " << rays;
}

TEST(Shaft, RefusesWhatIsNotAShaft) {
    const Vec3f o{1, 2, 3};
    Ray c[4] = {
        {o, {0.1f, 0.1f, 1}}, {o, {0.2f, 0.1f, 1}}, {o, {0.1f, 0.2f, 1}}, {o, {0.2f, 0.2f, 1}}};
    Shaft s;
    EXPECT_TRUE(make_shaft(c, s));
    Ray moved[4] = {c[0], c[1], c[2], c[3]};
    moved[2].org.x += 1e-3f;  // not one apex
    EXPECT_FALSE(make_shaft(moved, s));
    Ray crossed[4] = {c[0], c[1], c[3], c[2]};  // corners out of order: a bow tie
    EXPECT_FALSE(make_shaft(crossed, s));
    // In two steps: the rays are fine, the quad is refused.
    EXPECT_TRUE(make_shaft_corners(crossed, s));
    EXPECT_FALSE(s.has_quad);
    EXPECT_FALSE(make_shaft_quad(s));
    EXPECT_FALSE(make_shaft_corners(moved, s));
    Ray flat[4] = {c[0], c[0], c[2], c[2]};  // degenerate quad
    EXPECT_FALSE(make_shaft(flat, s));
    Ray turned[4] = {
        c[0], c[1], c[2], {o, {1, 0.2f, 0.1f}}};  // a corner with another dominant axis
    EXPECT_FALSE(make_shaft(turned, s));
    // A ray outside the quad, or from elsewhere, is not accepted.
    ASSERT_TRUE(make_shaft_corners(c, s));
    ASSERT_TRUE(make_shaft_quad(s));
    EXPECT_TRUE(s.has_quad);
    EXPECT_TRUE(shaft_accepts(s, Ray{o, {0.15f, 0.15f, 1}}));
    EXPECT_FALSE(shaft_accepts(s, Ray{o, {0.25f, 0.15f, 1}}));
    EXPECT_FALSE(shaft_accepts(s, Ray{{1, 2, 3.5f}, {0.15f, 0.15f, 1}}));
    EXPECT_FALSE(shaft_accepts(s, Ray{o, {0.15f, 0.15f, 1}, 0.5f, pos_inf}));  // another start
}

// A box the region test drops contains no point of any accepted ray within its offsets: the
// one-box test, the K-wide test and the cone's slice alone, with and without a start offset.
TEST(Shaft, RegionCullingIsConservative) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    constexpr int K = simd_max_width;
    uint64_t dropped = 0, dropped_wide = 0, dropped_slice = 0, violations = 0;
    for (int tile = 0; tile < 60; ++tile) {
        DenseTile t = camera_tile(rng, 2);
        take_corners(t);
        Shaft s;
        if (!make_shaft(t.corners, s)) continue;
        const Vec3f o = s.org;
        const Bbox3f scene{o - Vec3f(20.f), o + Vec3f(20.f)};
        const float o_lo = tile % 2 ? 0.f : 1.5f * u(rng), o_hi = 2.f + 6.f * u(rng);
        ShaftRegion region(s, scene, o_lo, o_hi);
        // Points of accepted rays between offsets o_lo and o_hi.
        std::vector<Vec3f> points;
        for (const Ray& r : t.rays) {
            if (!shaft_accepts(s, r)) continue;
            const float dz = std::fabs(r.dir[s.kz]);
            for (int k = 0; k <= 16; ++k)
                points.push_back(r.org + r.dir * ((o_lo + (o_hi - o_lo) * float(k) / 16.f) / dz));
        }
        const auto holds_a_point = [&](const Bbox3f& box) {
            uint64_t n = 0;
            for (const Vec3f& p : points)
                n += p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y &&
                     p.z >= box.lo.z && p.z <= box.hi.z;
            return n;
        };
        for (int b = 0; b < 400; b += K) {
            // Boxes around a random point of the shaft, of random size, sometimes shifted off
            // it; K of them for the wide test.
            alignas(64) float lo[3][K], hi[3][K];
            Bbox3f boxes[K];
            for (int i = 0; i < K; ++i) {
                const Vec3f c = points[size_t(rng() % points.size())] +
                                Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 0.2f;
                const Vec3f half = Vec3f(u(rng), u(rng), u(rng)) * 0.05f;
                boxes[i] = Bbox3f{c - half, c + half};
                for (int a = 0; a < 3; ++a) {
                    lo[a][i] = boxes[i].lo[a];
                    hi[a][i] = boxes[i].hi[a];
                }
            }
            vfloat<K> vlo[3], vhi[3];
            for (int a = 0; a < 3; ++a) {
                vlo[a] = vfloat<K>::load(lo[a]);
                vhi[a] = vfloat<K>::load(hi[a]);
            }
            const uint32_t wide = movemask(region.meets<K>(vlo, vhi));
            for (int i = 0; i < K; ++i) {
                if (!(wide >> i & 1)) {
                    ++dropped_wide;
                    violations += holds_a_point(boxes[i]);
                }
                // The slice test alone (relative to the apex, as meets() calls it).
                const vfloat4 rl[3] = {vfloat4(boxes[i].lo.x - o.x), vfloat4(boxes[i].lo.y - o.y),
                                       vfloat4(boxes[i].lo.z - o.z)};
                const vfloat4 rh[3] = {vfloat4(boxes[i].hi.x - o.x), vfloat4(boxes[i].hi.y - o.y),
                                       vfloat4(boxes[i].hi.z - o.z)};
                if (!(movemask(region.slice_meets<4>(rl, rh)) & 1)) {
                    ++dropped_slice;
                    violations += holds_a_point(boxes[i]);
                }
                if (region.meets(BoxV(boxes[i]))) continue;
                ++dropped;
                violations += holds_a_point(boxes[i]);
            }
        }
    }
    EXPECT_GT(dropped, 1000u);
    EXPECT_GT(dropped_wide, 1000u);
    EXPECT_GT(dropped_slice, 500u);
    EXPECT_EQ(violations, 0u);
}

// The region's bounding box drops a box beside the cone that no plane of the cone has wholly
// outside (the box reaches back behind the apex), and keeps one that holds a point of a ray.
TEST(Shaft, RegionBoundsDropBoxesBesideTheCone) {
    const Vec3f o{0.f, 0.f, 0.f};
    Ray c[4];
    for (int i = 0; i < 4; ++i)
        c[i] = Ray{o, normalize(Vec3f{(i & 1) ? 0.1f : 0.f, (i & 2) ? 0.1f : 0.f, 1.f})};
    Shaft s;
    ASSERT_TRUE(make_shaft(c, s));
    const Bbox3f scene{Vec3f(-20.f), Vec3f(20.f)};
    const ShaftRegion region(s, scene, 0.f, 2.f);
    // The cone spans x in [0, 0.2] at offset 2; this box lies at x >= 0.25, from z = -5 to 5.
    const Bbox3f beside{{0.25f, 0.f, -5.f}, {1.f, 0.1f, 5.f}};
    EXPECT_FALSE(region.meets(BoxV(beside)));
    const Bbox3f touching{{0.15f, 0.f, -5.f}, {1.f, 0.1f, 5.f}};
    EXPECT_TRUE(region.meets(BoxV(touching)));
}

// ---- exact plane identity ------------------------------------------------------------------

__extension__ typedef __int128 int128;

/// Exact orientation of float points on a 2^-17 grid within +-64, with 128-bit integers.
int orient3d_reference(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
    const auto q = [](float x) { return int128(std::llround(double(x) * 131072.0)); };
    const int128 ax = q(a.x) - q(d.x), ay = q(a.y) - q(d.y), az = q(a.z) - q(d.z);
    const int128 bx = q(b.x) - q(d.x), by = q(b.y) - q(d.y), bz = q(b.z) - q(d.z);
    const int128 cx = q(c.x) - q(d.x), cy = q(c.y) - q(d.y), cz = q(c.z) - q(d.z);
    const int128 det =
        ax * (by * cz - bz * cy) + bx * (cy * az - cz * ay) + cx * (ay * bz - az * by);
    return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

TEST(PlaneId, Orient3dIsExact) {
    std::mt19937 rng(24);
    std::uniform_int_distribution<int> grid(-64 * 131072, 64 * 131072);
    const auto g = [&] { return float(double(grid(rng)) / 131072.0); };
    uint64_t mismatches = 0, zeros = 0;
    for (int i = 0; i < 200000; ++i) {
        const Vec3f a{g(), g(), g()}, b{g(), g(), g()}, c{g(), g(), g()};
        Vec3f d{g(), g(), g()};
        if (i % 2) {
            // A point on the plane (a + s (b - a) + t (c - a) with small integer s, t), then a
            // neighbour one grid step off it.
            const int s = int(rng() % 5) - 2, t = int(rng() % 5) - 2;
            d = a + (b - a) * float(s) + (c - a) * float(t);
            if (i % 4 == 1) d.z += 1.f / 131072.f;
        }
        if (std::fabs(d.x) > 64 || std::fabs(d.y) > 64 || std::fabs(d.z) > 64) continue;
        const int want = orient3d_reference(a, b, c, d);
        zeros += want == 0;
        mismatches += orient3d_sign(a, b, c, d) != want;
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(zeros, 10000u);
}

TEST(PlaneId, SameIdOnlyForExactlyCoplanarTriangles) {
    std::mt19937 rng(25);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<TriangleVerts> tris;
    // Grids on random planes (coplanar up to the rounding of their vertices: their ids may
    // differ, never wrongly agree), axis-aligned floors (exactly coplanar: one id), triangles
    // one ulp off those floors, and degenerate triangles.
    for (int p = 0; p < 20; ++p) {
        const Vec3f o{u(rng) * 10, u(rng) * 10, u(rng) * 10}, a{u(rng), u(rng), u(rng)},
            b{u(rng), u(rng), u(rng)};
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                tris.push_back({o + a * float(i) + b * float(j),
                                o + a * float(i + 1) + b * float(j),
                                o + a * float(i) + b * float(j + 1)});
    }
    const size_t floors = tris.size();
    for (int i = 0; i < 30; ++i) {
        const float y = float(i % 3);
        tris.push_back({{u(rng), y, u(rng)}, {u(rng), y, u(rng)}, {u(rng), y, u(rng)}});
    }
    tris.push_back({{0.1f, std::nextafter(0.f, 1.f), 0.2f}, {0.3f, 0.f, 0.1f}, {0.2f, 0.f, 0.5f}});
    tris.push_back({{1, 1, 1}, {2, 2, 2}, {3, 3, 3}});  // collinear
    const PlaneIds ids = compute_plane_ids(tris);
    ASSERT_EQ(ids.id.size(), tris.size());
    EXPECT_EQ(ids.id.back(), no_plane);
    uint64_t wrong = 0;
    for (size_t i = 0; i < tris.size(); ++i)
        for (size_t j = i + 1; j < tris.size(); ++j) {
            if (ids.id[i] == no_plane || ids.id[i] != ids.id[j]) continue;
            const TriangleVerts& r = tris[i];
            for (const Vec3f& v : {tris[j].v0, tris[j].v1, tris[j].v2})
                wrong += orient3d_sign(r.v0, r.v1, r.v2, v) != 0;
        }
    EXPECT_EQ(wrong, 0u);
    // Axis-aligned floors at one height share one id; the one-ulp-off triangle has its own.
    for (size_t i = floors; i + 3 < floors + 30; ++i) EXPECT_EQ(ids.id[i], ids.id[i + 3]);
    EXPECT_NE(ids.id[floors + 30], ids.id[floors]);
    for (size_t i = 0; i < floors + 30; ++i) EXPECT_NE(ids.id[i], no_plane);
}

TEST(PlaneId, DegenerateExactlyWhenCollinear) {
    // Points stepped along lines (collinear unless their rounding parts them) and the same
    // triangles with one coordinate one ulp off: degenerate exactly when the exact predicate
    // says collinear, whatever the filter on the rounded normal decides first.
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<TriangleVerts> tris;
    for (int i = 0; i < 4000; ++i) {
        const float scale = i % 2 ? 1e4f : 1.f;
        const Vec3f a{u(rng) * scale, u(rng) * scale, u(rng) * scale};
        const Vec3f d{float(int(rng() % 7) - 3), float(int(rng() % 7) - 3),
                      float(int(rng() % 7) - 3)};
        TriangleVerts t{a, a + d * 0.25f, a + d * 0.5f};
        if (i % 3 == 1) t.v2.y = std::nextafter(t.v2.y, 1e30f);
        if (i % 3 == 2) t.v1.z = std::nextafter(t.v1.z, -1e30f);
        tris.push_back(t);
    }
    const PlaneIds ids = compute_plane_ids(tris);
    uint64_t mismatches = 0, degenerate = 0;
    for (size_t i = 0; i < tris.size(); ++i) {
        const bool line = collinear(tris[i].v0, tris[i].v1, tris[i].v2);
        degenerate += line;
        mismatches += line != (ids.id[i] == no_plane);
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(degenerate, 500u);
    EXPECT_LT(degenerate, 3500u);
}

}  // namespace
}  // namespace rtt
