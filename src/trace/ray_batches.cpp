// Arbitrary rays: chunks of rays handed to Tracer::intersect_arbitrary and visible_arbitrary in
// parallel (by default one-row tiles without a shaft); a large batch of closest hits in the order
// of ray_order.h, a large any-hit batch in that order when a probe says it pays (ray_batches.h),
// a small one as it comes.
#include "trace/ray_batches.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "rtt/error.h"
#include "rtt/tracer.h"
#include "trace/ray_order.h"

namespace rtt {
namespace {

/// Rays per tile: a multiple of every packet width, large enough to hide the call, small enough
/// to spread over threads.
constexpr size_t chunk_rays = 1024;

size_t chunks_of(size_t rays) {
    return (rays + chunk_rays - 1) / chunk_rays;
}

/// The first of `rays` that is not a ray (a NaN or infinite value, a zero direction, tmin > tmax),
/// with what is wrong with it; rays.size() when all are rays.
std::pair<size_t, const char*> first_bad_ray(std::span<const Ray> rays) {
    const auto bad = [](const Ray& r) -> const char* {
        if (!is_finite(r.org) || !is_finite(r.dir))
            return " has a NaN or infinite origin or direction";
        if (r.dir == Vec3f{0.f}) return " has a zero direction";
        if (std::isnan(r.tmin) || std::isnan(r.tmax) || !(r.tmin <= r.tmax))
            return " has tmin > tmax or a NaN bound";
        return nullptr;
    };
    // In parallel: a serial pass cost as much as ordering the batch (ray_order.h).
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, rays.size(), 4096),
        std::pair<size_t, const char*>{rays.size(), nullptr},
        [&](const tbb::blocked_range<size_t>& r, std::pair<size_t, const char*> first) {
            for (size_t i = r.begin(); i != r.end() && i < first.first; ++i)
                if (const char* what = bad(rays[i])) return std::pair<size_t, const char*>{i, what};
            return first;
        },
        [](const auto& a, const auto& b) { return a.first <= b.first ? a : b; });
}

void check_rays(std::span<const Ray> rays, size_t outputs, const char* output) {
    if (outputs != rays.size())
        throw Error(std::string(output) + " holds " + std::to_string(outputs) + " entries for " +
                    std::to_string(rays.size()) + " rays");
    if (const auto [i, what] = first_bad_ray(rays); what)
        throw Error("ray " + std::to_string(i) + what);
}

/// Chunks a probe traces, every `stride`-th from the first: at most max_count, so that tracing
/// them twice costs a 1M-ray batch under 1 %, and at most one in eight of a small batch.
struct Probe {
    static constexpr size_t max_count = 8;
    size_t count, stride;
    explicit Probe(size_t chunks)
        : count(std::clamp<size_t>(chunks / 8, 1, max_count)), stride(chunks / count) {}
    bool probed(size_t c) const { return c % stride == 0 && c / stride < count; }
};

/// Fills out[i] for every rays[i] by answer(chunk, answers, stats) on chunks in parallel, and
/// sums the statistics. A chunk is consecutive rays, answered in place, or, when `order` is not
/// empty, rays gathered in that order (ray_order.h), answered into a buffer and scattered back.
/// Chunks a probe has answered (`done`, when given) are left as they are.
template <typename T, typename Answer>
void answer_in_chunks(std::span<const Ray> rays, const large_vector<uint32_t>& order,
                      std::span<T> out, TraceStats* stats, const Answer& answer,
                      const Probe* done = nullptr) {
    tbb::combinable<TraceStats> partial;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks_of(rays.size())),
                      [&](const tbb::blocked_range<size_t>& r) {
                          Ray gathered[chunk_rays];
                          T answers[chunk_rays];
                          for (size_t c = r.begin(); c != r.end(); ++c) {
                              if (done && done->probed(c)) continue;
                              const size_t first = c * chunk_rays;
                              const size_t n = std::min(chunk_rays, rays.size() - first);
                              TraceStats* st = stats ? &partial.local() : nullptr;
                              if (order.empty()) {
                                  answer(rays.subspan(first, n), out.subspan(first, n), st);
                                  continue;
                              }
                              const uint32_t* at = order.data() + first;
                              for (size_t k = 0; k < n; ++k) gathered[k] = rays[at[k]];
                              answer(std::span<const Ray>(gathered, n), std::span<T>(answers, n),
                                     st);
                              for (size_t k = 0; k < n; ++k) out[at[k]] = answers[k];
                          }
                      });
    if (stats) partial.combine_each([&](const TraceStats& s) { *stats += s; });
}

