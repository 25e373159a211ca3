// vint<16>: 16 signed 32-bit integers in an AVX-512 register.
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/vbool16.h"

// GCC 12's intrinsics and false warnings: simd/isa.h.
RTT_INTRINSICS_BEGIN

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct alignas(64) vint<16> {
    __m512i v;

    vint() = default;
    RTT_FORCEINLINE vint(__m512i x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vint(int32_t s) : v(_mm512_set1_epi32(s)) {}
    RTT_FORCEINLINE operator __m512i() const { return v; }

    static RTT_FORCEINLINE vint load(const int32_t* p) { return _mm512_load_si512(p); }
    static RTT_FORCEINLINE vint loadu(const int32_t* p) { return _mm512_loadu_si512(p); }
    /// 0, 1, ..., 15.
    static RTT_FORCEINLINE vint step() {
        return _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    }

    RTT_FORCEINLINE int32_t operator[](int i) const { return ((__v16si)v)[i]; }
    RTT_FORCEINLINE void set(int i, int32_t s) {
        __v16si t = (__v16si)v;
        t[i] = s;
        v = (__m512i)t;
    }
};
using vint16 = vint<16>;

RTT_FORCEINLINE void store(int32_t* p, vint16 a) {
    _mm512_store_si512(p, a);
}
RTT_FORCEINLINE void storeu(int32_t* p, vint16 a) {
    _mm512_storeu_si512(p, a);
}

RTT_FORCEINLINE vint16 operator+(vint16 a, vint16 b) {
    return _mm512_add_epi32(a, b);
}
RTT_FORCEINLINE vint16 operator-(vint16 a, vint16 b) {
    return _mm512_sub_epi32(a, b);
}
/// Low 32 bits of the product (wraps like unsigned arithmetic).
RTT_FORCEINLINE vint16 operator*(vint16 a, vint16 b) {
    return _mm512_mullo_epi32(a, b);
}
RTT_FORCEINLINE vint16 operator&(vint16 a, vint16 b) {
    return _mm512_and_si512(a, b);
}
RTT_FORCEINLINE vint16 operator|(vint16 a, vint16 b) {
    return _mm512_or_si512(a, b);
}
RTT_FORCEINLINE vint16 operator^(vint16 a, vint16 b) {
    return _mm512_xor_si512(a, b);
}

RTT_FORCEINLINE vbool16 operator==(vint16 a, vint16 b) {
    return _mm512_cmpeq_epi32_mask(a, b);
}
RTT_FORCEINLINE vbool16 operator!=(vint16 a, vint16 b) {
    return _mm512_cmpneq_epi32_mask(a, b);
}
RTT_FORCEINLINE vbool16 operator<(vint16 a, vint16 b) {
    return _mm512_cmplt_epi32_mask(a, b);
}
RTT_FORCEINLINE vbool16 operator>(vint16 a, vint16 b) {
    return _mm512_cmpgt_epi32_mask(a, b);
}
/// Unsigned a < b (triangle indices, where 0xFFFFFFFF means "none").
RTT_FORCEINLINE vbool16 ult(vint16 a, vint16 b) {
    return _mm512_cmplt_epu32_mask(a, b);
}

RTT_FORCEINLINE vint16 min(vint16 a, vint16 b) {
    return _mm512_min_epi32(a, b);
}
RTT_FORCEINLINE vint16 max(vint16 a, vint16 b) {
    return _mm512_max_epi32(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vint16 select(vbool16 m, vint16 t, vint16 f) {
    return _mm512_mask_blend_epi32(m, f, t);
}
/// The lanes of `a` where m is set, in lane order from lane 0; zero above them.
RTT_FORCEINLINE vint16 compress(vbool16 m, vint16 a) {
    return _mm512_maskz_compress_epi32(m, a);
}
/// Lane i = a[index[i] & 15].
RTT_FORCEINLINE vint16 permute(vint16 a, vint16 index) {
    return _mm512_permutexvar_epi32(index, a);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt

RTT_INTRINSICS_END
