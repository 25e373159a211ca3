// vint<4>: 4 signed 32-bit integers in an SSE register (SSE4.1).
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/vbool4.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct alignas(16) vint<4> {
    __m128i v;

    vint() = default;
    RTT_FORCEINLINE vint(__m128i x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vint(int32_t s) : v(_mm_set1_epi32(s)) {}
    RTT_FORCEINLINE operator __m128i() const { return v; }

    static RTT_FORCEINLINE vint load(const int32_t* p) {
        return _mm_load_si128(reinterpret_cast<const __m128i*>(p));
    }
    static RTT_FORCEINLINE vint loadu(const int32_t* p) {
        return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
    }
    /// 0, 1, 2, 3.
    static RTT_FORCEINLINE vint step() { return _mm_setr_epi32(0, 1, 2, 3); }

    RTT_FORCEINLINE int32_t operator[](int i) const { return ((__v4si)v)[i]; }
    RTT_FORCEINLINE void set(int i, int32_t s) {
        __v4si t = (__v4si)v;
        t[i] = s;
        v = (__m128i)t;
    }
};
using vint4 = vint<4>;

RTT_FORCEINLINE void store(int32_t* p, vint4 a) {
    _mm_store_si128(reinterpret_cast<__m128i*>(p), a);
}
RTT_FORCEINLINE void storeu(int32_t* p, vint4 a) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(p), a);
}

RTT_FORCEINLINE vint4 operator+(vint4 a, vint4 b) {
    return _mm_add_epi32(a, b);
}
RTT_FORCEINLINE vint4 operator-(vint4 a, vint4 b) {
    return _mm_sub_epi32(a, b);
}
/// Low 32 bits of the product (wraps like unsigned arithmetic).
RTT_FORCEINLINE vint4 operator*(vint4 a, vint4 b) {
    return _mm_mullo_epi32(a, b);
}
RTT_FORCEINLINE vint4 operator&(vint4 a, vint4 b) {
    return _mm_and_si128(a, b);
}
RTT_FORCEINLINE vint4 operator|(vint4 a, vint4 b) {
    return _mm_or_si128(a, b);
}
RTT_FORCEINLINE vint4 operator^(vint4 a, vint4 b) {
    return _mm_xor_si128(a, b);
}

RTT_FORCEINLINE vbool4 operator==(vint4 a, vint4 b) {
    return _mm_castsi128_ps(_mm_cmpeq_epi32(a, b));
}
RTT_FORCEINLINE vbool4 operator!=(vint4 a, vint4 b) {
    return !(a == b);
}
RTT_FORCEINLINE vbool4 operator<(vint4 a, vint4 b) {
    return _mm_castsi128_ps(_mm_cmplt_epi32(a, b));
}
RTT_FORCEINLINE vbool4 operator>(vint4 a, vint4 b) {
    return _mm_castsi128_ps(_mm_cmpgt_epi32(a, b));
}
/// Unsigned a < b (triangle indices, where 0xFFFFFFFF means "none").
RTT_FORCEINLINE vbool4 ult(vint4 a, vint4 b) {
    const __m128i flip = _mm_set1_epi32(INT32_MIN);
    return _mm_castsi128_ps(_mm_cmplt_epi32(_mm_xor_si128(a, flip), _mm_xor_si128(b, flip)));
}

RTT_FORCEINLINE vint4 min(vint4 a, vint4 b) {
    return _mm_min_epi32(a, b);
}
RTT_FORCEINLINE vint4 max(vint4 a, vint4 b) {
    return _mm_max_epi32(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vint4 select(vbool4 m, vint4 t, vint4 f) {
    return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(f), _mm_castsi128_ps(t), m));
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
