#!/usr/bin/env bash
# The one build both README commands share (scripts/main.sh, scripts/test.sh): the same folder and the same flags, so
# test.sh builds only what main.sh has not (docs/performance.md, "Build"). Release, warnings as errors, the MPI driver;
# ccache when installed (scripts/install-deps.sh installs it), so a clean build or a fresh clone on the same machine
# recompiles nothing that was compiled before.
#   usage: bash scripts/configure.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
flags=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DGEARTOPO_MPI=ON -DGEARTOPO_WERROR=ON)
if command -v ccache >/dev/null 2>&1; then
  # ccache settings that travel with the build folder (any `cmake --build` of it uses them), whatever the user's
  # ccache.conf says: the precompiled headers are cached only with this sloppiness, and base_dir = this clone makes
  # its paths relative, so a clone in another folder finds the same objects.
  flags+=("-DCMAKE_CXX_COMPILER_LAUNCHER=env;CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime;CCACHE_BASEDIR=$PWD;ccache")
else
  flags+=(-DCMAKE_CXX_COMPILER_LAUNCHER=)
fi
cmake -S . -B "$build" "${flags[@]}" >/dev/null
