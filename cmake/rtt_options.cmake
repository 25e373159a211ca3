# Compile options of rtt's own targets, as INTERFACE targets (pbrt-v4 pattern). Neither is part
# of an installed target's usage requirements: a consumer of the library inherits no flag
# (docs/architecture.md, "What a consumer compiles with").

# rtt_build_flags: how every rtt target is compiled.
#  -ffp-contract=off  CONVENTIONS: rays are generated and triangles intersected without fused
#                     multiply-add, so every tracer (scalar, SSE, AVX2, AVX-512) computes the
#                     same bits and ties break the same way. Never add -ffast-math.
#  -march=...        the baseline: x86-64-v2 (SSE4.2), so the library runs on any x86-64 CPU
#                     since about 2009; RTT_NATIVE=ON: the build machine's (experiments only).
#                     A target may set its own level in the property RTT_MARCH: the per-ISA
#                     kernel objects (rtt_add_isa_kernels) do.
add_library(rtt_build_flags INTERFACE)
target_compile_options(rtt_build_flags INTERFACE -ffp-contract=off -fno-fast-math)
if(RTT_NATIVE)
  set(RTT_BASELINE_MARCH native)
else()
  set(RTT_BASELINE_MARCH x86-64-v2)
endif()
target_compile_options(rtt_build_flags INTERFACE
  "-march=$<IF:$<BOOL:$<TARGET_PROPERTY:RTT_MARCH>>,$<TARGET_PROPERTY:RTT_MARCH>,${RTT_BASELINE_MARCH}>")
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

# rtt_add_isa_kernels(target sources...): the SIMD kernels once more for each wider ISA
# (docs/architecture.md, "One binary for every x86-64"). The target itself compiles them at the
# baseline (SSE4.2); each variant's objects join it, in namespaces of their own (src/simd/isa.h),
# and RTT_KERNELS_<ISA> tells src/core/isa.cpp and src/trace/registry.cpp which are there.
# RTT_NATIVE builds have the build machine's kernels only.
set(RTT_ISA_VARIANTS "avx2;avx512" CACHE STRING
  "Wider ISAs whose kernels are compiled beside the SSE4.2 baseline (avx2, avx512; ignored with RTT_NATIVE)")
# rtt_isa_level(isa out): the -march level of a variant ISA.
function(rtt_isa_level isa out)
  if(isa STREQUAL "avx2")
    set(${out} x86-64-v3 PARENT_SCOPE)
  elseif(isa STREQUAL "avx512")
    set(${out} x86-64-v4 PARENT_SCOPE)
  else()
    message(FATAL_ERROR "RTT_ISA_VARIANTS: unknown ISA '${isa}' (avx2, avx512)")
  endif()
endfunction()

function(rtt_add_isa_kernels target)
  target_sources(${target} PRIVATE ${ARGN})
  if(RTT_NATIVE)
    return()
  endif()
  foreach(isa ${RTT_ISA_VARIANTS})
    rtt_isa_level(${isa} level)
    set(objects ${target}_${isa})
    add_library(${objects} OBJECT ${ARGN})
    set_target_properties(${objects} PROPERTIES RTT_MARCH ${level} POSITION_INDEPENDENT_CODE ON)
    # The target's own include folders (set before or after this call), as its sources see them.
    target_include_directories(${objects} PRIVATE ${PROJECT_SOURCE_DIR}/include
      ${PROJECT_SOURCE_DIR}/src ${PROJECT_BINARY_DIR}/include
      $<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>)
    target_compile_features(${objects} PRIVATE cxx_std_20)
    target_link_libraries(${objects} PRIVATE rtt_build_flags rtt_warnings TBB::tbb)
    target_sources(${target} PRIVATE $<TARGET_OBJECTS:${objects}>)
    string(TOUPPER ${isa} ISA)
    target_compile_definitions(${target} PRIVATE RTT_KERNELS_${ISA}=1)
  endforeach()
endfunction()
