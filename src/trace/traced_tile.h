// Bookkeeping shared by the tracers that trace every ray of a tile (brute, ray, packet, embree).
#pragma once

#include <cstdint>
#include <span>

#include "rtt/tracer.h"

namespace rtt {

/// Marks every sample as traced and counts one tile of `rays` traced rays.
inline void record_traced_tile(uint64_t rays, TraceStats* stats, std::span<SampleAnswer> answers) {
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    if (!stats) return;
    stats->tiles += 1;
    stats->rays += rays;
    stats->traced += rays;
}

}  // namespace rtt