/// Whether a batch's rays wait on memory (order_any_hit_above): traces the probe's chunks as
/// given, answers into `out` and statistics into `stats`, each once more right after (that
/// pass's answers are the same and are dropped), and compares the two passes' times.
template <typename T, typename Answer>
bool waits_on_memory(std::span<const Ray> rays, std::span<T> out, TraceStats& stats,
                     const Probe& probe, double order_above, const Answer& answer) {
    using clock = std::chrono::steady_clock;
    std::array<clock::duration, Probe::max_count> first{}, again{};
    tbb::combinable<TraceStats> partial;
    tbb::parallel_for(size_t(0), probe.count, [&](size_t p) {
        const size_t at = p * probe.stride * chunk_rays;
        const size_t n = std::min(chunk_rays, rays.size() - at);
        T repeat[chunk_rays];
        const auto t0 = clock::now();
        answer(rays.subspan(at, n), out.subspan(at, n), &partial.local());
        const auto t1 = clock::now();
        answer(rays.subspan(at, n), std::span<T>(repeat, n), nullptr);
        again[p] = clock::now() - t1;
        first[p] = t1 - t0;
    });
    partial.combine_each([&](const TraceStats& s) { stats += s; });
    clock::duration first_sum{}, again_sum{};
    for (size_t p = 0; p < probe.count; ++p) first_sum += first[p], again_sum += again[p];
    return std::chrono::duration<double>(first_sum).count() >=
           order_above * std::chrono::duration<double>(again_sum).count();
}

}  // namespace

void Tracer::intersect_arbitrary(std::span<const Ray> rays, std::span<Hit> hits,
                                 TraceStats* stats) const {
    intersect(RayTile{int(rays.size()), 1, rays, false}, hits, TraceContext{stats});
}

void Tracer::visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                               TraceStats* stats) const {
    Hit hits[chunk_rays];
    for (size_t first = 0; first < rays.size(); first += chunk_rays) {
        const size_t n = std::min(chunk_rays, rays.size() - first);
        intersect_arbitrary(rays.subspan(first, n), std::span<Hit>(hits, n), stats);
        for (size_t i = 0; i < n; ++i) visible[first + i] = hits[i].valid() ? 0 : 1;
    }
}

void intersect_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits,
                    TraceStats* stats) {
    check_rays(rays, hits.size(), "hits");
    // Closest hits paid for the order on every scene measured (docs/benchmarks.md).
    const large_vector<uint32_t> order =
        tracer.reorders_batches() ? coherent_order(rays) : large_vector<uint32_t>{};
    answer_in_chunks(rays, order, hits, stats,
                     [&](std::span<const Ray> chunk, std::span<Hit> out, TraceStats* st) {
                         tracer.intersect_arbitrary(chunk, out, st);
                     });
}

void visible_rays_probed(const Tracer& tracer, std::span<const Ray> rays,
                         std::span<uint8_t> visible, TraceStats* stats, double order_above) {
    check_rays(rays, visible.size(), "visible");
    const auto answer = [&](std::span<const Ray> chunk, std::span<uint8_t> out, TraceStats* st) {
        tracer.visible_arbitrary(chunk, out, st);
    };
    if (!tracer.reorders_batches() || rays.size() < reorder_min_rays)
        return answer_in_chunks(rays, {}, visible, stats, answer);
    const Probe probe(chunks_of(rays.size()));
    TraceStats probed;
    if (waits_on_memory(rays, visible, probed, probe, order_above, answer)) {
        // The probe's chunks are traced again in their places in the order.
        if (const auto order = coherent_order(rays); !order.empty())
            return answer_in_chunks(rays, order, visible, stats, answer);
    }
    if (stats) *stats += probed;
    answer_in_chunks(rays, {}, visible, stats, answer, &probe);
}

void visible_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<uint8_t> visible,
                  TraceStats* stats) {
    visible_rays_probed(tracer, rays, visible, stats, order_any_hit_above);
}

}  // namespace rtt
