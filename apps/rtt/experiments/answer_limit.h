// The limit of an answered ray (rtt bench answers): a kernel compiled once per ISA, like rtt's
// own (src/simd/isa.h), so the limit is measured at the width the answers run at.
#pragma once

#include <span>

#include "rtt/tracer.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// `rounds` times, for the 16x16 samples of one camera tile: the camera directions made in
/// registers (bit for bit the camera's), their watertight constants, `count` large triangles
/// tested (every ray hits the last, nearest one), the hits written to `hits` (256). Returns the
/// lanes per step.
int answer_limit_kernel(int count, int rounds, std::span<Hit> hits);

}  // namespace RTT_ISA_NS
}  // namespace rtt
