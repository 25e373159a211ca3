#include "experiments/measure.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/combinable.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>

#include "rtt/error.h"
#include "rtt/render.h"
#include "trace/trace_embree.h"

namespace rtt::bench {
namespace {

double clock_seconds(clockid_t id) {
    timespec ts{};
    clock_gettime(id, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Reads both clocks at construction and on elapsed().
class Stopwatch {
public:
    explicit Stopwatch(bool whole_process)
        : cpu_id_(whole_process ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_THREAD_CPUTIME_ID),
          wall_(std::chrono::steady_clock::now()),
          cpu_(clock_seconds(cpu_id_)) {}
    Clocks elapsed() const {
        const double cpu = clock_seconds(cpu_id_);
        return {std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_).count(),
                cpu - cpu_};
    }

private:
    clockid_t cpu_id_;
    std::chrono::steady_clock::time_point wall_;
    double cpu_;
};

/// Runs body(i) for i in [0, count): on the calling thread, or spread over `arena`.
template <typename Body>
void for_each_index(tbb::task_arena* arena, size_t count, const Body& body) {
    if (!arena) {
        for (size_t i = 0; i < count; ++i) body(i);
        return;
    }
    arena->execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i < r.end(); ++i) body(i);
                          });
    });
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// One band's answers of one tracer, and the counters of its checking pass.
struct BandAnswers {
    std::vector<Hit> hits;
    std::vector<uint8_t> visible;
};

struct BandRunner {
    const Band& band;
    const Scene& scene;
    tbb::task_arena* arena;

    /// The tiles' counters, per thread, added to `into` at the end.
    struct Sums {
        tbb::combinable<KindStats> parts;
        TraceContext local() { return parts.local().context(); }
        void add_to(KindResult& into) {
            parts.combine_each([&](const KindStats& k) {
                into.stats += k.trace;
                into.rtt += k.rtt;
            });
        }
    };

    void primary(const Tracer& t, std::vector<Hit>& hits, KindResult* into) const {
        hits.resize(band.rays.size());
        const auto out = [&](size_t i) {
            return std::span(hits).subspan(band.tile_offset(i), band.tile_size(i));
        };
        if (!into) {
            for_each_index(arena, band.tile_count(), [&](size_t i) {
                band.prefetch_ray_tile(i + 1);
                t.intersect(band.ray_tile(i), out(i));
            });
            return;
        }
        Sums sums;
        for_each_index(arena, band.tile_count(), [&](size_t i) {
            band.prefetch_ray_tile(i + 1);
            t.intersect(band.ray_tile(i), out(i), sums.local());
        });
        sums.add_to(*into);
    }

    void shadow(const Tracer& t, std::vector<uint8_t>& visible, KindResult* into) const {
        const size_t n = band.tile_samples();
        visible.resize(band.shadow_jobs.size() * n);
        auto one = [&](size_t j, const TraceContext& context) {
            band.prefetch_shadow_job(j + 1);
            const ShadowJob& job = band.shadow_jobs[j];
            t.occluded(band.segment_tile(job, scene.lights[job.light].position),
                       std::span(visible).subspan(j * n, band.tile_size(job.tile)), context);
        };
        if (!into) {
            for_each_index(arena, band.shadow_jobs.size(), [&](size_t j) { one(j, {}); });
            return;
        }
        Sums sums;
        for_each_index(arena, band.shadow_jobs.size(), [&](size_t j) { one(j, sums.local()); });
        sums.add_to(*into);
    }
};

uint64_t hit_differences(const std::vector<Hit>& a, const std::vector<Hit>& b, bool exact) {
    uint64_t d = 0;
    for (size_t i = 0; i < a.size(); ++i) d += exact ? !(a[i] == b[i]) : a[i].tri != b[i].tri;
    return d;
}

uint64_t visibility_differences(const Band& band, const std::vector<uint8_t>& a,
                                const std::vector<uint8_t>& b) {
    uint64_t d = 0;
    const size_t n = band.tile_samples();
    for (size_t j = 0; j < band.shadow_jobs.size(); ++j)
        for (size_t i = 0; i < band.tile_size(band.shadow_jobs[j].tile); ++i) {
            const size_t s = j * n + i;
            d += band.masks[band.shadow_jobs[j].mask_offset + i] && (a[s] != 0) != (b[s] != 0);
        }
    return d;
}

}  // namespace

double KindResult::mrays_per_second(ClockKind clock) const {
    const double s = seconds(clock);
    return s > 0 ? double(rays) / s * 1e-6 : 0.0;
}

