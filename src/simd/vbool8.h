// vbool<8>: an 8-lane AVX mask (all bits set = true), as produced by vfloat8 comparisons.
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/varying.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct vbool<8> {
    __m256 v;

    vbool() = default;
    RTT_FORCEINLINE vbool(__m256 m) : v(m) {}
    RTT_FORCEINLINE explicit vbool(bool b)
        : v(_mm256_castsi256_ps(_mm256_set1_epi32(b ? -1 : 0))) {}
    RTT_FORCEINLINE operator __m256() const { return v; }

    /// Lane i is true when bit i of `bits` is set.
    static RTT_FORCEINLINE vbool from_bits(uint32_t bits) {
        const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        const __m256i b = _mm256_and_si256(_mm256_set1_epi32(int(bits)), lane_bits);
        return _mm256_castsi256_ps(_mm256_cmpeq_epi32(b, lane_bits));
    }
    RTT_FORCEINLINE bool operator[](int i) const { return (_mm256_movemask_ps(v) >> i) & 1; }
};
using vbool8 = vbool<8>;

RTT_FORCEINLINE vbool8 operator&(vbool8 a, vbool8 b) {
    return _mm256_and_ps(a, b);
}
RTT_FORCEINLINE vbool8 operator|(vbool8 a, vbool8 b) {
    return _mm256_or_ps(a, b);
}
RTT_FORCEINLINE vbool8 operator^(vbool8 a, vbool8 b) {
    return _mm256_xor_ps(a, b);
}
RTT_FORCEINLINE vbool8 operator!(vbool8 a) {
    return _mm256_xor_ps(a, vbool8(true));
}
/// a && !b.
RTT_FORCEINLINE vbool8 andnot(vbool8 a, vbool8 b) {
    return _mm256_andnot_ps(b, a);
}
RTT_FORCEINLINE vbool8& operator&=(vbool8& a, vbool8 b) {
    return a = a & b;
}
RTT_FORCEINLINE vbool8& operator|=(vbool8& a, vbool8 b) {
    return a = a | b;
}

/// Bit i = lane i.
RTT_FORCEINLINE uint32_t movemask(vbool8 a) {
    return uint32_t(_mm256_movemask_ps(a));
}
RTT_FORCEINLINE bool any(vbool8 a) {
    return _mm256_movemask_ps(a) != 0;
}
RTT_FORCEINLINE bool all(vbool8 a) {
    return _mm256_movemask_ps(a) == 0xFF;
}
RTT_FORCEINLINE bool none(vbool8 a) {
    return _mm256_movemask_ps(a) == 0;
}
RTT_FORCEINLINE int popcount(vbool8 a) {
    return std::popcount(movemask(a));
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
