#!/usr/bin/env bash
# run_if_cpu_has.sh ISA COMMAND...: runs the per-ISA kernel tests when this CPU has the ISA,
# else exits 77 (ctest: skipped). The level names are those of src/core/isa.cpp.
set -euo pipefail
isa=$1
shift
case $isa in
  avx2) need="avx2 fma bmi2 movbe" ;;
  avx512) need="avx512f avx512bw avx512dq avx512vl avx512cd" ;;
  *) echo "run_if_cpu_has.sh: unknown ISA $isa" >&2; exit 2 ;;
esac
flags=" $(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2) "
for f in $need; do
  if [[ $flags != *" $f "* ]]; then
    echo "this CPU has no $f: the $isa kernel tests are skipped"
    exit 77
  fi
done
exec "$@"
