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

RTT_INTRINSICS_BEGIN
/// Lane l (0-3) of x in every lane of a K-lane vector: one permute where the ISA has one.
template <int K>
RTT_FORCEINLINE vfloat<K> broadcast_lane(vfloat4 x, int l) {
#if defined(RTT_HAVE_SIMD16)
    if constexpr (K == 16)
        return _mm512_permutexvar_ps(_mm512_set1_epi32(l), _mm512_castps128_ps512(x));
#endif
#if defined(RTT_HAVE_SIMD8)
    if constexpr (K == 8)
        return _mm256_permutevar8x32_ps(_mm256_castps128_ps256(x), _mm256_set1_epi32(l));
#endif
    return vfloat<K>(x[l]);
}
RTT_INTRINSICS_END

}  // namespace RTT_ISA_NS
}  // namespace rtt
