// vbool<4>: a 4-lane SSE mask (all bits set = true), as produced by vfloat4 comparisons.
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/varying.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct vbool<4> {
    __m128 v;

    vbool() = default;
    RTT_FORCEINLINE vbool(__m128 m) : v(m) {}
    RTT_FORCEINLINE explicit vbool(bool b) : v(_mm_castsi128_ps(_mm_set1_epi32(b ? -1 : 0))) {}
    RTT_FORCEINLINE operator __m128() const { return v; }

    /// Lane i is true when bit i of `bits` is set.
    static RTT_FORCEINLINE vbool from_bits(uint32_t bits) {
        const __m128i lane_bits = _mm_setr_epi32(1, 2, 4, 8);
        const __m128i b = _mm_and_si128(_mm_set1_epi32(int(bits)), lane_bits);
        return _mm_castsi128_ps(_mm_cmpeq_epi32(b, lane_bits));
    }
    RTT_FORCEINLINE bool operator[](int i) const { return (_mm_movemask_ps(v) >> i) & 1; }
};
using vbool4 = vbool<4>;

RTT_FORCEINLINE vbool4 operator&(vbool4 a, vbool4 b) {
    return _mm_and_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator|(vbool4 a, vbool4 b) {
    return _mm_or_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator^(vbool4 a, vbool4 b) {
    return _mm_xor_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator!(vbool4 a) {
    return _mm_xor_ps(a, vbool4(true));
}
/// a && !b.
RTT_FORCEINLINE vbool4 andnot(vbool4 a, vbool4 b) {
    return _mm_andnot_ps(b, a);
}
RTT_FORCEINLINE vbool4& operator&=(vbool4& a, vbool4 b) {
    return a = a & b;
}
RTT_FORCEINLINE vbool4& operator|=(vbool4& a, vbool4 b) {
    return a = a | b;
}

/// Bit i = lane i.
RTT_FORCEINLINE uint32_t movemask(vbool4 a) {
    return uint32_t(_mm_movemask_ps(a));
}
RTT_FORCEINLINE bool any(vbool4 a) {
    return _mm_movemask_ps(a) != 0;
}
RTT_FORCEINLINE bool all(vbool4 a) {
    return _mm_movemask_ps(a) == 0xF;
}
RTT_FORCEINLINE bool none(vbool4 a) {
    return _mm_movemask_ps(a) == 0;
}
RTT_FORCEINLINE int popcount(vbool4 a) {
    return std::popcount(movemask(a));
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
