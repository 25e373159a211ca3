// Arbitrary rays: chunks of consecutive rays handed to Tracer::intersect_arbitrary and
// visible_arbitrary in parallel (by default one-row tiles without a shaft).
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "rtt/error.h"
#include "rtt/tracer.h"

namespace rtt {
namespace {

/// Rays per tile: a multiple of every packet width, large enough to hide the call, small enough
/// to spread over threads.
constexpr size_t chunk_rays = 1024;

void check_rays(std::span<const Ray> rays, size_t outputs, const char* output) {
    if (outputs != rays.size())
        throw Error(std::string(output) + " holds " + std::to_string(outputs) + " entries for " +
                    std::to_string(rays.size()) + " rays");
    // The message is made only for a bad ray: a string per ray cost as much as a BVH node test.
    const auto fail = [](size_t i, const char* what) {
        throw Error("ray " + std::to_string(i) + what);
    };
    for (size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        if (!is_finite(r.org) || !is_finite(r.dir))
            fail(i, " has a NaN or infinite origin or direction");
        if (r.dir == Vec3f{0.f}) fail(i, " has a zero direction");
        if (std::isnan(r.tmin) || std::isnan(r.tmax) || !(r.tmin <= r.tmax))
            fail(i, " has tmin > tmax or a NaN bound");
    }
}

/// Calls trace(chunk, first) for every chunk of `rays` in parallel and sums the statistics.
template <typename Trace>
void for_each_chunk(std::span<const Ray> rays, TraceStats* stats, const Trace& trace) {
    tbb::combinable<TraceStats> partial;
    const size_t chunks = (rays.size() + chunk_rays - 1) / chunk_rays;
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, chunks), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t c = r.begin(); c != r.end(); ++c) {
                const size_t first = c * chunk_rays;
                const size_t n = std::min(chunk_rays, rays.size() - first);
                trace(rays.subspan(first, n), first, stats ? &partial.local() : nullptr);
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
    for_each_chunk(rays, stats, [&](std::span<const Ray> chunk, size_t first, TraceStats* st) {
        tracer.intersect_arbitrary(chunk, hits.subspan(first, chunk.size()), st);
    });
}

void visible_rays(const Tracer& tracer, std::span<const Ray> rays, std::span<uint8_t> visible,
                  TraceStats* stats) {
    check_rays(rays, visible.size(), "visible");
    for_each_chunk(rays, stats, [&](std::span<const Ray> chunk, size_t first, TraceStats* st) {
        tracer.visible_arbitrary(chunk, visible.subspan(first, chunk.size()), st);
    });
}

}  // namespace rtt
