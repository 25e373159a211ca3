// vfloat<4>: 4 floats in an SSE register (SSE4.1; AVX encodings when the compiler targets AVX).
#pragma once

#include <immintrin.h>

#include <cstddef>

#include "simd/isa.h"
#include "simd/vint4.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct alignas(16) vfloat<4> {
    __m128 v;

    vfloat() = default;
    RTT_FORCEINLINE vfloat(__m128 x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vfloat(float s) : v(_mm_set1_ps(s)) {}
    RTT_FORCEINLINE operator __m128() const { return v; }

    static RTT_FORCEINLINE vfloat load(const float* p) { return _mm_load_ps(p); }
    static RTT_FORCEINLINE vfloat loadu(const float* p) { return _mm_loadu_ps(p); }
    /// Lanes (a, b, c, d), built in registers: a vector loaded from scalars just stored to
    /// memory would wait on store forwarding.
    static RTT_FORCEINLINE vfloat setr(float a, float b, float c, float d) {
        return _mm_setr_ps(a, b, c, d);
    }

    RTT_FORCEINLINE float operator[](int i) const { return v[i]; }
    RTT_FORCEINLINE void set(int i, float s) { v[i] = s; }
};
using vfloat4 = vfloat<4>;

RTT_FORCEINLINE void store(float* p, vfloat4 a) {
    _mm_store_ps(p, a);
}
RTT_FORCEINLINE void storeu(float* p, vfloat4 a) {
    _mm_storeu_ps(p, a);
}
/// Writes only the lanes of `m`; the others keep what `p` held.
RTT_FORCEINLINE void store(vbool4 m, float* p, vfloat4 a) {
#ifdef __AVX__
    _mm_maskstore_ps(p, _mm_castps_si128(m), a);
#else
    for (uint32_t bits = movemask(m); bits; bits &= bits - 1)
        p[std::countr_zero(bits)] = a[std::countr_zero(bits)];
#endif
}

/// Stores a and b interleaved, p[2 i] = a[i] and p[2 i + 1] = b[i] (records of two floats).
RTT_FORCEINLINE void storeu_pairs(float* p, vfloat4 a, vfloat4 b) {
    _mm_storeu_ps(p, _mm_unpacklo_ps(a, b));
    _mm_storeu_ps(p + 4, _mm_unpackhi_ps(a, b));
}

RTT_FORCEINLINE vfloat4 operator+(vfloat4 a, vfloat4 b) {
    return _mm_add_ps(a, b);
}
RTT_FORCEINLINE vfloat4 operator-(vfloat4 a, vfloat4 b) {
    return _mm_sub_ps(a, b);
}
RTT_FORCEINLINE vfloat4 operator*(vfloat4 a, vfloat4 b) {
    return _mm_mul_ps(a, b);
}
RTT_FORCEINLINE vfloat4 operator/(vfloat4 a, vfloat4 b) {
    return _mm_div_ps(a, b);
}
RTT_FORCEINLINE vfloat4 operator-(vfloat4 a) {
    return _mm_xor_ps(a, _mm_set1_ps(-0.f));
}

