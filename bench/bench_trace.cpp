// Every tracer on the same tiles, at the micro level: ray, packet (4-wide), packet8, packet16,
// rtt, embree and embree1 on one built-in scene's primary tiles, then on its shadow tiles
// (segments from the packet tracer's hit points, the renderer's active rule). The rays are
// `rtt bench`'s (src/bench/workload.h), so the two tools measure the same thing.
//
//   bench_trace [--scene=room] [--size=640x480] [--aa=1] [Google Benchmark flags]
//
// One tracing thread. Counter Mrays = million rays (active segments) per CPU second of that
// thread (Google Benchmark's rate; steadier than wall time on a shared machine).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench/workload.h"

namespace rtt::bench {
namespace {

struct Frame {
    BenchScene scene;
    std::vector<Band> bands;
    uint64_t primary_rays = 0;
    uint64_t shadow_rays = 0;
};

Frame make_frame(const std::string& scene_name, int width, int height, int aa) {
    Frame f;
    f.scene = load_bench_scene(scene_name);
    const Workload workload(f.scene, width, height, aa, size_t(1) << 16);
    const auto packet = make_tracer("packet", f.scene.scene, f.scene.tree);
    for (int b = 0; b < workload.band_count(); ++b) {
        Band band = workload.make_band(b);
        std::vector<Hit> hits(band.rays.size());
        const size_t n = band.tile_samples();
        for (size_t t = 0; t < band.tile_count(); ++t)
            packet->intersect(band.ray_tile(t), std::span(hits).subspan(t * n, n));
        workload.add_shadows(band, hits);
        for (const ShadowJob& j : band.shadow_jobs) f.shadow_rays += j.active;
        f.bands.push_back(std::move(band));
    }
    f.primary_rays = workload.primary_rays();
    return f;
}

const Frame* frame = nullptr;

void primary(benchmark::State& state, const std::string& kind) {
    const auto tracer = make_tracer(kind, frame->scene.scene, frame->scene.tree);
    std::vector<Hit> hits;
    for (auto _ : state)
        for (const Band& band : frame->bands) {
            hits.resize(band.rays.size());
            const size_t n = band.tile_samples();
            for (size_t t = 0; t < band.tile_count(); ++t) {
                band.prefetch_ray_tile(t + 1);  // hot rays, as the renderer's (workload.h)
                tracer->intersect(band.ray_tile(t), std::span(hits).subspan(t * n, n));
            }
            benchmark::DoNotOptimize(hits.data());
        }
    state.counters["Mrays"] = benchmark::Counter(double(frame->primary_rays) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void shadow(benchmark::State& state, const std::string& kind) {
    const auto tracer = make_tracer(kind, frame->scene.scene, frame->scene.tree);
    const std::vector<Light>& lights = frame->scene.scene.lights;
    std::vector<uint8_t> visible;
    for (auto _ : state)
        for (const Band& band : frame->bands) {
            const size_t n = band.tile_samples();
            visible.resize(n);
            for (size_t j = 0; j < band.shadow_jobs.size(); ++j) {
                band.prefetch_shadow_job(j + 1);
                const ShadowJob& job = band.shadow_jobs[j];
                tracer->occluded(band.segment_tile(job, lights[job.light].position), visible);
            }
            benchmark::DoNotOptimize(visible.data());
        }
    state.counters["Mrays"] = benchmark::Counter(double(frame->shadow_rays) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace
}  // namespace rtt::bench

int main(int argc, char** argv) {
    std::string scene = "room";
    int width = 640, height = 480, aa = 1;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        if (std::strncmp(argv[i], "--scene=", 8) == 0)
            scene = argv[i] + 8;
        else if (std::strncmp(argv[i], "--size=", 7) == 0 &&
                 std::sscanf(argv[i] + 7, "%dx%d", &width, &height) == 2)
            continue;
        else if (std::strncmp(argv[i], "--aa=", 5) == 0)
            aa = std::atoi(argv[i] + 5);
        else
            args.push_back(argv[i]);
    }
    int n = int(args.size());
    benchmark::Initialize(&n, args.data());
    try {
        static const rtt::bench::Frame f = rtt::bench::make_frame(scene, width, height, aa);
        rtt::bench::frame = &f;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_trace: error: %s\n", e.what());
        return 1;
    }
    std::printf("%s %dx%d, %dx%d: %llu primary rays, %llu shadow segments per frame\n",
                scene.c_str(), width, height, aa, aa,
                (unsigned long long)rtt::bench::frame->primary_rays,
                (unsigned long long)rtt::bench::frame->shadow_rays);
    for (const std::string& kind : rtt::tracer_kinds()) {
        if (kind == "brute") continue;  // the oracle would take minutes per frame
        benchmark::RegisterBenchmark(("Primary/" + kind).c_str(), rtt::bench::primary, kind)
            ->Unit(benchmark::kMillisecond);
    }
    for (const std::string& kind : rtt::tracer_kinds()) {
        if (kind == "brute") continue;
        benchmark::RegisterBenchmark(("Shadow/" + kind).c_str(), rtt::bench::shadow, kind)
            ->Unit(benchmark::kMillisecond);
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
