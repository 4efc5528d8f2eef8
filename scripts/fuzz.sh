#!/usr/bin/env bash
# Fuzzes the five strict readers with libFuzzer (clang-14 from Debian, ASan + UBSan) for SECONDS each, seeded with the
# broken-input corpus (tests/robustness/corpus) and the shipped scenes and error tables. Optional: not part of either
# README command or CI. Anything libFuzzer finds is left in build-fuzz/findings/<reader>/ — turn it into a corpus file
# (tests/robustness/corpus/make_corpus.py) and fix the reader. Results of the last run: docs/performance.md, "Fuzzing".
#
#   bash scripts/fuzz.sh               # 60 s per reader
#   SECONDS_EACH=600 bash scripts/fuzz.sh
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${SECONDS_EACH:-60}
build_dir=${BUILD_DIR:-build-fuzz}

# libclang-rt-14-dev holds libFuzzer and the sanitizer runtimes; clang-14 only recommends it.
bash scripts/install-deps.sh clang-14 libclang-rt-14-dev

cmake -S . -B "$build_dir" -G Ninja -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEARTOPO_FUZZ=ON -DGEARTOPO_BUILD_BENCH=OFF -DGEARTOPO_BUILD_TESTS=ON \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined" >/dev/null
cmake --build "$build_dir" --target fuzz_scene fuzz_error_table fuzz_topology fuzz_point_cloud fuzz_klingelnberg

declare -A corpus=([scene]=scenes [error_table]=error_tables [topology]=topology [point_cloud]=point_clouds [klingelnberg]=exports)
declare -A shipped=([scene]="scenes/*.yaml" [error_table]="scenes/machine/*.csv" [topology]="" [point_cloud]="" [klingelnberg]="tests/measurement/data/*.mka")
status=0
for reader in scene error_table topology point_cloud klingelnberg; do
  work="$build_dir/corpus/$reader" findings="$build_dir/findings/$reader"
  rm -rf "$work" "$findings" && mkdir -p "$work" "$findings"
  # Every file of the reader's corpus folder, its subfolders' too (exports/reference/good.mka), flat: libFuzzer reads
  # a corpus folder's files, not its subfolders.
  if [ -d tests/robustness/corpus/"${corpus[$reader]}" ]; then
    find tests/robustness/corpus/"${corpus[$reader]}" -type f -exec cp {} "$work"/ \;
  fi
  rm -f "$work"/expected.tsv
  for f in ${shipped[$reader]}; do cp "$f" "$work"/; done
  echo "fuzz_$reader: $seconds s"
  # Killed after SECONDS + 120 s: on an out-of-memory input libFuzzer's report (its heap profile, taken under
  # StopTheWorld) hung here for good (2026-11-28) and wrote no input; `gdb -p PID -batch -ex "thread 1" -ex "frame
  # function LLVMFuzzerTestOneInput" -ex "p text"` printed it while the fuzzer still ran.
  if ! timeout --signal=KILL $((seconds + 120)) "$build_dir/bin/fuzz_$reader" -max_total_time="$seconds" -timeout=10 \
       -rss_limit_mb=2048 -artifact_prefix="$findings/" "$work" >"$build_dir/fuzz_$reader.log" 2>&1; then
    status=1
    echo "fuzz_$reader: FOUND something — $findings, log $build_dir/fuzz_$reader.log"
  fi
  grep -E "^Done [0-9]+ runs" "$build_dir/fuzz_$reader.log" || tail -5 "$build_dir/fuzz_$reader.log"
done
exit "$status"