// Comparisons follow C++: ordered (false on NaN), except != (true on NaN).
RTT_FORCEINLINE vbool4 operator<(vfloat4 a, vfloat4 b) {
    return _mm_cmplt_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator<=(vfloat4 a, vfloat4 b) {
    return _mm_cmple_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator>(vfloat4 a, vfloat4 b) {
    return _mm_cmpgt_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator>=(vfloat4 a, vfloat4 b) {
    return _mm_cmpge_ps(a, b);
}
/// Lanes of `m` where !(a > b) (NaN included), as vfloat16.h's.
RTT_FORCEINLINE vbool4 not_greater(vbool4 m, vfloat4 a, vfloat4 b) {
    return andnot(m, a > b);
}
RTT_FORCEINLINE vbool4 operator==(vfloat4 a, vfloat4 b) {
    return _mm_cmpeq_ps(a, b);
}
RTT_FORCEINLINE vbool4 operator!=(vfloat4 a, vfloat4 b) {
    return _mm_cmpneq_ps(a, b);
}
RTT_FORCEINLINE vbool4 isnan(vfloat4 a) {
    return _mm_cmpunord_ps(a, a);
}

/// a < b ? a : b, lane by lane (the SSE rule: b when either is NaN or they are equal), so
/// std::min(x, y) == min(y, x) bit for bit, NaN and signed zeros included.
RTT_FORCEINLINE vfloat4 min(vfloat4 a, vfloat4 b) {
    return _mm_min_ps(a, b);
}
/// a > b ? a : b, lane by lane; std::max(x, y) == max(y, x) bit for bit.
RTT_FORCEINLINE vfloat4 max(vfloat4 a, vfloat4 b) {
    return _mm_max_ps(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vfloat4 select(vbool4 m, vfloat4 t, vfloat4 f) {
    return _mm_blendv_ps(f, t, m);
}
/// a * b - c and a * b + c: one rounding where the target has FMA, two (product, then sum)
/// where it does not. Only for bounds that tolerate either; -ffp-contract=off keeps every other
/// product rounded on its own.
RTT_FORCEINLINE vfloat4 mul_sub(vfloat4 a, vfloat4 b, vfloat4 c) {
#ifdef __FMA__
    return _mm_fmsub_ps(a, b, c);
#else
    return a * b - c;
#endif
}
RTT_FORCEINLINE vfloat4 mul_add(vfloat4 a, vfloat4 b, vfloat4 c) {
#ifdef __FMA__
    return _mm_fmadd_ps(a, b, c);
#else
    return a * b + c;
#endif
}
#ifndef __FMA__
/// x * y - z for two lanes of floats widened to double, rounded to odd: the product is exact in
/// double, the difference is rounded to nearest and its error recovered exactly (Knuth's
/// TwoSum); an inexact result with an even last bit moves one ulp towards the exact value.
/// Rounding that to float is then the correctly rounded float result (Boldo and Melquiond,
/// "Emulation of FMA and correctly rounded sums: proved algorithms using rounding to odd",
/// IEEE Trans. Computers 57(4), 2008: double has more than twice float's bits plus one).
RTT_FORCEINLINE __m128d mul_sub_round_to_odd(__m128d x, __m128d y, __m128d z) {
    const __m128d p = _mm_mul_pd(x, y), nz = _mm_xor_pd(z, _mm_set1_pd(-0.0));
    const __m128d s = _mm_add_pd(p, nz);
    const __m128d bb = _mm_sub_pd(s, p);
    const __m128d err = _mm_add_pd(_mm_sub_pd(p, _mm_sub_pd(s, bb)), _mm_sub_pd(nz, bb));
    // err is NaN where s is infinite or NaN: those lanes are left as they are.
    const __m128i inexact =
        _mm_castpd_si128(_mm_and_pd(_mm_cmpneq_pd(err, _mm_setzero_pd()), _mm_cmpord_pd(err, err)));
    const __m128i bits = _mm_castpd_si128(s);
    const __m128i even =
        _mm_cmpeq_epi64(_mm_and_si128(bits, _mm_set1_epi64x(1)), _mm_setzero_si128());
    // +1 in the bits moves away from zero: where err points towards zero, -1.
    const __m128i towards_zero =
        _mm_cmpgt_epi64(_mm_setzero_si128(), _mm_castpd_si128(_mm_xor_pd(err, s)));
    const __m128i step = _mm_or_si128(towards_zero, _mm_set1_epi64x(1));
    return _mm_castsi128_pd(_mm_add_epi64(bits, _mm_and_si128(_mm_and_si128(inexact, even), step)));
}
#endif

/// a * b - c with one rounding on every target: the FMA instruction, or where there is none
/// (SSE4.2) the same correctly rounded result through double, so each ISA computes the same
/// bits. For the triangle test's edge functions (geom/triangle.h, difference_of_products).
RTT_FORCEINLINE vfloat4 fused_mul_sub(vfloat4 a, vfloat4 b, vfloat4 c) {
#ifdef __FMA__
    return _mm_fmsub_ps(a, b, c);
#else
    const auto high = [](__m128 v) { return _mm_cvtps_pd(_mm_movehl_ps(v, v)); };
    const __m128d lo = mul_sub_round_to_odd(_mm_cvtps_pd(a), _mm_cvtps_pd(b), _mm_cvtps_pd(c));
    const __m128d hi = mul_sub_round_to_odd(high(a), high(b), high(c));
    return _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi));
#endif
}
RTT_FORCEINLINE vfloat4 abs(vfloat4 a) {
    return _mm_andnot_ps(_mm_set1_ps(-0.f), a);
}
/// 1 / a, correctly rounded (a division, not the approximate rcpps: rtt needs exact results).
RTT_FORCEINLINE vfloat4 rcp(vfloat4 a) {
    return _mm_div_ps(_mm_set1_ps(1.f), a);
}
RTT_FORCEINLINE vfloat4 sqrt(vfloat4 a) {
    return _mm_sqrt_ps(a);
}
/// Lanes whose sign bit is set (-0.f and NaNs with the sign bit included), as lane bits.
RTT_FORCEINLINE uint32_t signbits(vfloat4 a) {
    return uint32_t(_mm_movemask_ps(a));
}

/// Horizontal minimum / maximum broadcast to every lane (inputs without NaN).
RTT_FORCEINLINE vfloat4 reduce_min(vfloat4 a) {
    const vfloat4 b = _mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_min_ps(b, _mm_shuffle_ps(b, b, _MM_SHUFFLE(1, 0, 3, 2)));
}
RTT_FORCEINLINE vfloat4 reduce_max(vfloat4 a) {
    const vfloat4 b = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_max_ps(b, _mm_shuffle_ps(b, b, _MM_SHUFFLE(1, 0, 3, 2)));
}

RTT_FORCEINLINE vint4 as_int(vfloat4 a) {
    return _mm_castps_si128(a);
}
RTT_FORCEINLINE vfloat4 as_float(vint4 a) {
    return _mm_castsi128_ps(a);
}
/// Each lane rounded toward zero to an integer (lanes within int32's range).
RTT_FORCEINLINE vint4 truncate_to_int(vfloat4 a) {
    return _mm_cvttps_epi32(a);
}

/// Reads 4 records of 8 floats in two rows of 2, row r at p + r * stride, as 8 vectors: out[f]
/// lane 2 r + i = p[r * stride + 8 i + f] (two 4x4 transposes, one per half record).
RTT_FORCEINLINE void load_record_rows8(const float* p, std::ptrdiff_t stride, vfloat4 (&out)[8]) {
    for (int h = 0; h < 2; ++h) {
        __m128 a = _mm_loadu_ps(p + 4 * h), b = _mm_loadu_ps(p + 8 + 4 * h),
               c = _mm_loadu_ps(p + stride + 4 * h), d = _mm_loadu_ps(p + stride + 8 + 4 * h);
        _MM_TRANSPOSE4_PS(a, b, c, d);
        out[4 * h] = a;
        out[4 * h + 1] = b;
        out[4 * h + 2] = c;
        out[4 * h + 3] = d;
    }
}

/// Reads 4 consecutive records of 8 floats, p[8 i + f], as 8 vectors: out[f] lane i = p[8 i + f].
RTT_FORCEINLINE void load_records8(const float* p, vfloat4 (&out)[8]) {
    load_record_rows8(p, 16, out);
}

/// Reads 4 records of 3 floats in two rows of 2, row r at p + r * stride, as 3 vectors: out[c]
/// lane 2 r + i = p[r * stride + 3 i + c].
RTT_FORCEINLINE void load_record_rows3(const float* p, std::ptrdiff_t stride, vfloat4 (&out)[3]) {
    for (int c = 0; c < 3; ++c)
        out[c] = _mm_setr_ps(p[c], p[3 + c], p[stride + c], p[stride + 3 + c]);
}

/// Reads 4 consecutive records of 3 floats, p[3 i + c], as 3 vectors: out[c] lane i = p[3 i + c].
RTT_FORCEINLINE void load_records3(const float* p, vfloat4 (&out)[3]) {
    load_record_rows3(p, 6, out);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
