# Compile options of rtt's own targets, as INTERFACE targets (pbrt-v4 pattern). Neither is part
# of an installed target's usage requirements: a consumer of the library inherits no flag
# (docs/architecture.md, "What a consumer compiles with").

# rtt_build_flags: how every rtt target is compiled.
#  -ffp-contract=off  CONVENTIONS: rays are generated and triangles intersected without fused
#                     multiply-add, so every tracer (scalar, SSE, AVX2, AVX-512) computes the
#                     same bits and ties break the same way. Never add -ffast-math.
#  -march=native      the SIMD width follows the build machine (RTT_NATIVE=OFF: SSE4.1).
add_library(rtt_build_flags INTERFACE)
target_compile_options(rtt_build_flags INTERFACE -ffp-contract=off -fno-fast-math)
if(RTT_NATIVE)
  target_compile_options(rtt_build_flags INTERFACE -march=native)
else()
  # The 4-wide SSE path is always available on x86-64; SSE4.1 gives blendv and round.
  target_compile_options(rtt_build_flags INTERFACE -msse4.1)
endif()
if(RTT_SANITIZE)
  target_compile_options(rtt_build_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(rtt_build_flags INTERFACE -fsanitize=address,undefined)
endif()

# rtt_warnings: warnings for our own code only.
add_library(rtt_warnings INTERFACE)
target_compile_options(rtt_warnings INTERFACE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)

# rtt_add_library(name EXPORT_NAME sources...): one of the installed library targets, built
# position-independent (so it can go into a shared object: BUILD_SHARED_LIBS, the Python
# module) with rtt's flags kept private.
function(rtt_add_library name export_name)
  add_library(${name} ${ARGN})
  add_library(rtt::${export_name} ALIAS ${name})
  set_target_properties(${name} PROPERTIES
    EXPORT_NAME ${export_name}
    POSITION_INDEPENDENT_CODE ON
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_include_directories(${name}
    PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_compile_features(${name} PUBLIC cxx_std_20)
  target_link_libraries(${name} PRIVATE $<BUILD_INTERFACE:rtt_build_flags> $<BUILD_INTERFACE:rtt_warnings>)
endfunction()
