// vbool<16>: a 16-lane AVX-512 mask register (one bit per lane).
#pragma once

#include <immintrin.h>

#include "simd/isa.h"
#include "simd/varying.h"

namespace rtt {
inline namespace RTT_ISA_NS {

template <>
struct vbool<16> {
    __mmask16 v;

    vbool() = default;
    RTT_FORCEINLINE vbool(__mmask16 m) : v(m) {}
    RTT_FORCEINLINE explicit vbool(bool b) : v(b ? 0xFFFF : 0) {}
    RTT_FORCEINLINE operator __mmask16() const { return v; }

    /// Lane i is true when bit i of `bits` is set.
    static RTT_FORCEINLINE vbool from_bits(uint32_t bits) { return __mmask16(bits); }
    RTT_FORCEINLINE bool operator[](int i) const { return (v >> i) & 1; }
};
using vbool16 = vbool<16>;

RTT_FORCEINLINE vbool16 operator&(vbool16 a, vbool16 b) {
    return __mmask16(a.v & b.v);
}
RTT_FORCEINLINE vbool16 operator|(vbool16 a, vbool16 b) {
    return __mmask16(a.v | b.v);
}
RTT_FORCEINLINE vbool16 operator^(vbool16 a, vbool16 b) {
    return __mmask16(a.v ^ b.v);
}
RTT_FORCEINLINE vbool16 operator!(vbool16 a) {
    return __mmask16(~a.v);
}
/// a && !b.
RTT_FORCEINLINE vbool16 andnot(vbool16 a, vbool16 b) {
    return __mmask16(a.v & ~b.v);
}
RTT_FORCEINLINE vbool16& operator&=(vbool16& a, vbool16 b) {
    return a = a & b;
}
RTT_FORCEINLINE vbool16& operator|=(vbool16& a, vbool16 b) {
    return a = a | b;
}

/// Bit i = lane i.
RTT_FORCEINLINE uint32_t movemask(vbool16 a) {
    return uint32_t(a.v);
}
RTT_FORCEINLINE bool any(vbool16 a) {
    return a.v != 0;
}
RTT_FORCEINLINE bool all(vbool16 a) {
    return a.v == 0xFFFF;
}
RTT_FORCEINLINE bool none(vbool16 a) {
    return a.v == 0;
}
RTT_FORCEINLINE int popcount(vbool16 a) {
    return std::popcount(movemask(a));
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
