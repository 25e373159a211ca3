// vfloat<8>: 8 floats in an AVX register (built when the compiler targets AVX2).
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/vfloat4.h"
#include "simd/vint8.h"

namespace rtt {
inline namespace RTT_ISA_NS {

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

/// Stores a and b interleaved, p[2 i] = a[i] and p[2 i + 1] = b[i] (records of two floats).
RTT_FORCEINLINE void storeu_pairs(float* p, vfloat8 a, vfloat8 b) {
    const __m256 lo = _mm256_unpacklo_ps(a, b), hi = _mm256_unpackhi_ps(a, b);
    _mm256_storeu_ps(p, _mm256_permute2f128_ps(lo, hi, 0x20));
    _mm256_storeu_ps(p + 8, _mm256_permute2f128_ps(lo, hi, 0x31));
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
/// Lanes of `m` where !(a > b) (NaN included), as vfloat16.h's.
RTT_FORCEINLINE vbool8 not_greater(vbool8 m, vfloat8 a, vfloat8 b) {
    return andnot(m, a > b);
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
/// a * b - c and a * b + c in one rounding (vfloat4.h's mul_sub, which says when to use it).
RTT_FORCEINLINE vfloat8 mul_sub(vfloat8 a, vfloat8 b, vfloat8 c) {
    return _mm256_fmsub_ps(a, b, c);
}
RTT_FORCEINLINE vfloat8 mul_add(vfloat8 a, vfloat8 b, vfloat8 c) {
    return _mm256_fmadd_ps(a, b, c);
}
/// a * b - c with one rounding (vfloat4.h's fused_mul_sub).
RTT_FORCEINLINE vfloat8 fused_mul_sub(vfloat8 a, vfloat8 b, vfloat8 c) {
    return _mm256_fmsub_ps(a, b, c);
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

/// Reads 8 records of 8 floats in two rows of 4, row r at p + r * stride, as 8 vectors: out[f]
/// lane 4 r + i = p[r * stride + 8 i + f] (the classic 8x8 transpose: unpack, shuffle, swap
/// 128-bit halves).
RTT_FORCEINLINE void load_record_rows8(const float* p, std::ptrdiff_t stride, vfloat8 (&out)[8]) {
    __m256 r[8], t[8], s[8];
    for (int j = 0; j < 8; ++j) r[j] = _mm256_loadu_ps(p + (j / 4) * stride + 8 * (j % 4));
    for (int j = 0; j < 8; j += 2) {
        t[j] = _mm256_unpacklo_ps(r[j], r[j + 1]);
        t[j + 1] = _mm256_unpackhi_ps(r[j], r[j + 1]);
    }
    for (int j = 0; j < 8; j += 4) {
        s[j] = _mm256_shuffle_ps(t[j], t[j + 2], 0x44);
        s[j + 1] = _mm256_shuffle_ps(t[j], t[j + 2], 0xEE);
        s[j + 2] = _mm256_shuffle_ps(t[j + 1], t[j + 3], 0x44);
        s[j + 3] = _mm256_shuffle_ps(t[j + 1], t[j + 3], 0xEE);
    }
    for (int f = 0; f < 4; ++f) {
        out[f] = _mm256_permute2f128_ps(s[f], s[f + 4], 0x20);
        out[f + 4] = _mm256_permute2f128_ps(s[f], s[f + 4], 0x31);
    }
}

/// Reads 8 consecutive records of 8 floats, p[8 i + f], as 8 vectors: out[f] lane i = p[8 i + f].
RTT_FORCEINLINE void load_records8(const float* p, vfloat8 (&out)[8]) {
    load_record_rows8(p, 32, out);
}

/// Reads 8 records of 3 floats, p[3 i + c], as 3 vectors: out[c] lane i = p[3 i + c]: per
/// coordinate, each register's lanes permuted into place, then blended.
RTT_FORCEINLINE void load_records3(const float* p, vfloat8 (&out)[3]) {
    const __m256 r0 = _mm256_loadu_ps(p), r1 = _mm256_loadu_ps(p + 8), r2 = _mm256_loadu_ps(p + 16);
    // Element 3 i + c sits in register (3 i + c) / 8 at lane (3 i + c) % 8.
    const __m256i index[3] = {_mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5),
                              _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6),
                              _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7)};
    __m256 from[3][3];
    for (int c = 0; c < 3; ++c) {
        from[c][0] = _mm256_permutevar8x32_ps(r0, index[c]);
        from[c][1] = _mm256_permutevar8x32_ps(r1, index[c]);
        from[c][2] = _mm256_permutevar8x32_ps(r2, index[c]);
    }
    out[0] = _mm256_blend_ps(_mm256_blend_ps(from[0][0], from[0][1], 0x38), from[0][2], 0xC0);
    out[1] = _mm256_blend_ps(_mm256_blend_ps(from[1][0], from[1][1], 0x18), from[1][2], 0xE0);
    out[2] = _mm256_blend_ps(_mm256_blend_ps(from[2][0], from[2][1], 0x1C), from[2][2], 0xE0);
}

/// The 8 lanes (lo[0..3], hi[0..3]).
RTT_FORCEINLINE vfloat8 combine(vfloat4 lo, vfloat4 hi) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(lo), hi, 1);
}

/// Reads 8 records of 3 floats in two rows of 4, row r at p + r * stride, as 3 vectors: out[c]
/// lane 4 r + i = p[r * stride + 3 i + c] (each row as 4 lanes, then the halves combined).
RTT_FORCEINLINE void load_record_rows3(const float* p, std::ptrdiff_t stride, vfloat8 (&out)[3]) {
    if (stride == 12) {  // the rows are one run: fewer, wider loads
        load_records3(p, out);
        return;
    }
    vfloat4 lo[3], hi[3];
    load_records3(p, lo);
    load_records3(p + stride, hi);
    for (int c = 0; c < 3; ++c) out[c] = combine(lo[c], hi[c]);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
