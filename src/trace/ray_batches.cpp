// Arbitrary rays: chunks of rays handed to Tracer::intersect_arbitrary and visible_arbitrary in
// parallel (by default one-row tiles without a shaft); a large batch in the order of
// ray_order.h, a small one as it comes.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

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

/// Fills out[i] for every rays[i] by answer(chunk, answers, stats) on chunks in parallel, and
/// sums the statistics. A chunk is consecutive rays, answered in place, or rays gathered in the
/// tracer's order (ray_order.h), answered into a buffer and scattered back.
template <typename T, typename Answer>
void answer_in_chunks(const Tracer& tracer, std::span<const Ray> rays, std::span<T> out,
                      TraceStats* stats, const Answer& answer) {
    const large_vector<uint32_t> order =
        tracer.reorders_batches() ? coherent_order(rays) : large_vector<uint32_t>{};
    tbb::combinable<TraceStats> partial;
    const size_t chunks = (rays.size() + chunk_rays - 1) / chunk_rays;
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, chunks), [&](const tbb::blocked_range<size_t>& r) {
            Ray gathered[chunk_rays];
            T answers[chunk_rays];
            for (size_t c = r.begin(); c != r.end(); ++c) {
                const size_t first = c * chunk_rays;
                const size_t n = std::min(chunk_rays, rays.size() - first);
                TraceStats* st = stats ? &partial.local() : nullptr;
                if (order.empty()) {
                    answer(rays.subspan(first, n), out.subspan(first, n), st);
                    continue;
                }
                const uint32_t* at = order.data() + first;
                for (size_t k = 0; k < n; ++k) gathered[k] = rays[at[k]];
                answer(std::span<const Ray>(gathered, n), std::span<T>(answers, n), st);
                for (size_t k = 0; k < n; ++k) out[at[k]] = answers[k];
            }
        });
    if (stats) partial.combine_each([&](const TraceStats& s) { *stats += s; });
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
    answer_in_chunks(tracer, rays, hits, stats,
                     [&](std::span<const Ray> chunk, std::span<Hit> out, TraceStats* st) {
                         tracer.intersect_arbitrary(chunk, out, st);
                     });
}

void visible_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<uint8_t> visible,
                  TraceStats* stats) {
    check_rays(rays, visible.size(), "visible");
    answer_in_chunks(tracer, rays, visible, stats,
                     [&](std::span<const Ray> chunk, std::span<uint8_t> out, TraceStats* st) {
                         tracer.visible_arbitrary(chunk, out, st);
                     });
}

}  // namespace rtt
