// The width-generic SIMD value types: vfloat<K>, vint<K>, vbool<K> (Embree's naming).
// Each width lives in its own header (vfloat4.h, vfloat8.h, ...); simd.h includes the widths
// the compiler targets. Kernels are written once over K and never touch intrinsics.
//
// Exactness: every arithmetic operation maps to one IEEE single-precision instruction with the
// same rounding as the scalar C++ expression, and there is deliberately no fused multiply-add
// (rtt is compiled with -ffp-contract=off): a kernel evaluates per lane exactly what the scalar
// routine evaluates, bit for bit.
#pragma once

#include <bit>
#include <cstdint>

#include "core/platform.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <int K>
struct vfloat;
template <int K>
struct vint;
template <int K>
struct vbool;

/// Lane masks as plain integers: bit i = lane i (K <= 16).
template <int K>
inline constexpr uint32_t all_lanes = (1u << K) - 1u;

}  // namespace RTT_ISA_NS
}  // namespace rtt
