// Every tracer on the same tiles, at the micro level: ray, packet (4-wide), packet8, packet16,
// rtt and every Embree mode (tracer_kinds()) on one built-in scene's primary tiles, then on its
// shadow tiles (segments from the packet tracer's hit points, the renderer's active rule). The
// rays are `rtt bench`'s (apps/rtt/experiments/workload.h), so the two tools measure the same
// thing.
//
//   bench_trace [--scene=room] [--size=640x480] [--aa=1] [--region=0]
//               [--shadow-fallback=bvh|kd] [Google Benchmark flags]
//
// --region: pixels per tile side, as `rtt render --region` (0 = the renderer's default per K).
// --shadow-fallback: how rtt traces the shadow regions it declines (RttOptions::shadow_fallback).
//
// One tracing thread. Counter Mrays = million rays (active segments) per CPU second of that
// thread (Google Benchmark's rate; steadier than wall time on a shared machine).
//
// Split/... runs rtt, packet, the widest packets and bvh (rtt's fallback for declined camera
// regions) on two halves of the same frame: the tiles rtt answers from a relevant list (at least
// one ray answered) and the tiles it declines (all traced), so that what an answered tile costs
// can be set beside what tracing it costs (docs/benchmarks.md, "What each goal needs"). Counter
// tiles = tiles of that half per frame.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "bench_args.h"
#include "cli_values.h"
#include "experiments/workload.h"
#include "rtt/rtt_options.h"

