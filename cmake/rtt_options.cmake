# Compile options shared by every rtt target, as INTERFACE targets (pbrt-v4 pattern).

# rtt_options: flags that are part of the correctness contract.
#  -ffp-contract=off  CONVENTIONS: rays are generated and triangles intersected without fused
#                     multiply-add, so every tracer (scalar, SSE, AVX2, AVX-512) computes the
#                     same bits and ties break the same way. Never add -ffast-math.
add_library(rtt_options INTERFACE)
target_compile_options(rtt_options INTERFACE -ffp-contract=off -fno-fast-math)
if(RTT_NATIVE)
  target_compile_options(rtt_options INTERFACE -march=native)
else()
  # The 4-wide SSE path is always available on x86-64; SSE4.1 gives blendv and round.
  target_compile_options(rtt_options INTERFACE -msse4.1)
endif()
if(RTT_SANITIZE)
  target_compile_options(rtt_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(rtt_options INTERFACE -fsanitize=address,undefined)
endif()

# rtt_warnings: warnings for our own code only.
add_library(rtt_warnings INTERFACE)
target_compile_options(rtt_warnings INTERFACE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
