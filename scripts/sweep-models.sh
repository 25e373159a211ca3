#!/usr/bin/env bash
# Opens every model of a folder as a new user would: `rtt render --mesh FILE` with the rtt and
# the ray tracer, and sorts the files into rendered (hit buffers equal), refused (exit 1 with a
# message), different (hit buffers differ), crashed (a signal) and hung (60 s).
# Usage: scripts/sweep-models.sh [RTT] [DIR] [OUT_DIR]
#   RTT      the program (default build/rtt)
#   DIR      the models (default /usr/share/assimp/models: Debian's assimp-testmodels)
#   OUT_DIR  where results.tsv (file, outcome, message) goes (default a temporary folder)
# Files whose extension names no model (textures, buffers, shaders, material libraries) are
# skipped. Prints the counts per outcome. docs/robustness.md quotes the last sweep.
set -u
rtt=$(realpath "${1:-build/rtt}")
dir=${2:-/usr/share/assimp/models}
out=${3:-$(mktemp -d)}
mkdir -p "$out"
skip='png|jpg|jpeg|bmp|tga|dds|gif|tif|tiff|bin|txt|md|mtl|material|glsl|vert|frag|xml|h|uc|gz|py|skin|shader|sib|max'
results="$out/results.tsv"
: >"$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

one() {
  local file=$1 n=$2 outcome message rc
  local a="$work/$n.a.rtth" b="$work/$n.b.rtth"
  timeout 60 "$rtt" render --mesh "$file" --size 32x24 -q --tracer rtt --hits "$a" \
    -o "$work/$n.png" 2>"$work/$n.err" >/dev/null
  rc=$?
  message=$(grep -m1 -v '^rtt: warning' "$work/$n.err" | tr '\t' ' ')
  if [ "$rc" -eq 124 ]; then outcome=hung
  elif [ "$rc" -gt 128 ]; then outcome=crashed
  elif [ "$rc" -ne 0 ]; then outcome=refused
  else
    timeout 60 "$rtt" render --mesh "$file" --size 32x24 -q --tracer ray --hits "$b" \
      -o "$work/$n.b.png" 2>/dev/null >/dev/null
    if cmp -s "$a" "$b"; then outcome=rendered; message=""; else outcome=different; fi
  fi
  rm -f "$a" "$b" "$work/$n.png" "$work/$n.b.png" "$work/$n.err"
  printf '%s\t%s\t%s\n' "$file" "$outcome" "$message"
}
export -f one
export rtt work

find "$dir" -type f | grep -Eiv "\.($skip)$" | sort | awk '{print NR "\t" $0}' |
  while IFS=$'\t' read -r n file; do printf '%s\0%s\0' "$file" "$n"; done |
  xargs -0 -n 2 -P 2 bash -c 'one "$0" "$1"' >>"$results"

sort -o "$results" "$results"
echo "sweep of $dir: $(wc -l <"$results") files ($results)"
cut -f2 "$results" | sort | uniq -c | sort -rn