namespace rtt::bench {
namespace {

struct Frame {
    BenchScene scene;
    std::vector<Band> bands;
    uint64_t primary_rays = 0;
    uint64_t shadow_rays = 0;
    /// Per band, per primary tile / per shadow job: rtt answered at least one of its rays.
    std::vector<std::vector<uint8_t>> tile_answered, job_answered;
};

/// How rtt traces the shadow regions it declines (--shadow-fallback).
ShadowFallback shadow_fallback = ShadowFallback::bvh;

/// The tracer `kind` as timed here: rtt with its BVH built at setup, as in rtt bench
/// (RttOptions::bvh_at_setup), so no frame pays for the build.
std::unique_ptr<Tracer> timed_tracer(const std::string& kind, const BenchScene& scene) {
    if (kind == "rtt")
        return make_rtt_tracer(scene.scene, scene.tree,
                               {.bvh_at_setup = true, .shadow_fallback = shadow_fallback});
    return make_tracer(kind, scene.scene, scene.tree);
}

/// Which primary tiles and shadow jobs of `f` rtt answers (from a relevant list, at least one
/// ray): the Split benchmarks' halves.
void mark_answered(Frame& f) {
    const auto rtt = make_tracer("rtt", f.scene.scene, f.scene.tree);
    const std::vector<Light>& lights = f.scene.scene.lights;
    for (const Band& band : f.bands) {
        const size_t n = band.tile_samples();
        std::vector<Hit> hits(n);
        std::vector<uint8_t> visible(n);
        std::vector<SampleAnswer> answers(n);
        const auto any_answered = [&] {
            for (const SampleAnswer a : answers)
                if (a != SampleAnswer::traced) return uint8_t(1);
            return uint8_t(0);
        };
        std::vector<uint8_t>& tiles = f.tile_answered.emplace_back(band.tile_count());
        for (size_t t = 0; t < band.tile_count(); ++t) {
            const size_t m = band.tile_size(t);
            answers.assign(m, SampleAnswer::traced);
            rtt->intersect(band.ray_tile(t), std::span(hits).first(m),
                           TraceContext{.answers = answers});
            tiles[t] = any_answered();
        }
        std::vector<uint8_t>& jobs = f.job_answered.emplace_back(band.shadow_jobs.size());
        for (size_t j = 0; j < band.shadow_jobs.size(); ++j) {
            const ShadowJob& job = band.shadow_jobs[j];
            const size_t m = band.tile_size(job.tile);
            answers.assign(m, SampleAnswer::traced);
            rtt->occluded(band.segment_tile(job, lights[job.light].position),
                          std::span(visible).first(m), TraceContext{.answers = answers});
            jobs[j] = any_answered();
        }
    }
}

Frame make_frame(const std::string& scene_name, int width, int height, int aa, int region) {
    Frame f;
    f.scene = load_bench_scene(scene_name);
    const Workload workload(f.scene, width, height, aa, size_t(1) << 16, region);
    const auto packet = make_tracer("packet", f.scene.scene, f.scene.tree);
    for (int b = 0; b < workload.band_count(); ++b) {
        Band band = workload.make_band(b);
        workload.add_shadows(band, band.intersect(*packet));
        for (const ShadowJob& j : band.shadow_jobs) f.shadow_rays += j.active;
        f.bands.push_back(std::move(band));
    }
    f.primary_rays = workload.primary_rays();
    mark_answered(f);
    return f;
}

const Frame* frame = nullptr;

void primary(benchmark::State& state, const std::string& kind) {
    const auto tracer = timed_tracer(kind, frame->scene);
    std::vector<Hit> hits;
    for (auto _ : state)
        for (const Band& band : frame->bands) {
            hits.resize(band.rays.size());
            for (size_t t = 0; t < band.tile_count(); ++t) {
                band.prefetch_ray_tile(t + 1);  // hot rays, as the renderer's (workload.h)
                tracer->intersect(band.ray_tile(t),
                                  std::span(hits).subspan(band.tile_offset(t), band.tile_size(t)));
            }
            benchmark::DoNotOptimize(hits.data());
        }
    state.counters["Mrays"] = benchmark::Counter(double(frame->primary_rays) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void shadow(benchmark::State& state, const std::string& kind) {
    const auto tracer = timed_tracer(kind, frame->scene);
    const std::vector<Light>& lights = frame->scene.scene.lights;
    std::vector<uint8_t> visible;
    for (auto _ : state)
        for (const Band& band : frame->bands) {
            const size_t n = band.tile_samples();
            visible.resize(n);
            for (size_t j = 0; j < band.shadow_jobs.size(); ++j) {
                band.prefetch_shadow_job(j + 1);
                const ShadowJob& job = band.shadow_jobs[j];
                tracer->occluded(band.segment_tile(job, lights[job.light].position),
                                 std::span(visible).first(band.tile_size(job.tile)));
            }
            benchmark::DoNotOptimize(visible.data());
        }
    state.counters["Mrays"] = benchmark::Counter(double(frame->shadow_rays) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

/// The primary tiles (shadows = false) or shadow jobs of one half of the frame: those rtt
/// answers (answered = true) or those it declines, band by band, with the next one prefetched
/// as in primary() and shadow().
void split(benchmark::State& state, const std::string& kind, bool shadows, bool answered) {
    const auto tracer = timed_tracer(kind, frame->scene);
    const std::vector<Light>& lights = frame->scene.scene.lights;
    std::vector<std::vector<size_t>> chosen(frame->bands.size());
    uint64_t tiles = 0;
    for (size_t b = 0; b < frame->bands.size(); ++b) {
        const std::vector<uint8_t>& in = shadows ? frame->job_answered[b] : frame->tile_answered[b];
        for (size_t i = 0; i < in.size(); ++i)
            if ((in[i] != 0) == answered) chosen[b].push_back(i);
        tiles += chosen[b].size();
    }
    std::vector<Hit> hits;
    std::vector<uint8_t> visible;
    for (auto _ : state)
        for (size_t b = 0; b < frame->bands.size(); ++b) {
            const Band& band = frame->bands[b];
            const std::vector<size_t>& ids = chosen[b];
            hits.resize(band.tile_samples());
            visible.resize(band.tile_samples());
            for (size_t i = 0; i < ids.size(); ++i) {
                const size_t next = i + 1 < ids.size() ? ids[i + 1] : ids[i] + 1;
                if (shadows) {
                    band.prefetch_shadow_job(next);
                    const ShadowJob& job = band.shadow_jobs[ids[i]];
                    tracer->occluded(band.segment_tile(job, lights[job.light].position),
                                     std::span(visible).first(band.tile_size(job.tile)));
                } else {
                    band.prefetch_ray_tile(next);
                    tracer->intersect(band.ray_tile(ids[i]),
                                      std::span(hits).first(band.tile_size(ids[i])));
                }
            }
            benchmark::DoNotOptimize(hits.data());
            benchmark::DoNotOptimize(visible.data());
        }
    state.counters["tiles"] = double(tiles);
}

}  // namespace
}  // namespace rtt::bench

int main(int argc, char** argv) {
    std::string scene = "room";
    int width = 640, height = 480, aa = 1, region = 0;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        const char* a = argv[i];
        bool ok = true;
        if (std::strcmp(a, "--help") == 0 || std::strcmp(a, "-h") == 0) {
            std::printf(
                "bench_trace: every tracer of this build on the same primary and shadow tiles of\n"
                "one scene (rtt bench's rays), one tracing thread; Split/... times the tiles rtt\n"
                "answers and those it declines apart.\n"
                "  --scene=NAME|FILE  built-in scene or scene file (default room)\n"
                "  --size=WxH         image size (default 640x480)\n"
                "  --aa=K             K x K samples per pixel (default 1)\n"
                "  --region=R         pixels per region side, as rtt render --region (0 = "
                "default)\n"
                "  --shadow-fallback=bvh|kd  how rtt traces the shadow regions it "
                "declines\n"
                "Google Benchmark flags (--benchmark_filter=..., --benchmark_repetitions=N) "
                "apply.\n");
            return 0;
        } else if (std::strncmp(a, "--scene=", 8) == 0) {
            scene = a + 8;
        } else if (std::strncmp(a, "--size=", 7) == 0) {
            try {
                rtt::parse_size(a + 7, width, height);
            } catch (const std::exception&) {
                ok = false;
            }
        } else if (std::strncmp(a, "--aa=", 5) == 0) {
            ok = rtt::bench::parse_int(a + 5, aa);
        } else if (std::strncmp(a, "--region=", 9) == 0) {
            ok = rtt::bench::parse_int(a + 9, region);
        } else if (std::strncmp(a, "--shadow-fallback=", 18) == 0) {
            using rtt::ShadowFallback;
            const std::string_view v = a + 18;
            ok = v == "kd" || v == "bvh";
            rtt::bench::shadow_fallback = v == "kd" ? ShadowFallback::kd_tree : ShadowFallback::bvh;
        } else {
            args.push_back(argv[i]);
        }
        if (!ok) {
            std::fprintf(stderr, "bench_trace: error: bad value in '%s' (see --help)\n", a);
            return 1;
        }
    }
    int n = int(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
    try {
        static const rtt::bench::Frame f = rtt::bench::make_frame(scene, width, height, aa, region);
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
    // Split: the 4-wide baseline, the widest packets of this build (RTT's own fallback), rtt.
    const std::vector<std::string>& kinds = rtt::tracer_kinds();
    std::vector<std::string> split_kinds = {"packet"};
    for (const char* wide : {"packet16", "packet8"})
        if (std::find(kinds.begin(), kinds.end(), wide) != kinds.end()) {
            split_kinds.push_back(wide);
            break;
        }
    split_kinds.push_back("rtt");
    split_kinds.push_back("bvh");
    for (const std::string& kind : split_kinds)
        for (const bool shadows : {false, true})
            for (const bool answered : {true, false}) {
                const std::string name = std::string("Split/") +
                                         (shadows ? "shadow/" : "primary/") +
                                         (answered ? "answered/" : "declined/") + kind;
                benchmark::RegisterBenchmark(name.c_str(), rtt::bench::split, kind, shadows,
                                             answered)
                    ->Unit(benchmark::kMillisecond);
            }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
