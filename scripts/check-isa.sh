#!/usr/bin/env bash
# check-isa.sh [BINARY...]: fails when code outside the per-ISA kernel namespaces (isa_avx2,
# isa_avx512; src/simd/isa.h) uses an AVX instruction. Such code runs on every x86-64 CPU, so
# one AVX instruction there (an inline function or template the linker took from a kernel's
# copy) stops the program with an illegal instruction on a CPU without AVX.
# Default: build/rtt. A ctest (tests/CMakeLists.txt) runs it on the built program.
set -euo pipefail
cd "$(dirname "$0")/.."
binaries=("$@")
[ ${#binaries[@]} -gt 0 ] || binaries=(build/rtt)
status=0
for bin in "${binaries[@]}"; do
  # objdump -d -C: "<demangled name>:" heads each function; VEX/EVEX mnemonics start with v
  # (vaddps, vmovdqu, vzeroupper, ...); the few legacy ones that do (verr, verw) never occur.
  bad=$(objdump -d -C --no-show-raw-insn "$bin" | awk '
    /^[0-9a-f]+ <.*>:$/ { fn = $0; exempt = (fn ~ /isa_avx2|isa_avx512/); next }
    !exempt && $2 ~ /^v[a-z]/ && !($2 in seen_fn_op) { if (!(fn in seen)) { seen[fn] = 1; print fn ": " $2 } }
  ')
  if [ -n "$bad" ]; then
    echo "check-isa.sh: $bin: AVX instructions outside the kernel namespaces:" >&2
    echo "$bad" | head -40 >&2
    status=1
  else
    echo "check-isa.sh: $bin: no AVX instruction outside isa_avx2/isa_avx512"
  fi
done
exit $status
