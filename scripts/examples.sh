#!/usr/bin/env bash
# Installs the release build (build/) into a temporary prefix, then builds and runs examples/
# against that install from a clean folder, as a project outside rtt would. Also checks that
# rtt::core's exported targets ask for none of assimp, nlohmann-json, libpng and CLI11, and
# that the pkg-config files resolve.
set -euo pipefail
cd "$(dirname "$0")/.."

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install build --prefix "$prefix" >/dev/null
core_targets=$(find "$prefix" -name 'rtt-core-targets*.cmake')
if grep -Eq 'assimp|nlohmann|PNG|CLI11' $core_targets; then
  echo "examples: rtt::core's exported targets depend on a file-format or CLI library" >&2
  exit 1
fi
PKG_CONFIG_PATH=$(dirname "$(find "$prefix" -name rtt.pc)") pkg-config --exists --print-errors rtt-core rtt

cmake -S examples -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/build" -j"$(nproc)"
(cd "$work" && ./build/trace_tile && ./build/compare_tracers 4 && ./build/render_image room room.png)
test -s "$work/room.png"
echo "examples: built and ran against the install in $prefix"
