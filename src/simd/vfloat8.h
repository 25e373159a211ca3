// vfloat<8>: 8 floats in an AVX register (built when the compiler targets AVX2).
#pragma once

#include <immintrin.h>

#include "simd/vint8.h"

namespace rtt {

template <>
struct alignas(32) vfloat<8> {
    __m256 v;

    vfloat() = default;
    RTT_FORCEINLINE vfloat(__m256 x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vfloat(float s) : v(_mm256_set1_ps(s)) {}
    RTT_FORCEINLINE operator __m256() const { return v; }

    static RTT_FORCEINLINE vfloat load(const float* p) { return _mm256_load_ps(p); }
    static RTT_FORCEINLINE vfloat loadu(const float* p) { return _mm256_loadu_ps(p); }

    RTT_FORCEINLINE float operator[](int i) const { return v[i]; }
    RTT_FORCEINLINE void set(int i, float s) { v[i] = s; }
};
using vfloat8 = vfloat<8>;

RTT_FORCEINLINE void store(float* p, vfloat8 a) {
    _mm256_store_ps(p, a);
}
RTT_FORCEINLINE void storeu(float* p, vfloat8 a) {
    _mm256_storeu_ps(p, a);
}
/// Writes only the lanes of `m`; the others keep what `p` held.
RTT_FORCEINLINE void store(vbool8 m, float* p, vfloat8 a) {
    _mm256_maskstore_ps(p, _mm256_castps_si256(m), a);
}

RTT_FORCEINLINE vfloat8 operator+(vfloat8 a, vfloat8 b) {
    return _mm256_add_ps(a, b);
}
RTT_FORCEINLINE vfloat8 operator-(vfloat8 a, vfloat8 b) {
    return _mm256_sub_ps(a, b);
}
RTT_FORCEINLINE vfloat8 operator*(vfloat8 a, vfloat8 b) {
    return _mm256_mul_ps(a, b);
}
RTT_FORCEINLINE vfloat8 operator/(vfloat8 a, vfloat8 b) {
    return _mm256_div_ps(a, b);
}
RTT_FORCEINLINE vfloat8 operator-(vfloat8 a) {
    return _mm256_xor_ps(a, _mm256_set1_ps(-0.f));
}

// Comparisons follow C++: ordered (false on NaN), except != (true on NaN).
RTT_FORCEINLINE vbool8 operator<(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_LT_OQ);
}
RTT_FORCEINLINE vbool8 operator<=(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_LE_OQ);
}
RTT_FORCEINLINE vbool8 operator>(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_GT_OQ);
}
RTT_FORCEINLINE vbool8 operator>=(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_GE_OQ);
}
RTT_FORCEINLINE vbool8 operator==(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_EQ_OQ);
}
RTT_FORCEINLINE vbool8 operator!=(vfloat8 a, vfloat8 b) {
    return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ);
}
RTT_FORCEINLINE vbool8 isnan(vfloat8 a) {
    return _mm256_cmp_ps(a, a, _CMP_UNORD_Q);
}

/// a < b ? a : b, lane by lane (b when either is NaN or they are equal): std::min(x, y) ==
/// min(y, x) bit for bit.
RTT_FORCEINLINE vfloat8 min(vfloat8 a, vfloat8 b) {
    return _mm256_min_ps(a, b);
}
/// a > b ? a : b, lane by lane; std::max(x, y) == max(y, x) bit for bit.
RTT_FORCEINLINE vfloat8 max(vfloat8 a, vfloat8 b) {
    return _mm256_max_ps(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vfloat8 select(vbool8 m, vfloat8 t, vfloat8 f) {
    return _mm256_blendv_ps(f, t, m);
}
RTT_FORCEINLINE vfloat8 abs(vfloat8 a) {
    return _mm256_andnot_ps(_mm256_set1_ps(-0.f), a);
}
/// 1 / a, correctly rounded (a division, not the approximate rcpps).
RTT_FORCEINLINE vfloat8 rcp(vfloat8 a) {
    return _mm256_div_ps(_mm256_set1_ps(1.f), a);
}
RTT_FORCEINLINE vfloat8 sqrt(vfloat8 a) {
    return _mm256_sqrt_ps(a);
}
/// Lanes whose sign bit is set, as lane bits.
RTT_FORCEINLINE uint32_t signbits(vfloat8 a) {
    return uint32_t(_mm256_movemask_ps(a));
}

/// Horizontal minimum / maximum broadcast to every lane (inputs without NaN).
RTT_FORCEINLINE vfloat8 reduce_min(vfloat8 a) {
    const vfloat8 b = _mm256_min_ps(a, _mm256_permute_ps(a, _MM_SHUFFLE(2, 3, 0, 1)));
    const vfloat8 c = _mm256_min_ps(b, _mm256_permute_ps(b, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm256_min_ps(c, _mm256_permute2f128_ps(c, c, 1));
}
RTT_FORCEINLINE vfloat8 reduce_max(vfloat8 a) {
    const vfloat8 b = _mm256_max_ps(a, _mm256_permute_ps(a, _MM_SHUFFLE(2, 3, 0, 1)));
    const vfloat8 c = _mm256_max_ps(b, _mm256_permute_ps(b, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm256_max_ps(c, _mm256_permute2f128_ps(c, c, 1));
}

RTT_FORCEINLINE vint8 as_int(vfloat8 a) {
    return _mm256_castps_si256(a);
}
RTT_FORCEINLINE vfloat8 as_float(vint8 a) {
    return _mm256_castsi256_ps(a);
}

}  // namespace rtt
