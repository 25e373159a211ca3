// Compiler helpers for hot code.
#pragma once

#define RTT_FORCEINLINE inline __attribute__((always_inline))
#define RTT_NOINLINE __attribute__((noinline))
