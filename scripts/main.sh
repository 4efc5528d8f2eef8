#!/usr/bin/env bash
# README command (1): install what is needed, build the geartopo program (only it: scripts/test.sh builds the rest in
# the same folder), and run the main job on the default scene: simulate, evaluate (ISO 1328-1), compensate, compare
# with the scene's demo measurement, diagnose, and write the report.
# Output goes to ./out/run (index.html, report.pdf, PNG figures, CSV and JSON files; mm, µm, deg as named in each file).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/configure.sh build
cmake --build build --target geartopo
./build/bin/geartopo run scenes/skmc1200w-mn14-z35.yaml --out out/run
# The page as customers file it: report.pdf (and screenshot.png) via headless Chromium; skipped with a message without it.
bash scripts/screenshot-report.sh out/run/index.html out/run/screenshot.png out/run/report.pdf
