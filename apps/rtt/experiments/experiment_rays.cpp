// Arbitrary rays (issue 31's yardstick): what a Python user, a path tracer's bounces or a curved
// mirror send. Two ray sets per scene, made once with a fixed seed: random rays (origins
// uniform in the scene's box, directions uniform on the sphere) and bounce rays (from the
// first hits of the camera's rays, cosine-distributed about the hit triangle's normal, facing
// the camera). Each exact kind and each Embree mode traces them through the library's ray-array
// entry points, closest hit (intersect_rays) and visibility (visible_rays), on 1 thread and on
// all cores; exact kinds are held to `ray`'s answers.
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "experiments/experiment_common.h"
#include "rtt/camera.h"
#include "rtt/error.h"

namespace rtt::bench {

using namespace detail;

namespace {

/// A unit vector uniform on the sphere from two uniforms in [0, 1).
Vec3f on_sphere(float u, float v) {
    const float z = 1.f - 2.f * u, r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = 2.f * std::numbers::pi_v<float> * v;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

std::vector<Ray> random_rays(const Scene& scene, size_t n) {
    const Bbox3f box = scene.bounds();
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        const Vec3f o{box.lo.x + u(rng) * (box.hi.x - box.lo.x),
                      box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                      box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
        const float a = u(rng), b = u(rng);
        r = Ray{o, on_sphere(a, b), 0.f, pos_inf};
    }
    return rays;
}

/// One bounce per camera ray that hits: from the hit point, cosine-distributed about the
/// triangle's normal turned toward the camera; tmin a small fraction of the scene's size.
std::vector<Ray> bounce_rays(const BenchScene& s, const Tracer& reference, int width, int height) {
    const CameraRays camera(s.camera, width, height, 1);
    std::vector<Ray> primary(size_t(width) * size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            primary[size_t(y) * width + x] =
                Ray{camera.origin(), camera.direction(x, y, 0, 0), 0.f, pos_inf};
    std::vector<Hit> hits(primary.size());
    intersect_rays(reference, primary, hits);
    const Bbox3f box = s.scene.bounds();
    const float eps = 1e-4f * length(box.hi - box.lo);
    std::mt19937 rng(32);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<Ray> rays;
    rays.reserve(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].valid()) continue;
        const Ray& p = primary[i];
        const TriangleIndices& t = s.scene.triangles[hits[i].tri];
        const Vec3f &a = s.scene.vertices[t[0]], &b = s.scene.vertices[t[1]],
                    &c = s.scene.vertices[t[2]];
        Vec3f n = cross(b - a, c - a);
        if (length(n) == 0.f) continue;
        n = normalize(n);
        if (dot(n, p.dir) > 0.f) n = -n;
        // Cosine-weighted: a uniform point on the unit disk lifted onto the hemisphere.
        const Vec3f tx =
            normalize(std::fabs(n.x) > 0.5f ? cross(n, Vec3f{0, 1, 0}) : cross(n, Vec3f{1, 0, 0}));
        const Vec3f ty = cross(n, tx);
        const float r = std::sqrt(u(rng)), phi = 2.f * std::numbers::pi_v<float> * u(rng);
        const float dx = r * std::cos(phi), dy = r * std::sin(phi);
        const Vec3f d = tx * dx + ty * dy + n * std::sqrt(std::max(0.f, 1.f - r * r));
        if (length(d) == 0.f) continue;
        rays.push_back(Ray{p.org + p.dir * hits[i].t, d, eps, pos_inf});
    }
    return rays;
}

/// Median wall seconds of `reps` runs of `f` on an arena of `threads`.
template <typename F>
double median_wall(int threads, int reps, F&& f) {
    tbb::task_arena arena(threads);
    std::vector<double> t;
    for (int r = 0; r < reps; ++r) {
        const auto start = std::chrono::steady_clock::now();
        arena.execute(f);
        t.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

const std::vector<std::string> exact_kinds = {"ray",    "bvh",      "bvh-high",
                                              "packet", "packet16", "rtt"};
const std::vector<std::string> embree_kinds = {"embree1", "embree-stream", "embree"};

}  // namespace

ExperimentResult run_rays(const BenchConfig& config, SceneCache& scenes) {
    ExperimentResult r;
    r.id = "rays";
    const size_t n = config.quick() ? 20000 : 1000000;
    const int w = config.quick() ? 128 : 1024, h = config.quick() ? 96 : 768;
    r.title = "Arbitrary rays: " + format_count(n) + " random rays and the bounces of a " +
              size_label(w, h) + " frame, closest hit and visibility";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    std::vector<std::string> wanted = exact_kinds;
    wanted.insert(wanted.end(), embree_kinds.begin(), embree_kinds.end());
    const std::vector<std::string> kinds = available(wanted);
    std::vector<int> thread_counts{1};
    if (const int all = tbb::info::default_concurrency(); all > 1) thread_counts.push_back(all);

    TextTable t;
    t.title = "Mrays/s (wall time, median of " + std::to_string(config.repetitions) + ")";
    t.header = {"scene", "rays", "query", "threads"};
    for (const std::string& k : kinds) t.header.push_back(k);
    t.header.push_back("best exact / embree1");
    nlohmann::json cells = nlohmann::json::array();
    for (const std::string& name : config.scenes) {
        const BenchScene& scene = scenes.get(name);
        std::vector<std::unique_ptr<Tracer>> tracers;
        for (const std::string& k : kinds)
            tracers.push_back(make_tracer(k, scene.scene, scene.tree));
        const Tracer& reference = *tracers[0];  // "ray" comes first
        const std::pair<std::string, std::vector<Ray>> sets[] = {
            {"random", random_rays(scene.scene, n)},
            {"bounce", bounce_rays(scene, reference, w, h)}};
        for (const auto& [set, rays] : sets) {
            std::vector<Hit> want(rays.size()), got(rays.size());
            intersect_rays(reference, rays, want);
            std::vector<uint8_t> want_visible(rays.size()), visible(rays.size());
            for (size_t i = 0; i < rays.size(); ++i) want_visible[i] = want[i].valid() ? 0 : 1;
            for (const bool closest : {true, false})
                for (const int threads : thread_counts) {
                    std::vector<std::string> row{name, set + " " + format_count(rays.size()),
                                                 closest ? "closest" : "visible",
                                                 std::to_string(threads)};
                    double best_exact = 0, embree1 = 0;
                    for (size_t k = 0; k < kinds.size(); ++k) {
                        const Tracer& tracer = *tracers[k];
                        const double s = median_wall(threads, config.repetitions, [&] {
                            if (closest)
                                intersect_rays(tracer, rays, got);
                            else
                                visible_rays(tracer, rays, visible);
                        });
                        uint64_t differ = 0;
                        for (size_t i = 0; i < rays.size(); ++i)
                            differ += closest ? !(got[i].tri == want[i].tri &&
                                                  std::bit_cast<uint32_t>(got[i].t) ==
                                                      std::bit_cast<uint32_t>(want[i].t))
                                              : visible[i] != want_visible[i];
                        const bool exact = std::find(exact_kinds.begin(), exact_kinds.end(),
                                                     kinds[k]) != exact_kinds.end();
                        if (exact && differ != 0)
                            throw Error("rtt bench rays: " + kinds[k] + " differs from ray on " +
                                        std::to_string(differ) + " " + set + " rays of " + name);
                        const double mrays = double(rays.size()) / s * 1e-6;
                        if (exact) best_exact = std::max(best_exact, mrays);
                        if (kinds[k] == "embree1") embree1 = mrays;
                        row.push_back(format_fixed(mrays, 2));
                        cells.push_back({{"scene", name},
                                         {"rays", set},
                                         {"count", rays.size()},
                                         {"query", closest ? "closest" : "visible"},
                                         {"threads", threads},
                                         {"kind", kinds[k]},
                                         {"seconds", s},
                                         {"mrays_per_second", mrays},
                                         {"differences_from_ray", differ}});
                    }
                    row.push_back(embree1 > 0 ? format_ratio(best_exact / embree1) : "-");
                    if (embree1 > 0)
                        r.findings.push_back(name + " " + set + " " + row[2] + ", " +
                                             std::to_string(threads) +
                                             " thread(s): best exact rtt kind / embree1 " +
                                             format_ratio(best_exact / embree1));
                    t.rows.push_back(row);
                }
            std::fprintf(config.log, "  measured %s %s rays\n", name.c_str(), set.c_str());
        }
    }
    t.notes.push_back(
        "Through intersect_rays / visible_rays (the C++ ray-array entry points, as Python's "
        "intersect and visible): chunks of 1,024 rays without a tile shape, the random rays "
        "grouped by octant and origin first (not for Embree's kinds, which take them as given); "
        "packet and packet16 trace chunks as 16-wide packets, bvh, bvh-high and rtt one ray at "
        "a time through a BVH. Exact kinds: 0 differences from ray (checked).");
    print_table(config.log, t);
    r.tables.push_back(t);
    r.extra["rays"] = cells;
    return r;
}

}  // namespace rtt::bench
