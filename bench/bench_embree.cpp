// Embree beside our tracers on exactly the same tiles: a tessellated sphere of ~129k triangles
// on a ground grid, 1024x768, one ray per pixel, 4x4-pixel tiles; primary rays, then shadow
// segments from the reference tracer's hit points to one light. Also the build times of
// Embree's BVH and of our kd-tree.
//
//   bench_embree [--threads=N] [Google Benchmark flags, e.g. --benchmark_filter=Primary]
//
// Tracing runs on the benchmark's thread (one thread); --threads (default 1) caps oneTBB, so
// it sets the threads of the two builds. Counters: Mrays = million rays (or active segments)
// per CPU second of the tracing thread (Google Benchmark's rate; steadier than wall time on a
// shared machine, and the same thing on an idle one); build times are wall seconds per build
// (UseManualTime: Embree's rtcCommitScene alone, our build_kdtree alone).
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.h"
#include "builtin_scenes/procedural.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "trace/trace_embree.h"

namespace rtt {
namespace {

constexpr int width = 1024, height = 768, tile = 4;

/// The scene, the tree and the tiles every tracer answers.
struct Workload {
    Scene scene;
    KdTree tree;
    std::vector<Ray> rays;        ///< Tile after tile, 16 rays each (row-major inside a tile).
    std::vector<Vec3f> points;    ///< Hit point of each ray (reference tracer).
    std::vector<uint32_t> ids;    ///< Triangle each ray hit.
    std::vector<uint8_t> active;  ///< 1 when the ray hit something.
    Vec3f light;
    size_t active_count = 0;
};

Scene sphere_on_ground() {
    Scene s;
    s.name = "sphere129k";
    const uint32_t mat = s.add_material({});
    const proc::Mesh ball = proc::sphere(1.f, 360, 180);
    s.add_mesh(ball.vertices, ball.triangles, mat);
    const proc::Mesh ground =
        proc::quad_grid({-4.f, -1.f, 4.f}, {8.f, 0.f, 0.f}, {0.f, 0.f, -8.f}, 16, 16);
    s.add_mesh(ground.vertices, ground.triangles, mat);
    return s;
}

const Workload& workload() {
    static const Workload w = [] {
        Workload w;
        w.scene = sphere_on_ground();
        w.tree = build_kdtree(w.scene);
        const Camera cam{{2.2f, 1.2f, 2.6f}, {0.f, -0.2f, 0.f}, {0.f, 1.f, 0.f}, 50.f};
        const CameraRays camera(cam, width, height, 1);
        for (int ty = 0; ty < height; ty += tile)
            for (int tx = 0; tx < width; tx += tile)
                for (int y = 0; y < tile; ++y)
                    for (int x = 0; x < tile; ++x)
                        w.rays.push_back(
                            Ray{camera.origin(), camera.direction(tx + x, ty + y, 0, 0)});
        const std::unique_ptr<Tracer> ref = make_tracer("ray", w.scene, w.tree);
        std::vector<Hit> hits(w.rays.size());
        for (size_t i = 0; i < w.rays.size(); i += tile * tile)
            ref->intersect(RayTile{tile, tile, std::span(w.rays).subspan(i, tile * tile), true},
                           std::span(hits).subspan(i, tile * tile));
        for (size_t i = 0; i < w.rays.size(); ++i) {
            w.points.push_back(w.rays[i].org + hits[i].t * w.rays[i].dir);
            w.ids.push_back(hits[i].tri);
            w.active.push_back(hits[i].valid());
            w.active_count += hits[i].valid();
        }
        w.light = {3.f, 5.f, 1.f};
        return w;
    }();
    return w;
}

void primary(benchmark::State& state, const std::string& kind) {
    const Workload& w = workload();
    const std::unique_ptr<Tracer> tracer = make_tracer(kind, w.scene, w.tree);
    std::vector<Hit> hits(w.rays.size());
    for (auto _ : state) {
        for (size_t i = 0; i < w.rays.size(); i += tile * tile)
            tracer->intersect(RayTile{tile, tile, std::span(w.rays).subspan(i, tile * tile), true},
                              std::span(hits).subspan(i, tile * tile));
        benchmark::DoNotOptimize(hits.data());
    }
    state.counters["Mrays"] = benchmark::Counter(double(w.rays.size()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void shadow(benchmark::State& state, const std::string& kind) {
    const Workload& w = workload();
    const std::unique_ptr<Tracer> tracer = make_tracer(kind, w.scene, w.tree);
    std::vector<uint8_t> visible(w.rays.size());
    for (auto _ : state) {
        for (size_t i = 0; i < w.rays.size(); i += tile * tile) {
            const size_t n = tile * tile;
            tracer->occluded(SegmentTile{tile, tile, w.light, std::span(w.points).subspan(i, n),
                                         std::span(w.ids).subspan(i, n),
                                         std::span(w.active).subspan(i, n), true},
                             std::span(visible).subspan(i, n));
        }
        benchmark::DoNotOptimize(visible.data());
    }
    state.counters["Mrays"] = benchmark::Counter(double(w.active_count) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void build_embree(benchmark::State& state) {
    const Workload& w = workload();
    for (auto _ : state)
        state.SetIterationTime(embree_build_seconds(*make_tracer("embree", w.scene, w.tree)));
    state.counters["triangles"] = double(w.scene.triangle_count());
}

void build_kd(benchmark::State& state) {
    const Workload& w = workload();
    for (auto _ : state) state.SetIterationTime(build_kdtree(w.scene).stats.build_seconds);
    state.counters["triangles"] = double(w.scene.triangle_count());
}

}  // namespace
}  // namespace rtt

int main(int argc, char** argv) {
    int threads = 1;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::printf(
                "bench_embree: Embree beside rtt's tracers on a ~129k-triangle sphere on a ground\n"
                "grid, 1024x768, 4x4-pixel tiles, primary rays and shadow segments on one thread,\n"
                "and the build times of Embree's BVH and of the kd-tree.\n"
                "  --threads=N  threads of the two builds (default 1)\n"
                "Google Benchmark flags (--benchmark_filter=..., --benchmark_repetitions=N) "
                "apply.\n");
            return 0;
        }
        if (std::strncmp(argv[i], "--threads=", 10) == 0) {
            if (!rtt::bench::parse_int(argv[i] + 10, threads) || threads < 1 || threads > 4096) {
                std::fprintf(stderr, "bench_embree: error: --threads wants 1..4096, got '%s'\n",
                             argv[i] + 10);
                return 1;
            }
        } else {
            args.push_back(argv[i]);
        }
    }
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    int n = int(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
    for (const std::string& kind : rtt::tracer_kinds()) {
        if (kind == "brute") continue;  // the oracle would take minutes per frame
        benchmark::RegisterBenchmark(("Primary/" + kind).c_str(), rtt::primary, kind)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("Shadow/" + kind).c_str(), rtt::shadow, kind)
            ->Unit(benchmark::kMillisecond);
        if (kind == "embree")
            benchmark::RegisterBenchmark("Build/embree", rtt::build_embree)
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark("Build/kdtree", rtt::build_kd)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
