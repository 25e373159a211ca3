#include "rtt/builtin_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "builtin_scenes/procedural.h"
#include "geom/triangle.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "trace/brute_force.h"

namespace rtt {
namespace {

/// Each scene is generated once for the whole test program.
const Scene& scene(const std::string& name) {
    static std::map<std::string, Scene> cache;
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, make_builtin_scene(name)).first;
    return it->second;
}

struct Expectation {
    const char* name;
    size_t min_triangles;
    size_t lights;
    LightKind kind;
    Vec3f room;  ///< The closed room is [0, room].
};

const Expectation expectations[] = {
    {"room", 50000, 7, LightKind::spot, {6.f, 3.f, 5.f}},
    {"office", 150000, 16, LightKind::omni, {12.f, 3.f, 9.f}},
    {"plants", 400000, 16, LightKind::omni, {12.f, 3.f, 9.f}},
};

/// Squared distance from p to triangle abc (closest point by Voronoi regions, Ericson 5.1.5),
/// in double so that it is exact enough to tell centimetres apart.
double distance2_to_triangle(const Vec3f& pf, const Vec3f& af, const Vec3f& bf, const Vec3f& cf) {
    struct D {
        double x, y, z;
    };
    auto d = [](const Vec3f& v) { return D{v.x, v.y, v.z}; };
    auto sub = [](D u, D v) { return D{u.x - v.x, u.y - v.y, u.z - v.z}; };
    auto dt = [](D u, D v) { return u.x * v.x + u.y * v.y + u.z * v.z; };
    auto add_scaled = [](D u, D v, double s) {
        return D{u.x + v.x * s, u.y + v.y * s, u.z + v.z * s};
    };
    const D p = d(pf), a = d(af), b = d(bf), c = d(cf);
    const D ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    auto dist2 = [&](D q) {
        const D e = sub(p, q);
        return dt(e, e);
    };
    const double d1 = dt(ab, ap), d2 = dt(ac, ap);
    if (d1 <= 0 && d2 <= 0) return dist2(a);
    const D bp = sub(p, b);
    const double d3 = dt(ab, bp), d4 = dt(ac, bp);
    if (d3 >= 0 && d4 <= d3) return dist2(b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return dist2(add_scaled(a, ab, d1 / (d1 - d3)));
    const D cp = sub(p, c);
    const double d5 = dt(ab, cp), d6 = dt(ac, cp);
    if (d6 >= 0 && d5 <= d6) return dist2(c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return dist2(add_scaled(a, ac, d2 / (d2 - d6)));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return dist2(add_scaled(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const double denom = 1.0 / (va + vb + vc);
    return dist2(add_scaled(add_scaled(a, ab, vb * denom), ac, vc * denom));
}

TEST(BuiltinScenes, ListsRoomOfficePlantsInOrder) {
    const std::vector<BuiltinSceneInfo> list = builtin_scenes();
    ASSERT_EQ(list.size(), 3u);
    EXPECT_EQ(list[0].name, "room");
    EXPECT_EQ(list[1].name, "office");
    EXPECT_EQ(list[2].name, "plants");
    for (const BuiltinSceneInfo& info : list) {
        EXPECT_TRUE(is_builtin_scene(info.name));
        EXPECT_FALSE(info.description.empty());
    }
    EXPECT_FALSE(is_builtin_scene("kitchen"));
    EXPECT_FALSE(is_builtin_scene(""));
}

TEST(BuiltinScenes, UnknownNameThrows) {
    EXPECT_THROW(make_builtin_scene("kitchen"), Error);
    EXPECT_THROW(make_builtin_scene("Room"), Error);
}

TEST(BuiltinScenes, ValidateAndMeetTriangleMinimums) {
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Scene& s = scene(e.name);
        EXPECT_EQ(s.name, e.name);
        EXPECT_NO_THROW(validate(s));
        EXPECT_GE(s.triangle_count(), e.min_triangles);
        EXPECT_EQ(s.normals.size(), s.vertices.size());
    }
}

TEST(BuiltinScenes, GeometryFillsExactlyTheClosedRoom) {
    // The room shell is the bounding box: nothing pokes through a wall, floor or ceiling.
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Bbox3f box = scene(e.name).bounds();
        EXPECT_EQ(box.lo, Vec3f(0.f));
        EXPECT_EQ(box.hi, e.room);
    }
}

TEST(BuiltinScenes, HaveNoDegenerateTrianglesAndUnitOrZeroNormals) {
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Scene& s = scene(e.name);
        size_t degenerate = 0;
        for (const TriangleIndices& t : s.triangles) {
            const Vec3f n =
                cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]);
            if (!(dot(n, n) > 0.f)) ++degenerate;
        }
        EXPECT_EQ(degenerate, 0u);
        size_t bad_normals = 0;
        for (const Vec3f& n : s.normals)
            if (!(n == Vec3f{0.f}) && std::fabs(length(n) - 1.f) > 1e-4f) ++bad_normals;
        EXPECT_EQ(bad_normals, 0u);
    }
}

