// SAH kd-tree build time (binned and refined levels, exact small-node search below) on
// generated meshes of 10k, 100k, 1M and 4M triangles: a tessellated bumpy sphere and a soup of
// small random triangles, with one thread and with all of them (oneTBB; the tree is the same
// either way); and Embree's BVH build (quality HIGH) on the same meshes, as `rtt bench build`
// times it, when this build has Embree.
//
//   bench_kdbuild [--help] [Google Benchmark flags, e.g. --benchmark_filter=threads:1]
//
// Time is wall-clock per build (UseRealTime); build_s is the same from KdStats, cpu_s the CPU
// time of the whole process (all threads) per build, which a loaded machine does not inflate,
// and cpu_ns/NlogN = cpu_s / (N log2 N) stays about flat when the build is O(N log N). The other
// counters describe the tree: nodes, leaves, empty leaves, depth (max and average over leaves),
// triangles per non-empty leaf, references per triangle, SAH cost (default costs) and memory
// (nodes + leaf lists).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>

#include "experiments/measure.h"
#include "kd_bench_meshes.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "trace/trace_embree.h"

namespace rtt {
namespace {

enum MeshKind { sphere = 0, soup = 1 };

/// A benchmark's mesh (range 0: kind, 1: triangles) and its oneTBB thread cap (range 2: the
/// threads, 0 = all), held while the builds run; labels the benchmark.
struct MeshCase {
    Scene scene;
    tbb::global_control limit;

    explicit MeshCase(benchmark::State& state)
        : scene(MeshKind(state.range(0)) == sphere
                    ? kdbench::bumpy_sphere_of(size_t(state.range(1)))
                    : kdbench::triangle_soup(size_t(state.range(1)))),
          limit(tbb::global_control::max_allowed_parallelism,
                state.range(2) > 0 ? size_t(state.range(2))
                                   : size_t(tbb::info::default_concurrency())) {
        state.SetLabel(
            std::string(MeshKind(state.range(0)) == sphere ? "bumpy sphere" : "triangle soup") +
            (state.range(2) > 0 ? ", 1 thread" : ", all threads"));
        state.counters["tris"] = double(scene.triangle_count());
    }
};

void kd_build(benchmark::State& state) {
    const MeshCase mesh(state);
    const Scene& scene = mesh.scene;
    KdTree tree;
    double seconds = 0, cpu_seconds = 0;
    for (auto _ : state) {
        const std::clock_t start = std::clock();  // CPU time of the whole process, all threads
        tree = build_kdtree(scene);
        cpu_seconds += double(std::clock() - start) / CLOCKS_PER_SEC;
        benchmark::DoNotOptimize(tree.nodes.data());
        seconds += tree.stats.build_seconds;
    }
    const KdStats& s = tree.stats;
    const double tris = double(scene.triangle_count());
    const double per_build = seconds / double(state.iterations());
    const double cpu_per_build = cpu_seconds / double(state.iterations());
    state.counters["nodes"] = double(s.nodes);
    state.counters["leaves"] = double(s.leaves);
    state.counters["empty"] = double(s.empty_leaves);
    state.counters["depth"] = s.max_depth;
    state.counters["avg_depth"] = s.avg_leaf_depth;
    state.counters["tris/leaf"] = s.avg_leaf_triangles;
    state.counters["refs/tri"] = double(s.triangle_references) / tris;
    state.counters["sah"] = s.sah_cost;
    state.counters["MB"] = double(s.memory_bytes) / 1e6;
    state.counters["build_s"] = per_build;
    state.counters["cpu_s"] = cpu_per_build;
    state.counters["cpu_ns/NlogN"] = cpu_per_build * 1e9 / (tris * std::log2(tris));
}

/// Embree's BVH build (rtcCommitScene alone) on the same mesh and threads.
void embree_build(benchmark::State& state) {
    const MeshCase mesh(state);
    const KdTree unused;  // Embree builds its own BVH
    double seconds = 0;
    for (auto _ : state)
        seconds += embree_build_seconds(*make_tracer("embree", mesh.scene, unused));
    state.counters["build_s"] = seconds / double(state.iterations());
}

void sizes(benchmark::internal::Benchmark* b) {
    for (int kind : {sphere, soup})
        for (int threads : {1, 0})
            for (int n : {10'000, 100'000, 1'000'000, 4'000'000}) b->Args({kind, n, threads});
    b->ArgNames({"mesh", "tris", "threads"});
    b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
}
BENCHMARK(kd_build)->Apply(sizes);

[[maybe_unused]] const bool embree_registered = [] {
    if (bench::has_tracer("embree"))
        benchmark::RegisterBenchmark("embree_build", embree_build)->Apply(sizes);
    return true;
}();

}  // namespace
}  // namespace rtt

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::printf(
                "bench_kdbuild: SAH kd-tree build time on a bumpy sphere and a triangle soup of\n"
                "10k, 100k, 1M and 4M triangles, 1 thread and all threads (mesh: 0 = sphere,\n"
                "1 = soup; threads: 0 = all), and Embree's BVH build on the same meshes\n"
                "(embree_build, when Embree is built in). Counters give the tree's statistics,\n"
                "the process CPU time per build (cpu_s) and cpu_ns/NlogN = cpu_s / (N log2 N).\n"
                "Google Benchmark flags (--benchmark_filter=..., --benchmark_repetitions=N) "
                "apply.\n");
            return 0;
        }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
