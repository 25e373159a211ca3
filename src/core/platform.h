// Compiler helpers for hot code.
#pragma once

#include <cstddef>
#include <cstdint>

#define RTT_FORCEINLINE inline __attribute__((always_inline))
#define RTT_NOINLINE __attribute__((noinline))

namespace rtt {

/// Starts loading every cache line of the `bytes` bytes at `p`, which may start mid-line.
RTT_FORCEINLINE void prefetch_bytes(const void* p, size_t bytes) {
    const uintptr_t begin = reinterpret_cast<uintptr_t>(p);
    for (uintptr_t line = begin & ~uintptr_t(63); line < begin + bytes; line += 64)
        __builtin_prefetch(reinterpret_cast<const void*>(line));
}

}  // namespace rtt