TEST(BuiltinScenes, LightsHaveTheRightKindAndSitInsideTheRoomAwayFromSurfaces) {
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Scene& s = scene(e.name);
        ASSERT_EQ(s.lights.size(), e.lights);
        for (const Light& l : s.lights) {
            EXPECT_EQ(l.kind, e.kind);
            EXPECT_GT(l.intensity, 0.f);
            for (int a = 0; a < 3; ++a) {
                EXPECT_GT(l.position[a], 0.f);
                EXPECT_LT(l.position[a], e.room[a]);
            }
            if (l.kind == LightKind::spot) {
                EXPECT_LT(l.direction.y, 0.f);  // ceiling spots point down
                EXPECT_GT(l.inner_angle_deg, 0.f);
                EXPECT_LT(l.inner_angle_deg, l.outer_angle_deg);
                EXPECT_LT(l.outer_angle_deg, 90.f);
            }
        }
        // No light on (or inside) a surface: each is more than 5 cm from every triangle.
        for (size_t i = 0; i < s.lights.size(); ++i) {
            double nearest = 1e30;
            for (const TriangleIndices& t : s.triangles)
                nearest =
                    std::min(nearest, distance2_to_triangle(s.lights[i].position, s.vertices[t[0]],
                                                            s.vertices[t[1]], s.vertices[t[2]]));
            EXPECT_GT(std::sqrt(nearest), 0.05) << "light " << i;
        }
    }
}

TEST(BuiltinScenes, CamerasLookAcrossTheRoomFromInside) {
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Scene& s = scene(e.name);
        ASSERT_TRUE(s.camera.has_value());
        EXPECT_NO_THROW(CameraRays(*s.camera, 640, 480, 1));
        for (int a = 0; a < 3; ++a) {
            EXPECT_GT(s.camera->position[a], 0.f);
            EXPECT_LT(s.camera->position[a], e.room[a]);
        }
        // Looking across: the target is at least half the room's depth away.
        EXPECT_GT(length(s.camera->target - s.camera->position),
                  0.5f * std::min(e.room.x, e.room.z));
    }
}

TEST(BuiltinScenes, RoomHasOneLargePlanarMirrorInView) {
    const Scene& s = scene("room");
    std::vector<uint32_t> mirrors;
    for (uint32_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].mirror > 0.f) mirrors.push_back(i);
    ASSERT_EQ(mirrors.size(), 1u);
    const uint32_t mirror = mirrors[0];
    EXPECT_GE(s.materials[mirror].mirror, 0.8f);
    EXPECT_LE(s.materials[mirror].mirror, 0.9f);

    // Every vertex of every mirror triangle lies exactly on the plane of the first one.
    std::vector<uint32_t> tris;
    for (uint32_t i = 0; i < s.triangles.size(); ++i)
        if (s.triangle_material[i] == mirror) tris.push_back(i);
    ASSERT_FALSE(tris.empty());
    const TriangleIndices& t0 = s.triangles[tris[0]];
    const Vec3f p0 = s.vertices[t0[0]];
    const Vec3f n = cross(s.vertices[t0[1]] - p0, s.vertices[t0[2]] - p0);
    size_t off_plane = 0;
    double area = 0;
    for (uint32_t i : tris) {
        const TriangleIndices& t = s.triangles[i];
        for (uint32_t v : t)
            if (dot(n, s.vertices[v] - p0) != 0.f) ++off_plane;
        area += 0.5 * length(cross(s.vertices[t[1]] - s.vertices[t[0]],
                                   s.vertices[t[2]] - s.vertices[t[0]]));
    }
    EXPECT_EQ(off_plane, 0u);
    EXPECT_GT(area, 1.5);  // square metres

    // The default view shows it: a coarse grid of primary rays hits it often.
    const TriangleArray verts = gather_triangles(s);
    const int w = 24, h = 18;
    const CameraRays cam(*s.camera, w, h, 1);
    int hits = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Hit hit = trace_brute_force(verts, Ray{cam.origin(), cam.direction(x, y, 0, 0)});
            if (hit.valid() && s.triangle_material[hit.tri] == mirror) ++hits;
        }
    EXPECT_GE(hits, w * h / 25) << hits;
}

TEST(BuiltinScenes, GenerationIsDeterministic) {
    for (const Expectation& e : expectations) {
        SCOPED_TRACE(e.name);
        const Scene& a = scene(e.name);
        const Scene b = make_builtin_scene(e.name);
        EXPECT_TRUE(a.vertices == b.vertices);
        EXPECT_TRUE(a.normals == b.normals);
        EXPECT_TRUE(a.triangles == b.triangles);
        EXPECT_TRUE(a.triangle_material == b.triangle_material);
        ASSERT_EQ(a.lights.size(), b.lights.size());
        for (size_t i = 0; i < a.lights.size(); ++i) {
            EXPECT_EQ(a.lights[i].position, b.lights[i].position);
            EXPECT_EQ(a.lights[i].direction, b.lights[i].direction);
        }
    }
}

