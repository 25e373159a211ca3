// The instruction set this translation unit is compiled for, as a namespace. Every header and
// source of the SIMD kernels puts its code in the inline namespace `rtt::RTT_ISA_NS`, so the
// kernels compiled once per ISA (docs/architecture.md, "One binary for every x86-64") never share a
// symbol, and the linker cannot hand an SSE caller an AVX-512 copy of an inline function.
#pragma once

#include "rtt/isa.h"

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512BW__) && defined(__AVX512DQ__)
#define RTT_ISA_NS isa_avx512
#elif defined(__AVX2__) && defined(__FMA__) && defined(__BMI2__)
#define RTT_ISA_NS isa_avx2
#elif defined(__SSE4_2__)
#define RTT_ISA_NS isa_sse42
#else
#error "rtt's kernels need at least SSE4.2 (-march=x86-64-v2)"
#endif

// GCC 12's AVX-512 and permute intrinsics (min, max, sqrt, reductions, permutexvar...) pass
// _mm512_undefined_*() as the merge source, which trips a false -Wuninitialized where they are
// inlined (GCC PR 105593, fixed in GCC 13). The wrappers that use them sit between these two;
// Clang neither warns nor knows the name -Wmaybe-uninitialized.
#if defined(__GNUC__) && !defined(__clang__)
#define RTT_INTRINSICS_BEGIN                                                             \
    _Pragma("GCC diagnostic push") _Pragma("GCC diagnostic ignored \"-Wuninitialized\"") \
        _Pragma("GCC diagnostic ignored \"-Wmaybe-uninitialized\"")
#define RTT_INTRINSICS_END _Pragma("GCC diagnostic pop")
#else
#define RTT_INTRINSICS_BEGIN
#define RTT_INTRINSICS_END
#endif

namespace rtt {
inline namespace RTT_ISA_NS {

/// The ISA of the translation unit that includes this header.
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512BW__) && defined(__AVX512DQ__)
inline constexpr Isa compiled_isa = Isa::avx512;
#elif defined(__AVX2__) && defined(__FMA__) && defined(__BMI2__)
inline constexpr Isa compiled_isa = Isa::avx2;
#else
inline constexpr Isa compiled_isa = Isa::sse42;
#endif

}  // namespace RTT_ISA_NS
}  // namespace rtt
