#!/usr/bin/env bash
# README command (1): install what is needed, build, and run the main job on the default scene.
# Output goes to ./out (mm, µm, deg as named in each file).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
mkdir -p out
./build/bin/geartopo gear scenes/skmc1200w-mn14-z35.yaml --mesh out/gear.ply