bool has_tracer(const std::string& kind) {
    const std::vector<std::string> kinds = tracer_kinds();
    return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

std::unique_ptr<Tracer> make_bench_tracer(const std::string& kind, const Scene& scene,
                                          const KdTree& tree) {
    if (kind == "rtt") return make_rtt_tracer(scene, tree, {.bvh_at_setup = true});
    return make_tracer(kind, scene, tree);
}

std::vector<NamedTracer> make_tracers(const BenchScene& scene,
                                      const std::vector<std::string>& kinds) {
    std::vector<NamedTracer> out;
    for (const std::string& kind : kinds) {
        if (!has_tracer(kind)) continue;
        NamedTracer t;
        t.kind = kind;
        t.tracer = make_bench_tracer(kind, scene.scene, scene.tree);
        t.exact = kind.rfind("embree", 0) != 0;
        t.own_build_seconds = embree_build_seconds(*t.tracer);
        out.push_back(std::move(t));
    }
    return out;
}

const TracerResult* Measurement::find(const std::string& kind) const {
    for (const TracerResult& t : tracers)
        if (t.kind == kind) return &t;
    return nullptr;
}

uint64_t Measurement::mismatches() const {
    uint64_t d = 0;
    for (const TracerResult& t : tracers)
        if (t.exact) d += t.primary.differences + t.shadow.differences;
    return d;
}

double speedup(const Measurement& m, const std::string& kind, const std::string& baseline,
               bool shadow, ClockKind clock) {
    const TracerResult* a = m.find(kind);
    const TracerResult* b = m.find(baseline);
    if (!a || !b) return 0.0;
    const double ta = (shadow ? a->shadow : a->primary).seconds(clock);
    const double tb = (shadow ? b->shadow : b->primary).seconds(clock);
    return ta > 0 && tb > 0 ? tb / ta : 0.0;
}

Measurement measure(const Workload& workload, const std::vector<NamedTracer>& tracers,
                    const MeasureOptions& options) {
    if (options.repetitions < 1) throw Error("repetitions must be at least 1");
    if (options.threads < 1) throw Error("threads must be at least 1");
    size_t base = tracers.size();
    for (size_t i = 0; i < tracers.size(); ++i)
        if (tracers[i].kind == options.baseline) base = i;
    if (base == tracers.size())
        throw Error("baseline tracer '" + options.baseline + "' is not among the measured tracers");

    const Stopwatch total(true);
    const size_t count = tracers.size();
    const int reps = options.repetitions;
    Measurement m;
    m.scene = workload.scene().name;
    m.width = workload.width();
    m.height = workload.height();
    m.aa = workload.aa();
    m.threads = options.threads;
    m.repetitions = reps;
    m.baseline = options.baseline;
    m.primary_rays = workload.primary_rays();
    for (const NamedTracer& t : tracers) {
        TracerResult r;
        r.kind = t.kind;
        r.exact = t.exact;
        r.primary.reps.resize(size_t(reps));
        r.shadow.reps.resize(size_t(reps));
        m.tracers.push_back(std::move(r));
    }

    std::optional<tbb::task_arena> arena, check_arena;
    if (options.threads > 1) arena.emplace(options.threads);
    const int check_threads =
        options.check_threads > 0 ? options.check_threads : tbb::info::default_concurrency();
    if (check_threads > 1) check_arena.emplace(check_threads);
    const bool whole_process = options.threads > 1;
    std::vector<BandAnswers> answers(count);
    // band_times[tracer][kind][rep]
    std::vector<std::array<std::vector<Clocks>, 2>> band_times(count);

    for (int b = 0; b < workload.band_count(); ++b) {
        Band band = workload.make_band(b);
        const BandRunner run{band, workload.scene().scene, arena ? &*arena : nullptr};
        const BandRunner check{band, workload.scene().scene, check_arena ? &*check_arena : nullptr};

        // 1. Checking pass: answers, statistics, warm caches.
        for (size_t i = 0; i < count; ++i)
            check.primary(*tracers[i].tracer, answers[i].hits, &m.tracers[i].primary);
        for (size_t i = 0; i < count; ++i)
            m.tracers[i].primary.differences +=
                hit_differences(answers[i].hits, answers[base].hits, tracers[i].exact);
        if (options.shadows) {
            workload.add_shadows(band, answers[base].hits);
            m.shadow_tiles += band.shadow_jobs.size();
            for (const ShadowJob& job : band.shadow_jobs) m.shadow_rays += job.active;
            for (size_t i = 0; i < count; ++i)
                check.shadow(*tracers[i].tracer, answers[i].visible, &m.tracers[i].shadow);
            for (size_t i = 0; i < count; ++i)
                m.tracers[i].shadow.differences +=
                    visibility_differences(band, answers[i].visible, answers[base].visible);
        }

        // 2. Timed repetitions, tracers interleaved and rotated.
        for (auto& t : band_times)
            for (auto& kind : t) kind.assign(size_t(reps), Clocks{});
        for (int r = 0; r < reps; ++r) {
            for (size_t j = 0; j < count; ++j) {
                const size_t i = (size_t(r) + j) % count;
                const Stopwatch watch(whole_process);
                run.primary(*tracers[i].tracer, answers[i].hits, nullptr);
                band_times[i][0][size_t(r)] = watch.elapsed();
            }
            if (!options.shadows) continue;
            for (size_t j = 0; j < count; ++j) {
                const size_t i = (size_t(r) + j) % count;
                const Stopwatch watch(whole_process);
                run.shadow(*tracers[i].tracer, answers[i].visible, nullptr);
                band_times[i][1][size_t(r)] = watch.elapsed();
            }
        }
        for (size_t i = 0; i < count; ++i) {
            KindResult* kinds[2] = {&m.tracers[i].primary, &m.tracers[i].shadow};
            for (int k = 0; k < 2; ++k) {
                std::vector<double> wall, cpu;
                for (int r = 0; r < reps; ++r) {
                    const Clocks& c = band_times[i][size_t(k)][size_t(r)];
                    wall.push_back(c.wall);
                    cpu.push_back(c.cpu);
                    kinds[k]->reps[size_t(r)] += c;
                }
                kinds[k]->time += Clocks{median(wall), median(cpu)};
            }
        }
    }
    for (TracerResult& t : m.tracers) {
        t.primary.rays = m.primary_rays;
        t.shadow.rays = m.shadow_rays;
    }
    m.seconds = total.elapsed().wall;
    return m;
}

}  // namespace rtt::bench
