#!/usr/bin/env bash
# The README's main command: install what is missing, build, run the default job.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target rtt
./build/rtt "$@"
