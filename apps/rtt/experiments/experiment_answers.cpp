// What an answered ray costs (issue 29's micro benchmark): `rtt` timed on the tiles it answers
// from a relevant list, per ray it answers there, primary and shadow, at K = 1 and 4; beside
// it the limit, a kernel that does only what an answer must: make 16 camera directions in
// registers (bit for bit the camera's), test them against N triangles with the watertight
// test, and write the hits.
#include <time.h>

#include <algorithm>
#include <cmath>

#include "experiments/answer_limit.h"
#include "experiments/experiment_common.h"
#include "rtt/error.h"
#include "rtt/isa.h"

// The limit kernel of the ISAs compiled beside this file's (CMakeLists.txt).
#ifdef RTT_KERNELS_AVX2
namespace rtt::isa_avx2 {
int answer_limit_kernel(int count, int rounds, std::span<Hit> hits);
}
#endif
#ifdef RTT_KERNELS_AVX512
namespace rtt::isa_avx512 {
int answer_limit_kernel(int count, int rounds, std::span<Hit> hits);
}
#endif

namespace rtt::bench {

using namespace detail;

namespace {

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// The median of `reps` runs of `f`, in seconds of this thread's CPU time.
template <typename F>
double median_seconds(int reps, F&& f) {
    std::vector<double> t;
    for (int r = 0; r < reps; ++r) {
        const double start = thread_cpu_seconds();
        f();
        t.push_back(thread_cpu_seconds() - start);
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

/// rtt on the answered tiles of one configuration: their time and the rays answered in them.
struct AnsweredCost {
    uint64_t tiles = 0, all_tiles = 0, answered = 0;
    double seconds = 0;
    double ns_per_ray() const { return answered ? 1e9 * seconds / double(answered) : 0.0; }
};

struct FrameCosts {
    AnsweredCost primary, shadow;
};

FrameCosts answered_costs(const BenchConfig& config, const BenchScene& scene, int width, int height,
                          int aa) {
    const Workload workload(scene, width, height, aa, size_t(1) << 16, config.region);
    const auto rtt = make_tracer("rtt", scene.scene, scene.tree);
    const auto packet = make_tracer("packet", scene.scene, scene.tree);
    const std::vector<Light>& lights = scene.scene.lights;
    FrameCosts out;
    for (int b = 0; b < workload.band_count(); ++b) {
        Band band = workload.make_band(b);
        workload.add_shadows(band, band.intersect(*packet));
        const size_t n = band.tile_samples();
        std::vector<Hit> hits(n);
        std::vector<uint8_t> visible(n);
        std::vector<SampleAnswer> answers(n);
        const auto count_answered = [&](size_t m) {
            return uint64_t(
                std::count_if(answers.begin(), answers.begin() + long(m),
                              [](SampleAnswer a) { return a != SampleAnswer::traced; }));
        };
        std::vector<size_t> tiles, jobs;
        for (size_t t = 0; t < band.tile_count(); ++t) {
            const size_t m = band.tile_size(t);
            rtt->intersect(band.ray_tile(t), std::span(hits).first(m),
                           TraceContext{.answers = std::span(answers).first(m)});
            if (const uint64_t a = count_answered(m)) {
                tiles.push_back(t);
                out.primary.answered += a;
            }
        }
        for (size_t j = 0; j < band.shadow_jobs.size(); ++j) {
            const ShadowJob& job = band.shadow_jobs[j];
            const size_t m = band.tile_size(job.tile);
            rtt->occluded(band.segment_tile(job, lights[job.light].position),
                          std::span(visible).first(m),
                          TraceContext{.answers = std::span(answers).first(m)});
            if (const uint64_t a = count_answered(m)) {
                jobs.push_back(j);
                out.shadow.answered += a;
            }
        }
        out.primary.tiles += tiles.size();
        out.primary.all_tiles += band.tile_count();
        out.shadow.tiles += jobs.size();
        out.shadow.all_tiles += band.shadow_jobs.size();
        out.primary.seconds += median_seconds(config.repetitions, [&] {
            for (const size_t t : tiles) {
                band.prefetch_ray_tile(t + 1);
                rtt->intersect(band.ray_tile(t), std::span(hits).first(band.tile_size(t)));
            }
        });
        out.shadow.seconds += median_seconds(config.repetitions, [&] {
            for (const size_t j : jobs) {
                band.prefetch_shadow_job(j + 1);
                const ShadowJob& job = band.shadow_jobs[j];
                rtt->occluded(band.segment_tile(job, lights[job.light].position),
                              std::span(visible).first(band.tile_size(job.tile)));
            }
        });
    }
    return out;
}

/// The limit of an answer, per ray, and its lanes: answer_limit_kernel of the active ISA.
std::pair<double, int> limit_ns_per_ray(int count, int reps) {
    constexpr int side = 16, rounds = 20000;
    std::vector<Hit> hits(size_t(side) * side);
    const Isa isa = active_isa();
    int lanes = 0;
    const double s = median_seconds(reps, [&] {
        if (isa == compiled_isa) lanes = answer_limit_kernel(count, rounds, hits);
#ifdef RTT_KERNELS_AVX2
        if (isa == Isa::avx2) lanes = isa_avx2::answer_limit_kernel(count, rounds, hits);
#endif
#ifdef RTT_KERNELS_AVX512
        if (isa == Isa::avx512) lanes = isa_avx512::answer_limit_kernel(count, rounds, hits);
#endif
    });
    if (hits[0].tri != uint32_t(count - 1))
        throw Error("rtt bench answers: the limit kernel missed its nearest triangle");
    return {1e9 * s / (double(rounds) * side * side), lanes};
}

}  // namespace

ExperimentResult run_answers(const BenchConfig& config, SceneCache& scenes) {
    ExperimentResult r;
    r.id = "answers";
    r.title = "What an answered ray costs: rtt on the tiles it answers, beside the limit";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    const int w = config.quick() ? 256 : 1024, h = config.quick() ? 192 : 768;
    TextTable t;
    t.title = "ns per answered ray (" + size_label(w, h) + ", 1 thread, CPU time, median of " +
              std::to_string(config.repetitions) + ")";
    t.header = {
        "scene",        "K", "primary tiles answered", "primary ns/ray", "shadow jobs answered",
        "shadow ns/ray"};
    nlohmann::json cells = nlohmann::json::array();
    for (const std::string& name : config.scenes) {
        const BenchScene& scene = scenes.get(name);
        for (const int k : {1, 4}) {
            const FrameCosts c = answered_costs(config, scene, w, h, k);
            const auto share = [](const AnsweredCost& a) {
                return format_count(a.tiles) + " of " + format_count(a.all_tiles);
            };
            t.rows.push_back({name, std::to_string(k), share(c.primary),
                              format_fixed(c.primary.ns_per_ray(), 1), share(c.shadow),
                              format_fixed(c.shadow.ns_per_ray(), 1)});
            cells.push_back({{"scene", name},
                             {"aa", k},
                             {"primary_answered_rays", c.primary.answered},
                             {"primary_seconds", c.primary.seconds},
                             {"primary_ns_per_answered_ray", c.primary.ns_per_ray()},
                             {"shadow_answered_rays", c.shadow.answered},
                             {"shadow_seconds", c.shadow.seconds},
                             {"shadow_ns_per_answered_ray", c.shadow.ns_per_ray()}});
            std::fprintf(config.log, "  measured %s K=%d\n", name.c_str(), k);
        }
    }
    nlohmann::json limits = nlohmann::json::object();
    for (const int count : {1, 4}) {
        const auto [ns, lanes] = limit_ns_per_ray(count, config.repetitions);
        limits[std::to_string(count)] = ns;
        t.notes.push_back("The limit with " + std::to_string(count) + " triangle" +
                          (count > 1 ? "s" : "") + " per ray (make, test, write; " +
                          std::to_string(lanes) + " lanes): " + format_fixed(ns, 2) +
                          " ns per ray.");
    }
    t.notes.push_back(
        "ns/ray: the time of rtt on the tiles (shadow jobs) it answers at least one ray of, "
        "corners, walk and the rays it traces there included, over the rays it answers.");
    print_table(config.log, t);
    r.tables.push_back(t);
    r.extra["answers"] = cells;
    r.extra["limit_ns_per_ray"] = limits;
    return r;
}

}  // namespace rtt::bench
