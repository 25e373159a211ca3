#!/usr/bin/env bash
# emulated_cpus.sh RTT: the one binary on older CPUs. Runs the program under QEMU's user-mode
# emulation of an SSE4.2 CPU (Nehalem) and an AVX2 CPU (Haswell): each must pick its own kernels
# (rtt --version) and write hit and shadow buffers byte-identical to this machine's, for RTT and
# packets, K = 1 and 2, a built-in scene and a mesh. Exit 77 (ctest: skipped) without
# qemu-x86_64 (Debian: qemu-user).
set -euo pipefail
rtt=$1
data=$(cd "$(dirname "$0")/data" && pwd)
command -v qemu-x86_64 >/dev/null || { echo "no qemu-x86_64: skipped"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

declare -A expect=([Nehalem]=sse4.2 [Haswell]=avx2)
for cpu in Nehalem Haswell; do
  # TCG warns about CPU features it cannot emulate (TSX, ...): not ours.
  version=$(qemu-x86_64 -cpu "$cpu" "$rtt" --version 2>/dev/null) || version="stopped, status $?"
  if [[ $version != *"(${expect[$cpu]} kernels;"* ]]; then
    echo "FAIL: on $cpu expected ${expect[$cpu]} kernels: $version"
    exit 1
  fi
  echo "$cpu: $version"
done

fails=0
for input in "--scene room" "--mesh $data/render_mesh.obj"; do
  for tracer in rtt packet; do
    for aa in 1 2; do
      args=($input --size 48x32 --aa "$aa" --tracer "$tracer" --threads 2 -q)
      "$rtt" render "${args[@]}" --hits "$work/h.host" --shadows "$work/s.host" -o "$work/i.png"
      for cpu in Nehalem Haswell; do
        qemu-x86_64 -cpu "$cpu" "$rtt" render "${args[@]}" --hits "$work/h.$cpu" \
          --shadows "$work/s.$cpu" -o "$work/i.png" 2>/dev/null
        if ! cmp -s "$work/h.host" "$work/h.$cpu" || ! cmp -s "$work/s.host" "$work/s.$cpu"; then
          echo "FAIL: $cpu differs from this machine: ${args[*]}"
          fails=$((fails + 1))
        fi
      done
    done
  done
done
[ "$fails" -eq 0 ] || exit 1
echo "emulated CPUs: the same hit and shadow buffers as this machine's"
