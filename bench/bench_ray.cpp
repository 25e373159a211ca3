// Single-ray primary throughput of the reference kd-tree tracer (trace_ray), one thread:
// 1024x768 camera rays, one per pixel (CONVENTIONS' ray generation, rtt::CameraRays), at a
// tessellated bumpy sphere of 131,072 triangles; view 0 frames the whole sphere (54% of the
// rays hit), view 1 is a close-up where every ray hits.
//
//   bench_ray [--help] [Google Benchmark flags, e.g. --benchmark_repetitions=5]
//
// Mrays/s counts every primary ray (hits and misses) per second of CPU time; "hit" is the
// fraction of rays that hit the mesh. Rays are generated once, outside the timed loop.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "geom/triangle.h"
#include "kd_bench_meshes.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "trace/trace_ray.h"

namespace rtt {
namespace {

constexpr int width = 1024, height = 768;

struct Workload {
    Scene scene = kdbench::bumpy_sphere(256, 256);
    KdTree tree = build_kdtree(scene);
    TriangleArray triangles = gather_triangles(scene);
    std::vector<Ray> rays[2];

    Workload() {
        // The sphere has radius 1 +- 0.08. From 2.6 units away it fills the frame's height;
        // from 1.55 units the frame's corners (37.8 degrees off axis) still see it.
        const Camera views[2] = {Camera{{1.2f, 0.9f, 2.1f}, {0, 0, 0}, {0, 1, 0}, 50.f},
                                 Camera{{0.72f, 0.54f, 1.26f}, {0, 0, 0}, {0, 1, 0}, 50.f}};
        for (int v = 0; v < 2; ++v) {
            const CameraRays camera(views[v], width, height, 1);
            rays[v].reserve(size_t(width) * height);
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x)
                    rays[v].push_back({camera.origin(), camera.direction(x, y, 0, 0)});
        }
    }
};

const Workload& workload() {
    static const Workload w;
    return w;
}

void primary_rays(benchmark::State& state) {
    const Workload& w = workload();
    const std::vector<Ray>& rays = w.rays[state.range(0)];
    size_t hits = 0;
    for (auto _ : state) {
        hits = 0;
        for (const Ray& r : rays) hits += trace_ray(w.tree, w.triangles, r).valid();
        benchmark::DoNotOptimize(hits);
    }
    const double n = double(rays.size());
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
    state.counters["Mrays/s"] =
        benchmark::Counter(n * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
    state.counters["hit"] = double(hits) / n;
    state.counters["tris"] = double(w.scene.triangle_count());
    state.SetLabel("reference tracer, 1 thread, 1024x768 primary");
}
BENCHMARK(primary_rays)
    ->ArgName("view")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

}  // namespace
}  // namespace rtt

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::printf(
                "bench_ray: single-ray primary throughput (Mrays/s, 1 thread) of the reference\n"
                "kd-tree tracer, 1024x768 camera rays at a 131k-triangle bumpy sphere\n"
                "(view 0: whole sphere in frame, view 1: close-up, every ray hits).\n"
                "Google Benchmark flags (--benchmark_repetitions=N, ...) apply.\n");
            return 0;
        }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
