// vint<8>: 8 signed 32-bit integers in an AVX2 register.
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/vbool8.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct alignas(32) vint<8> {
    __m256i v;

    vint() = default;
    RTT_FORCEINLINE vint(__m256i x) : v(x) {}
    /// Broadcast.
    RTT_FORCEINLINE vint(int32_t s) : v(_mm256_set1_epi32(s)) {}
    RTT_FORCEINLINE operator __m256i() const { return v; }

    static RTT_FORCEINLINE vint load(const int32_t* p) {
        return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
    }
    static RTT_FORCEINLINE vint loadu(const int32_t* p) {
        return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    }
    /// 0, 1, ..., 7.
    static RTT_FORCEINLINE vint step() { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }

    RTT_FORCEINLINE int32_t operator[](int i) const { return ((__v8si)v)[i]; }
    RTT_FORCEINLINE void set(int i, int32_t s) {
        __v8si t = (__v8si)v;
        t[i] = s;
        v = (__m256i)t;
    }
};
using vint8 = vint<8>;

RTT_FORCEINLINE void store(int32_t* p, vint8 a) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(p), a);
}
RTT_FORCEINLINE void storeu(int32_t* p, vint8 a) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), a);
}

RTT_FORCEINLINE vint8 operator+(vint8 a, vint8 b) {
    return _mm256_add_epi32(a, b);
}
RTT_FORCEINLINE vint8 operator-(vint8 a, vint8 b) {
    return _mm256_sub_epi32(a, b);
}
/// Low 32 bits of the product (wraps like unsigned arithmetic).
RTT_FORCEINLINE vint8 operator*(vint8 a, vint8 b) {
    return _mm256_mullo_epi32(a, b);
}
RTT_FORCEINLINE vint8 operator&(vint8 a, vint8 b) {
    return _mm256_and_si256(a, b);
}
RTT_FORCEINLINE vint8 operator|(vint8 a, vint8 b) {
    return _mm256_or_si256(a, b);
}
RTT_FORCEINLINE vint8 operator^(vint8 a, vint8 b) {
    return _mm256_xor_si256(a, b);
}

RTT_FORCEINLINE vbool8 operator==(vint8 a, vint8 b) {
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(a, b));
}
RTT_FORCEINLINE vbool8 operator!=(vint8 a, vint8 b) {
    return !(a == b);
}
RTT_FORCEINLINE vbool8 operator<(vint8 a, vint8 b) {
    return _mm256_castsi256_ps(_mm256_cmpgt_epi32(b, a));
}
RTT_FORCEINLINE vbool8 operator>(vint8 a, vint8 b) {
    return _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b));
}
/// Unsigned a < b (triangle indices, where 0xFFFFFFFF means "none").
RTT_FORCEINLINE vbool8 ult(vint8 a, vint8 b) {
    const __m256i flip = _mm256_set1_epi32(INT32_MIN);
    return _mm256_castsi256_ps(
        _mm256_cmpgt_epi32(_mm256_xor_si256(b, flip), _mm256_xor_si256(a, flip)));
}

RTT_FORCEINLINE vint8 min(vint8 a, vint8 b) {
    return _mm256_min_epi32(a, b);
}
RTT_FORCEINLINE vint8 max(vint8 a, vint8 b) {
    return _mm256_max_epi32(a, b);
}
/// m ? t : f, lane by lane.
RTT_FORCEINLINE vint8 select(vbool8 m, vint8 t, vint8 f) {
    return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(f), _mm256_castsi256_ps(t), m));
}
/// Lane i = a[index[i] & 7].
RTT_FORCEINLINE vint8 permute(vint8 a, vint8 index) {
    return _mm256_permutevar8x32_epi32(a, index);
}
/// Lane i = byte i of `bytes`, zero-extended.
RTT_FORCEINLINE vint8 widen_bytes(uint64_t bytes) {
    return _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(int64_t(bytes)));
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
