// Bookkeeping shared by the tracers that trace every ray of a tile (brute, ray, packet, embree).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "rtt/tracer.h"

namespace rtt {

/// Counts one tile of `rays` traced rays.
inline void record_traced_tile(uint64_t rays, TraceStats* stats) {
    if (!stats) return;
    stats->tiles += 1;
    stats->rays += rays;
    stats->traced += rays;
}

/// Marks every sample as traced and counts one tile of `rays` traced rays.
inline void record_traced_tile(uint64_t rays, const TraceContext& context) {
    for (SampleAnswer& a : context.answers) a = SampleAnswer::traced;
    record_traced_tile(rays, context.stats);
}

/// Answers a tile ray by ray with `trace(const Ray&) -> Hit` (the brute-force and single-ray
/// tracers).
template <typename TraceOne>
void intersect_one_by_one(const RayTile& tile, std::span<Hit> hits, const TraceContext& context,
                          TraceOne trace) {
    for (size_t i = 0; i < tile.rays.size(); ++i) hits[i] = trace(tile.rays[i]);
    record_traced_tile(tile.rays.size(), context);
}

/// Answers a segment tile segment by segment with `blocked(const Ray&) -> bool` on each
/// active segment's shadow_ray(); inactive segments are reported not visible.
template <typename BlockedOne>
void occluded_one_by_one(const SegmentTile& tile, std::span<uint8_t> visible,
                         const TraceContext& context, BlockedOne blocked) {
    uint64_t n = 0;
    for (size_t i = 0; i < tile.points.size(); ++i) {
        visible[i] = 0;
        if (!tile.active[i]) continue;
        ++n;
        visible[i] = !blocked(shadow_ray(tile.light, tile.points[i]));
    }
    record_traced_tile(n, context);
}

}  // namespace rtt
