#!/usr/bin/env bash
# Installs rtt for this machine: Debian packages, a release build, then `cmake --install` into
# PREFIX (default /usr/local): the `rtt` program, headers, libraries, CMake and pkg-config
# files, and the Python module for Debian's /usr/bin/python3 (import rtt from any folder).
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=${PREFIX:-/usr/local}
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRTT_WITH_PYTHON=ON
cmake --build build -j"$(nproc)"
cmake --install build --prefix "$prefix"
echo "install: rtt $(./build/rtt --version | cut -d' ' -f2) in $prefix; try: /usr/bin/python3 -c 'import rtt; print(rtt.tracer_kinds())'"
