#!/usr/bin/env bash
# Builds rtt's libFuzzer targets with clang, AddressSanitizer and UndefinedBehaviorSanitizer in
# build-fuzz, then runs each for a bounded time over its seed corpus (fuzz/corpus/<target>/).
#
#   FUZZ_SECONDS   seconds per target (default 30)
#   FUZZ_TARGETS   targets to run (default: all four)
#   FUZZ_BUILD_DIR build folder (default build-fuzz)
#
# New interesting inputs go to <build>/corpus/<target>/ (the repository's seeds stay as they
# are); a crash, leak, hang (> 10 s per input), sanitizer report or over-allocation (> 2 GB)
# is saved in <build>/artifacts/<target>/ and makes the script fail after all targets ran.
# Reproduce one with: <build>/fuzz/<target> <artifact>
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${FUZZ_SECONDS:-30}
build=${FUZZ_BUILD_DIR:-build-fuzz}
read -r -a targets <<<"${FUZZ_TARGETS:-fuzz_scene_json fuzz_cli_values fuzz_buffers fuzz_mesh}"

command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (scripts/install-deps.sh)" >&2; exit 1; }
# -O1 -g: readable sanitizer reports at a useful speed. Embree is left out: its tracers are
# compared with nobody, and its thread pool slows every input down. The readers under test run
# no SIMD kernel: the SSE4.2 baseline alone (no per-ISA variants) builds faster.
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DRTT_FUZZ=ON -DRTT_SANITIZE=ON -DRTT_WITH_EMBREE=OFF \
  -DBUILD_TESTING=OFF -DRTT_ISA_VARIANTS="" >/dev/null
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"

# Leaks inside assimp (third party) on malformed files are not ours to fix: scripts/lsan.supp.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

failed=()
summary=()
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  artifacts="$build/artifacts/$t"
  mkdir -p "$work" "$artifacts"
  dict=()
  [ -f "fuzz/$t.dict" ] && dict=(-dict="fuzz/$t.dict")
  echo "fuzz: $t for ${seconds} s"
  log="$build/$t.log"
  start=$(date +%s)
  status=0
  # The seeds are regression inputs: a checkout without them must not pass quietly.
  if [ ! -d "fuzz/corpus/$t" ]; then
    failed+=("$t")
    summary+=("$t: FAILED, seed corpus fuzz/corpus/$t missing (ignored by git?)")
    continue
  fi
  # The importer child gets 4 s of CPU: the fuzz build has AddressSanitizer, so no memory cap
  # (scene/assimp_sandbox.cpp), and libFuzzer gives an input 10 s.
  RTT_IMPORT_CPU_SECONDS=4 "$build/fuzz/$t" "$work" "fuzz/corpus/$t" "${dict[@]}" -max_total_time="$seconds" \
    -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$artifacts/" -print_final_stats=1 \
    >"$log" 2>&1 || status=$?
  elapsed=$(($(date +%s) - start))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)
  if [ "$status" -ne 0 ]; then
    failed+=("$t")
    summary+=("$t: FAILED after ${elapsed} s (exit $status), log $log, artifacts $artifacts/")
    grep -E 'ERROR|SUMMARY|rtt fuzz|Test unit written' "$log" | head -n 20 >&2 || true
  else
    summary+=("$t: ok, ${elapsed} s, ${runs:-?} inputs, ${cov:-cov: ?}")
  fi
done

printf 'fuzz: %s\n' "${summary[@]}"
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: failures in ${failed[*]}" >&2
  exit 1
fi
