#!/usr/bin/env bash
# Installs the release build (build/) into a temporary prefix and runs the Python suite
# (python/tests) with Debian's interpreter against that installed module, from another folder,
# with the installed `rtt` program for the command-line comparisons.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install build --prefix "$work/prefix" >/dev/null
site=$(find "$work/prefix" -name __init__.py -path '*/rtt/*' -printf '%h\n' | head -1)
test -n "$site" || { echo "python-tests: the build has no Python module (RTT_WITH_PYTHON)" >&2; exit 1; }
cd "$work"
PYTHONPATH=$(dirname "$site") RTT_CLI="$work/prefix/bin/rtt" \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider "$repo/python/tests" "$@"
