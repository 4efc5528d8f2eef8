#!/usr/bin/env bash
# README command (2): install what is needed, build warning-free (-Werror), and run every test with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEARTOPO_MPI=ON -DGEARTOPO_WERROR=ON >/dev/null
cmake --build build
ctest --test-dir build --output-on-failure -j2
