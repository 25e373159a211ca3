#!/usr/bin/env bash
# The README's test command: install what is missing, build, run the whole test suite; then
# the suite again under sanitizers and a short fuzzing pass (docs/robustness.md). Each stage
# prints its wall time (CI has 90 minutes; on a 2-core machine shared with other builds the
# whole script took 39 minutes from scratch, docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."

stage() {
  local name=$1 start=$SECONDS
  shift
  "$@"
  echo "test.sh: $name took $((SECONDS - start)) s"
}

scripts/install-deps.sh
stage "format check" scripts/format.sh
stage "commit subjects" scripts/check-commits.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRTT_WITH_PYTHON=ON
stage "release build" cmake --build build -j"$(nproc)"
stage "release ctest" ctest --test-dir build --output-on-failure -j"$(nproc)"
# rtt as a package: installed into a temporary prefix, used by examples/ from a clean folder.
stage "install and examples" scripts/examples.sh
stage "python tests" scripts/python-tests.sh
stage "pip install" scripts/pip-test.sh
stage "mpi tests" scripts/mpi-tests.sh

# The same suite under AddressSanitizer + UndefinedBehaviorSanitizer (gcc, -O1 -g, debug checks
# on, Embree kept: its uninstrumented library runs fine under ASan). Tests that cannot work
# instrumented skip themselves (ulimit -v with ASan's reserved address space). This build has
# no MPI: the whole suite also passes without it (the MPI tests above use the release build).
# Its kernels are the SSE4.2 baseline and AVX-512 (the widest, run by default where the CPU has
# it); the per-ISA reruns (label "isa") are the release run's.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DRTT_SANITIZE=ON \
  -DRTT_WITH_MPI=OFF -DRTT_ISA_VARIANTS=avx512
stage "asan build" cmake --build build-asan -j"$(nproc)" --target rtt_tests rtt
stage "asan ctest" env LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp" \
  UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -LE isa

# A short pass of every fuzz target (clang + libFuzzer, ASan + UBSan, in build-fuzz).
stage "fuzz build and run" env FUZZ_SECONDS="${FUZZ_SECONDS:-20}" scripts/fuzz.sh
