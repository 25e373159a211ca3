#!/usr/bin/env bash
# `pip install .` as a Python user does it (README, "Python"): a fresh virtual environment that
# sees Debian's numpy, the package built by the project's CMake (setup.py), a wheel beside it;
# then `import rtt` and examples/python/trace_mesh.py from another folder. No package index is
# needed (--no-build-isolation: setuptools comes from Debian).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
"$work/venv/bin/pip" install --no-build-isolation --no-index -q "$repo"
"$work/venv/bin/pip" wheel --no-build-isolation --no-index --no-deps -q -w "$work/wheels" "$repo"
ls "$work"/wheels/rtt-*.whl >/dev/null
cd "$work"
"$work/venv/bin/python" -c 'import rtt, sys; assert rtt.__file__.startswith(sys.prefix), rtt.__file__; print("pip-test: rtt", rtt.__version__, "from", rtt.__file__)'
"$work/venv/bin/python" "$repo/examples/python/trace_mesh.py" "$repo/scenes/example_mesh.obj" --out "$work/mesh.ppm"
test -s "$work/mesh.ppm"
