#!/usr/bin/env bash
# Installs every Debian package geartopo needs to build, test and render (Debian 12 "bookworm").
# Idempotent: packages already installed are skipped, so a second run costs a few dpkg queries.
# Needs root (or sudo) only when something is missing. Extra packages may be given as arguments.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  ccache                 # compiled objects kept across clean builds and clones (scripts/configure.sh)
  libeigen3-dev          # dense linear algebra, transforms
  libboost-dev           # header-only Boost.Math: χ², F and normal quantiles (src/core/statistics.cpp)
  libcgal-dev            # k-d tree neighbour search of scattered residual points (diagnosis)
  libopenmesh-dev        # triangle meshes (PLY/OBJ/STL/OFF)
  libvtk9-dev libegl-dev # off-screen rendering (surfaceless EGL + VTK)
  libpng-dev             # the figures' PNG files (src/render/image.cpp)
  libyaml-cpp-dev        # scene files, with line/column marks for error messages
  libmuparser-dev        # the expressions of a scene's custom_effects (src/effects/custom_effect.cpp)
  libcli11-dev           # command-line parsing
  libfmt-dev             # formatting
  nlohmann-json3-dev     # JSON output
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin # geartopo-mpi, the MPI driver of the Monte Carlo prediction (-DGEARTOPO_MPI=ON)
  chromium               # the report page in a browser: screenshot and PDF (scripts/screenshot-report.sh, test_report)
  poppler-utils          # pdftoppm/pdfinfo: the printed report read page by page (test_report, docs/rendering.md)
  python3-dev pybind11-dev python3-numpy # the Python module geartopo (python/, docs/python.md)
  python3-pytest python3-matplotlib      # its tests (ctest runs pytest) and the example's figure (examples/python/)
)

packages+=("$@") # extra packages a caller needs (scripts/fuzz.sh: clang-14 libclang-rt-14-dev)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
