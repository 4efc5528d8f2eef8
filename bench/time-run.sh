#!/usr/bin/env bash
# The main job's wall time, as a user waits for it: `geartopo run` on the default scene, N times (default 3), each in
# a fresh output folder; prints every run's wall, user and system time, the median wall time, and the machine's
# load (uptime) and core count before and after, since the machine may be shared (docs/performance.md).
# Target (issue 25): median < 3 s wall on the idle 2-core machine. A process-level timing on purpose: a Google
# Benchmark loop in one process would keep the OpenGL context and its compiled shaders warm between iterations.
#   usage: bash bench/time-run.sh [BUILD_DIR (default build)] [N (default 3)] [extra run flags…]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
runs=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
bin="$build/bin/geartopo"
[[ "$bin" = /* ]] || bin="$root/$bin"
[ -x "$bin" ] || { echo "time-run: no $bin (build the geartopo target first)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "time-run: $(nproc) cores; load before: $(uptime | sed 's/.*load average: //')"
walls=()
TIMEFORMAT='%R %U %S' # bash's own `time`: wall, user and system seconds (no /usr/bin/time or bc needed)
for i in $(seq 1 "$runs"); do
  { time "$bin" run "$root/scenes/skmc1200w-mn14-z35.yaml" --out "$out/run$i" --quiet "$@" > /dev/null 2> "$out/err.txt" \
      || { cat "$out/err.txt" >&2; exit 1; }; } 2> "$out/time.txt"
  read -r wall user sys < "$out/time.txt"
  printf "time-run: run %d: %.2f s wall, %.2f s user, %.2f s system\n" "$i" "$wall" "$user" "$sys"
  walls+=("$wall")
done
median=$(printf "%s\n" "${walls[@]}" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}')
printf "time-run: median %.2f s wall over %d runs; load after: %s\n" "$median" "$runs" "$(uptime | sed 's/.*load average: //')"
