// Includes the SIMD widths the compiler targets: 4 lanes (SSE) always, 8 lanes with AVX2,
// 16 lanes with AVX-512F. RTT_SIMD_MAX_WIDTH names the widest; RTT_HAVE_SIMD8/16 say which
// packet widths this build can instantiate.
#pragma once

#include "simd/isa.h"
#include "simd/vfloat4.h"

#if defined(__AVX2__)
#define RTT_HAVE_SIMD8 1
#include "simd/vfloat8.h"
#endif

#if defined(__AVX512F__)
#define RTT_HAVE_SIMD16 1
#include "simd/vfloat16.h"
#endif

#include "simd/vec3v.h"

namespace rtt {
inline namespace RTT_ISA_NS {

#if defined(RTT_HAVE_SIMD16)
inline constexpr int simd_max_width = 16;
#elif defined(RTT_HAVE_SIMD8)
inline constexpr int simd_max_width = 8;
#else
inline constexpr int simd_max_width = 4;
#endif

}  // namespace RTT_ISA_NS
}  // namespace rtt
