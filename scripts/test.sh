#!/usr/bin/env bash
# README command (2): install what is needed, build everything warning-free (-Werror) in the folder main.sh uses (what
# it built is reused), and run every test with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/configure.sh build
cmake --build build
ctest --test-dir build --output-on-failure -j2