// Closed primitives must be closed surfaces wound outward: after merging vertices by position,
// every directed edge has exactly one opposite partner, and the enclosed volume (divergence
// theorem) is positive and close to the analytic one.
struct Closedness {
    size_t unmatched_edges = 0;
    double volume = 0;
};

Closedness closedness(const proc::Mesh& m) {
    using Key = std::tuple<float, float, float, float, float, float>;
    std::map<Key, int> edges;
    Closedness c;
    for (const TriangleIndices& t : m.triangles) {
        const Vec3f a = m.vertices[t[0]], b = m.vertices[t[1]], d = m.vertices[t[2]];
        c.volume += double(dot(a, cross(b, d))) / 6.0;
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = m.vertices[t[size_t(k)]], q = m.vertices[t[size_t((k + 1) % 3)]];
            ++edges[{p.x, p.y, p.z, q.x, q.y, q.z}];
        }
    }
    for (const auto& [key, count] : edges) {
        const auto& [px, py, pz, qx, qy, qz] = key;
        const auto rev = edges.find({qx, qy, qz, px, py, pz});
        if (count != 1 || rev == edges.end() || rev->second != 1) ++c.unmatched_edges;
    }
    return c;
}

TEST(Procedural, ClosedPrimitivesAreWatertightAndWoundOutward) {
    using namespace proc;
    const float pi_f = proc::pi;
    const Vec2f polygon[] = {{0.f, 0.f},   {1.f, 0.f},  {1.f, 0.4f},
                             {0.4f, 0.4f}, {0.4f, 1.f}, {0.f, 1.f}};
    const std::vector<Vec2f> profile{{0.f, 0.f},  {0.3f, 0.f}, {0.3f, 0.f},
                                     {0.3f, 1.f}, {0.3f, 1.f}, {0.f, 1.f}};
    const Vec3f path[3] = {{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.5f, 1.5f, 0.f}};
    const float radii[3] = {0.1f, 0.1f, 0.1f};
    struct Case {
        const char* name;
        Mesh mesh;
        double volume;  // analytic, 0 = only check the sign
    };
    const Case cases[] = {
        {"box", box({0.f, 0.f, 0.f}, {1.f, 2.f, 3.f}, 0.4f), 6.0},
        {"rounded_box", rounded_box({0.5f, 0.3f, 0.2f}, 0.1f, 4, Shading::smooth, 0.1f),
         // Steiner: the inner 0.8 x 0.4 x 0.2 box grown by r = 0.1: V + r S + pi r^2 E / 4 +
         // 4/3 pi r^3 (S its area, E its total edge length).
         8.0 * 0.4 * 0.2 * 0.1 + 2.0 * 0.1 * (4.0 * (0.4 * 0.2 + 0.2 * 0.1 + 0.1 * 0.4)) +
             pi_f * 0.01 * (2.0 * (0.4 + 0.2 + 0.1)) + 4.0 / 3.0 * pi_f * 0.001},
        {"lathe_cylinder", lathe(profile, 64), pi_f * 0.09},
        {"cylinder", cylinder(0.2f, 0.1f, 1.f, 48), pi_f / 3.0 * (0.04 + 0.02 + 0.01)},
        {"sphere", sphere(1.f, 64, 32), 4.0 / 3.0 * pi_f},
        {"torus", torus(1.f, 0.25f, 64, 32), 2.0 * pi_f * pi_f * 0.0625},
        {"extrude", extrude(polygon, 0.5f), 0.5 * (1.0 * 0.4 + 0.4 * 0.6)},
        {"tube", tube(path, radii, 32, true), 0.0},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const Closedness r = closedness(c.mesh);
        EXPECT_EQ(r.unmatched_edges, 0u);
        EXPECT_GT(r.volume, 0.0);
        if (c.volume > 0.0) {
            EXPECT_NEAR(r.volume, c.volume, 0.01 * c.volume);
        }
        EXPECT_EQ(c.mesh.normals.size(), c.mesh.vertices.size());
    }
}

TEST(Procedural, SceneRngFloatsComeFromTheSpecifiedEngineOutputs) {
    // std::mt19937 is fully specified: its 10000th output from seed 5489 is 4123659995. Our
    // floats are that output's top 24 bits times 2^-24, the same on every standard library.
    proc::SceneRng rng(5489u);
    for (int i = 0; i < 9999; ++i) {
        const float u = rng.uniform();
        ASSERT_GE(u, 0.f);
        ASSERT_LT(u, 1.f);
    }
    EXPECT_EQ(rng.uniform(), float(4123659995u >> 8) * 0x1p-24f);
}

}  // namespace
}  // namespace rtt
