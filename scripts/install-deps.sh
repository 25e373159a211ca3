#!/usr/bin/env bash
# Installs what rtt needs from Debian's packages. Safe to rerun: installs only what is missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config  # gcc 12 brings libasan8 and libubsan1 (the sanitizer build)
  libassimp-dev libtbb-dev libcli11-dev nlohmann-json3-dev libpng-dev libstb-dev libopenexr-dev
  libgtest-dev libbenchmark-dev libembree-dev
  python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module and its tests
  python3-venv python3-pip python3-setuptools            # `pip install .` (scripts/pip-test.sh)
  libopenmpi-dev openmpi-bin                             # distributed rendering under mpirun
  libglfw3-dev libgl-dev libgl1-mesa-dri  # rtt view: a window (GLFW) drawn with OpenGL (Mesa)
  xvfb xauth xdotool                      # its tests: a headless X server and synthetic input
  clang libclang-rt-14-dev  # scripts/fuzz.sh: libFuzzer and the sanitizer runtimes for clang 14
  llvm                      # llvm-symbolizer: function names and lines in clang's sanitizer reports
  clang-format              # scripts/format.sh: every C++ file follows .clang-format
  qemu-user                 # tests/emulated_cpus.sh: the one binary on SSE4.2 and AVX2 CPUs
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
