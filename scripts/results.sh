#!/usr/bin/env bash
# Regenerates docs/RESULTS.md: builds rtt, runs every experiment of `rtt bench` (the paper's
# Table 1, Figures 5, 7, 8, the 2048x1536 6x6 point, Embree side by side) and writes the
# Markdown, the JSON with every figure, the SVG plots and the Figure 5 images under docs/results/.
#
#   bash scripts/results.sh            # full mode, 10-15 minutes on a 2-core machine
#   bash scripts/results.sh --quick    # smoke run, 1-2 minutes (numbers are not the paper's)
#   bash scripts/results.sh --long     # every experiment at the paper's exact sizes, ~30 minutes
#
# Extra arguments go to `rtt bench all` (e.g. --threads 2, --reps 5, --scenes room,office).
# Run it on a machine as idle as you can: the load average is recorded in the results.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${RTT_BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j"$(nproc)" --target rtt
mkdir -p docs/results
"$build/rtt" bench all --out-dir docs/results --json docs/results/bench.json \
    --markdown docs/RESULTS.md "$@"
