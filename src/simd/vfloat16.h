// vfloat<16>: 16 floats in an AVX-512 register (built when the compiler targets AVX-512F).
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/vfloat4.h"
#include "simd/vint16.h"

// GCC 12's intrinsics and false warnings: simd/isa.h.
RTT_INTRINSICS_BEGIN

namespace rtt {
inline namespace RTT_ISA_NS {

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

/// Stores a and b interleaved, p[2 i] = a[i] and p[2 i + 1] = b[i] (records of two floats, e.g.
/// a hit's t and a triangle index as bits): one two-register permute per 16 floats.
RTT_FORCEINLINE void storeu_pairs(float* p, vfloat16 a, vfloat16 b) {
    alignas(64) static constexpr int32_t index[2][16] = {
        {0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23},
        {8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31}};
    _mm512_storeu_ps(p, _mm512_permutex2var_ps(a, _mm512_load_si512(index[0]), b));
    _mm512_storeu_ps(p + 16, _mm512_permutex2var_ps(a, _mm512_load_si512(index[1]), b));
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
/// Lanes of `m` where !(a > b) (NaN included): andnot(m, a > b) as one masked compare, which
/// keeps the mask in a mask register (the packet descent's branches test it directly).
RTT_FORCEINLINE vbool16 not_greater(vbool16 m, vfloat16 a, vfloat16 b) {
    return _mm512_mask_cmp_ps_mask(m, a, b, _CMP_NGT_UQ);
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
/// a * b - c and a * b + c in one rounding (vfloat4.h's mul_sub, which says when to use it).
RTT_FORCEINLINE vfloat16 mul_sub(vfloat16 a, vfloat16 b, vfloat16 c) {
    return _mm512_fmsub_ps(a, b, c);
}
RTT_FORCEINLINE vfloat16 mul_add(vfloat16 a, vfloat16 b, vfloat16 c) {
    return _mm512_fmadd_ps(a, b, c);
}
/// a * b - c with one rounding (vfloat4.h's fused_mul_sub).
RTT_FORCEINLINE vfloat16 fused_mul_sub(vfloat16 a, vfloat16 b, vfloat16 c) {
    return _mm512_fmsub_ps(a, b, c);
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

/// Reads 16 records of 8 floats in four rows of 4, row r at p + r * stride, as 8 vectors:
/// out[f] lane 4 r + i = p[r * stride + 8 i + f] (three rounds of two-register permutes, each
/// swapping one bit of the register number with one of the lane number; no gather, which is
/// slow on some cores, and no staging through memory).
RTT_FORCEINLINE void load_record_rows8(const float* p, std::ptrdiff_t stride, vfloat16 (&out)[8]) {
    alignas(64) static constexpr int32_t index[3][2][16] = {
        {{0, 16, 2, 18, 4, 20, 6, 22, 8, 24, 10, 26, 12, 28, 14, 30},
         {1, 17, 3, 19, 5, 21, 7, 23, 9, 25, 11, 27, 13, 29, 15, 31}},
        {{0, 1, 16, 17, 4, 5, 20, 21, 8, 9, 24, 25, 12, 13, 28, 29},
         {2, 3, 18, 19, 6, 7, 22, 23, 10, 11, 26, 27, 14, 15, 30, 31}},
        // The last round also puts the lanes in record order.
        {{0, 8, 1, 9, 2, 10, 3, 11, 16, 24, 17, 25, 18, 26, 19, 27},
         {4, 12, 5, 13, 6, 14, 7, 15, 20, 28, 21, 29, 22, 30, 23, 31}}};
    __m512 r[8];
    for (int j = 0; j < 8; ++j) r[j] = _mm512_loadu_ps(p + (j / 2) * stride + 16 * (j % 2));
    for (int s = 0; s < 3; ++s) {
        const __m512i lo = _mm512_load_si512(index[s][0]), hi = _mm512_load_si512(index[s][1]);
        for (int a = 0; a < 8; ++a) {
            if ((a >> s) & 1) continue;
            const int b = a | (1 << s);
            const __m512 x = _mm512_permutex2var_ps(r[a], lo, r[b]);
            r[b] = _mm512_permutex2var_ps(r[a], hi, r[b]);
            r[a] = x;
        }
    }
    for (int f = 0; f < 8; ++f) out[f] = r[f];
}

/// Reads 16 consecutive records of 8 floats, p[8 i + f], as 8 vectors: out[f] lane i =
/// p[8 i + f].
RTT_FORCEINLINE void load_records8(const float* p, vfloat16 (&out)[8]) {
    load_record_rows8(p, 32, out);
}

/// Reads 16 records of 3 floats, p[3 i + c], as 3 vectors: out[c] lane i = p[3 i + c].
RTT_FORCEINLINE void load_records3(const float* p, vfloat16 (&out)[3]) {
    // Per coordinate: lanes from the first two registers (record i's element 3 i + c < 32),
    // then the third's.
    alignas(64) static constexpr int32_t first[3][16] = {
        {0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0},
        {1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0},
        {2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0}};
    alignas(64) static constexpr int32_t second[3][16] = {
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29},
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30},
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31}};
    const __m512 r0 = _mm512_loadu_ps(p), r1 = _mm512_loadu_ps(p + 16),
                 r2 = _mm512_loadu_ps(p + 32);
    for (int c = 0; c < 3; ++c) {
        const __m512 t = _mm512_permutex2var_ps(r0, _mm512_load_si512(first[c]), r1);
        out[c] = _mm512_permutex2var_ps(t, _mm512_load_si512(second[c]), r2);
    }
}

/// Reads 16 records of 3 floats in four rows of 4, row r at p + r * stride, as 3 vectors:
/// out[c] lane 4 r + i = p[r * stride + 3 i + c] (each row as 4 lanes, then inserted).
RTT_FORCEINLINE void load_record_rows3(const float* p, std::ptrdiff_t stride, vfloat16 (&out)[3]) {
    if (stride == 12) {  // the rows are one run: fewer, wider loads
        load_records3(p, out);
        return;
    }
    vfloat4 row[4][3];
    for (int r = 0; r < 4; ++r) load_records3(p + r * stride, row[r]);
    for (int c = 0; c < 3; ++c) {
        __m512 v = _mm512_castps128_ps512(row[0][c]);
        v = _mm512_insertf32x4(v, row[1][c], 1);
        v = _mm512_insertf32x4(v, row[2][c], 2);
        out[c] = _mm512_insertf32x4(v, row[3][c], 3);
    }
}

}  // namespace RTT_ISA_NS
}  // namespace rtt

RTT_INTRINSICS_END
