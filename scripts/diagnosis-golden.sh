#!/usr/bin/env bash
# The golden set of diagnoses (docs/diagnosis.md, "The golden set"): runs the whole test suite (the tutorial's commands
# included: test_tutorial runs them) with GEARTOPO_DIAGNOSIS_DUMP=DIR, so that every diagnose() writes its
# diagnosis.json into DIR, named after the test. Capture before a change to diagnose and after it, then compare:
#   bash scripts/diagnosis-golden.sh /tmp/golden-before      # on the commit before
#   bash scripts/diagnosis-golden.sh /tmp/golden-after       # on the change
#   python3 scripts/compare-diagnoses.py /tmp/golden-before /tmp/golden-after
# Needs a built tree in build/ (scripts/test.sh). Test failures are reported but do not stop the capture.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: diagnosis-golden.sh DIR [ctest args...]}
shift
rm -rf "$dir" && mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
GEARTOPO_DIAGNOSIS_DUMP="$dir" ctest --test-dir build -j2 "$@" | tail -5
echo "$(ls "$dir" | wc -l) diagnoses in $dir"
