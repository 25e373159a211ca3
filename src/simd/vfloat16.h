// vfloat<16>: 16 floats in an AVX-512 register (built when the compiler targets AVX-512F).
#pragma once

#include <immintrin.h>

#include "simd/vint16.h"

// GCC 12's AVX-512 intrinsics (min, max, sqrt, reductions...) pass _mm512_undefined_*() as the
// merge source, which trips a false -Wuninitialized where they are inlined (GCC PR 105593,
// fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace rtt {

template <>
struct alignas(64) vfloat<16> {
    __m512 v;

    vfloat() = default;
    RTT_FORCEINLINE vfloat(__m512 x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vfloat(float s) : v(_mm512_set1_ps(s)) {}
    RTT_FORCEINLINE operator __m512() const { return v; }

    static RTT_FORCEINLINE vfloat load(const float* p) { return _mm512_load_ps(p); }
    static RTT_FORCEINLINE vfloat loadu(const float* p) { return _mm512_loadu_ps(p); }

    RTT_FORCEINLINE float operator[](int i) const { return v[i]; }
    RTT_FORCEINLINE void set(int i, float s) { v[i] = s; }
};
using vfloat16 = vfloat<16>;

RTT_FORCEINLINE void store(float* p, vfloat16 a) {
    _mm512_store_ps(p, a);
}
RTT_FORCEINLINE void storeu(float* p, vfloat16 a) {
    _mm512_storeu_ps(p, a);
}
/// Writes only the lanes of `m`; the others keep what `p` held.
RTT_FORCEINLINE void store(vbool16 m, float* p, vfloat16 a) {
    _mm512_mask_storeu_ps(p, m, a);
}

RTT_FORCEINLINE vfloat16 operator+(vfloat16 a, vfloat16 b) {
    return _mm512_add_ps(a, b);
}
RTT_FORCEINLINE vfloat16 operator-(vfloat16 a, vfloat16 b) {
    return _mm512_sub_ps(a, b);
}
RTT_FORCEINLINE vfloat16 operator*(vfloat16 a, vfloat16 b) {
    return _mm512_mul_ps(a, b);
}
RTT_FORCEINLINE vfloat16 operator/(vfloat16 a, vfloat16 b) {
    return _mm512_div_ps(a, b);
}
RTT_FORCEINLINE vfloat16 operator-(vfloat16 a) {
    return _mm512_castsi512_ps(
        _mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32(INT32_MIN)));
}

// Comparisons follow C++: ordered (false on NaN), except != (true on NaN).
RTT_FORCEINLINE vbool16 operator<(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ);
}
RTT_FORCEINLINE vbool16 operator<=(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ);
}
RTT_FORCEINLINE vbool16 operator>(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ);
}
RTT_FORCEINLINE vbool16 operator>=(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ);
}
RTT_FORCEINLINE vbool16 operator==(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ);
}
RTT_FORCEINLINE vbool16 operator!=(vfloat16 a, vfloat16 b) {
    return _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ);
}
RTT_FORCEINLINE vbool16 isnan(vfloat16 a) {
    return _mm512_cmp_ps_mask(a, a, _CMP_UNORD_Q);
}

/// a < b ? a : b, lane by lane (b when either is NaN or they are equal): std::min(x, y) ==
/// min(y, x) bit for bit.
RTT_FORCEINLINE vfloat16 min(vfloat16 a, vfloat16 b) {
    return _mm512_min_ps(a, b);
}
/// a > b ? a : b, lane by lane; std::max(x, y) == max(y, x) bit for bit.
RTT_FORCEINLINE vfloat16 max(vfloat16 a, vfloat16 b) {
    return _mm512_max_ps(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vfloat16 select(vbool16 m, vfloat16 t, vfloat16 f) {
    return _mm512_mask_blend_ps(m, f, t);
}
RTT_FORCEINLINE vfloat16 abs(vfloat16 a) {
    return _mm512_castsi512_ps(
        _mm512_and_si512(_mm512_castps_si512(a), _mm512_set1_epi32(INT32_MAX)));
}
/// 1 / a, correctly rounded (a division, not the approximate rcp14).
RTT_FORCEINLINE vfloat16 rcp(vfloat16 a) {
    return _mm512_div_ps(_mm512_set1_ps(1.f), a);
}
RTT_FORCEINLINE vfloat16 sqrt(vfloat16 a) {
    return _mm512_sqrt_ps(a);
}
/// Lanes whose sign bit is set, as lane bits.
RTT_FORCEINLINE uint32_t signbits(vfloat16 a) {
    return uint32_t(_mm512_cmplt_epi32_mask(_mm512_castps_si512(a), _mm512_setzero_si512()));
}

/// Horizontal minimum / maximum broadcast to every lane (inputs without NaN).
RTT_FORCEINLINE vfloat16 reduce_min(vfloat16 a) {
    return _mm512_set1_ps(_mm512_reduce_min_ps(a));
}
RTT_FORCEINLINE vfloat16 reduce_max(vfloat16 a) {
    return _mm512_set1_ps(_mm512_reduce_max_ps(a));
}

RTT_FORCEINLINE vint16 as_int(vfloat16 a) {
    return _mm512_castps_si512(a);
}
RTT_FORCEINLINE vfloat16 as_float(vint16 a) {
    return _mm512_castsi512_ps(a);
}

}  // namespace rtt

#pragma GCC diagnostic pop
