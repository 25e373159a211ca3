// Lane masks to and from one byte per lane, the layout of the tracers' activity and visibility
// arrays (uint8_t, 0 or 1): a block's 16 bytes in a few instructions instead of a loop of
// byte loads or stores with a branch per lane.
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>

#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Bits of the nonzero bytes among p[0], ..., p[n - 1] (n <= 16; nothing past them is read).
inline uint32_t nonzero_bytes(const uint8_t* p, int n) {
    alignas(16) uint8_t b[16] = {};
    std::memcpy(b, p, size_t(n));
    const __m128i v = _mm_load_si128(reinterpret_cast<const __m128i*>(b));
    const uint32_t zero = uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128())));
    return ~zero & ((1u << n) - 1u);
}

/// p[i] = bit i of `bits` (0 or 1) for i < K (K <= 16).
template <int K>
inline void store_bits_as_bytes(uint8_t* p, uint32_t bits) {
#ifdef __BMI2__
    const uint64_t b[2] = {_pdep_u64(bits & 0xFFu, 0x0101010101010101ull),
                           _pdep_u64((bits >> 8) & 0xFFu, 0x0101010101010101ull)};
    std::memcpy(p, b, size_t(K));
#else
    for (int i = 0; i < K; ++i) p[i] = uint8_t((bits >> i) & 1u);
#endif
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
