#!/usr/bin/env bash
# geartopo-mpi under mpirun (docs/monte-carlo.md, "MPI"): ctest runs this script with a case name.
#   same-files: `mpirun -n 2` and `-n 3` (7 samples: 3 + 4 and 2 + 2 + 3) of geartopo-mpi write the very bytes
#               of one plain `geartopo compensate` run with the same seed and samples — every file of the output folder
#               and the text on stdout. The truth is the plain run, which knows nothing of MPI.
#   adaptive:   the adaptive stop (--adaptive-tolerance-um) under `mpirun -n 2` and `-n 3` (each batch of 100 split
#               50 + 50 and 33 + 33 + 34, rank 0 deciding): the very bytes of the plain adaptive run, once stopping
#               because stable (after 2 of at most 3 batches) and once at the --max-samples limit (3 batches).
#   bad-input:  a bad scene, bad flags, a refused work estimate, a rank alone with a bad scene or another seed: a
#               non-zero exit of mpirun, the message once, no output folder, no hang (ctest TIMEOUT); for a fixed
#               number of samples and inside an adaptive run's batches.
# Usage: mpi_driver_test.sh CASE GEARTOPO GEARTOPO_MPI MPIEXEC
set -euo pipefail
case_name=$1 geartopo=$2 geartopo_mpi=$3 mpiexec=$4

# OpenMPI in a container as root: --allow-run-as-root (and its two variables), --oversubscribe for more ranks than
# cores, shared-memory transport without the single-copy mechanism that needs ptrace rights (CMA) a container lacks.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
mpirun_local() { "$mpiexec" --oversubscribe --bind-to none "$@"; }

dir=$(mktemp -d "${TMPDIR:-/tmp}/geartopo_mpi_test.XXXXXX")
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# The small helical gear of tests/pipeline/test_monte_carlo.cpp (mc_scene_text with kMapErrors): seconds per run.
cat >"$dir/scene.yaml" <<'YAML'
gear:
  normal_module_mm: 4
  teeth: 20
  normal_pressure_angle_deg: 20
  helix_angle_deg: 20
  profile_shift: 0
  face_width_mm: 30
machine:
  datum_face_z_mm: 300
  constants: {S_xz_urad: 30, E_XOC_um: 5, delta_xx_um: 4, epsilon_zx_urad: 40, E_YOC_um: 6}
wheel: {outer_diameter_mm: 300}
measurement: {rows: 5, cols: 5, profile_points: 15, helix_points: 15}
YAML
# The same scene with a negative tooth count on line 3.
sed 's/teeth: 20/teeth: -20/' "$dir/scene.yaml" >"$dir/bad.yaml"
common=(--samples 7 --seed 5 --step 5)

# run NAME CMD…: stdout in NAME.out, stderr in NAME.err, exit code in $status.
run() {
  local name=$1
  shift
  status=0
  "$@" >"$dir/$name.out" 2>"$dir/$name.err" || status=$?
}
# once NAME TEXT: TEXT is on exactly one line of NAME's stderr.
once() {
  local n
  n=$(grep -c -F -- "$2" "$dir/$1.err" || true)
  [ "$n" = 1 ] || fail "$1: '$2' on $n lines of stderr, not once:$(printf '\n'; cat "$dir/$1.err")"
}
# refused NAME TEXT CMD…: mpirun exits non-zero, TEXT once on stderr, no output folder.
refused() {
  local name=$1 text=$2
  shift 2
  run "$name" "$@"
  [ "$status" != 0 ] || fail "$name: exit 0"
  once "$name" "$text"
  [ ! -e "$dir/$name" ] || fail "$name: wrote $dir/$name"
  echo "$name: exit $status"
}

# same_as_plain TAG FLAGS…: geartopo compensate with FLAGS, then geartopo-mpi under mpirun -n 2 and -n 3: every file
# of the output folder and stdout (but for the folder's name) identical to the plain run's.
same_as_plain() {
  local tag=$1
  shift
  run "$tag-plain" "$geartopo" compensate "$dir/scene.yaml" --out "$dir/$tag-plain" "$@"
  [ "$status" = 0 ] || { cat "$dir/$tag-plain.err"; fail "$tag: plain run: exit $status"; return; }
  [ -s "$dir/$tag-plain/prediction.json" ] || fail "$tag: the plain run wrote no prediction.json"
  for n in 2 3; do
    run "$tag-mpi$n" mpirun_local -n "$n" "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/$tag-mpi$n" "$@"
    [ "$status" = 0 ] || { cat "$dir/$tag-mpi$n.err"; fail "$tag: mpirun -n $n: exit $status"; continue; }
    before=$failures
    diff -r "$dir/$tag-plain" "$dir/$tag-mpi$n" || fail "$tag: mpirun -n $n: the output folder differs from the plain run's"
    # stdout too, but for the folder's name in the "wrote …" line
    diff <(sed "s|$dir/$tag-plain|OUT|g" "$dir/$tag-plain.out") <(sed "s|$dir/$tag-mpi$n|OUT|g" "$dir/$tag-mpi$n.out") ||
      fail "$tag: mpirun -n $n: stdout differs from the plain run's"
    [ "$failures" != "$before" ] ||
      echo "$tag: mpirun -n $n: $(find "$dir/$tag-mpi$n" -type f | wc -l) files and stdout identical to the plain run's"
  done
}
# samples_of DIR: the sample count prediction.json reports.
samples_of() { sed -n 's/^  "samples": \([0-9]*\),$/\1/p' "$1/prediction.json"; }

case $case_name in
same-files)
  same_as_plain fixed "${common[@]}"
  ;;
adaptive)
  # Stable after 2 batches (a tolerance every quantity meets), with room for 3.
  same_as_plain stable --seed 5 --step 5 --adaptive-tolerance-um 100 --max-samples 300
  [ "$(samples_of "$dir/stable-plain")" = 200 ] || fail "stable: the plain run stopped at $(samples_of "$dir/stable-plain") samples, not 200"
  # A tolerance no run meets: the limit, 3 batches (two decisions to go on).
  same_as_plain limit --seed 5 --step 5 --adaptive-tolerance-um 0.000001 --max-samples 300 --probe-noise-um 0.1
  [ "$(samples_of "$dir/limit-plain")" = 300 ] || fail "limit: the plain run stopped at $(samples_of "$dir/limit-plain") samples, not 300"
  ;;
bad-input)
  # Every rank fails the same way: rank 0 says it.
  refused bad-scene "bad.yaml:3" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/bad.yaml" --out "$dir/bad-scene" "${common[@]}"
  refused missing-scene "nothing.yaml" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/nothing.yaml" --out "$dir/missing-scene" "${common[@]}"
  refused shard-flag "--shard" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/shard-flag" "${common[@]}" --shard 1/2
  refused unknown-flag "--no-such-flag" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/unknown-flag" --no-such-flag
  refused too-few-samples "every rank needs a sample" mpirun_local -n 3 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/too-few-samples" --samples 2
  refused zero-samples "0 samples over 2 MPI ranks" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/zero-samples" --samples 0
  # Refused while the samples run (the work estimate, inside the scatter): every rank leaves through the agreement.
  refused time-limit "--max-time-s" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/time-limit" "${common[@]}" --max-time-s 0.001
  # One rank alone fails (MPMD: each rank its own words): that rank says it, the others wait for nobody.
  refused rank1-bad-scene "rank 1 of 2: geartopo: error: $dir/bad.yaml:3" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/rank1-bad-scene" "${common[@]}" : \
    -n 1 "$geartopo_mpi" compensate "$dir/bad.yaml" --out "$dir/rank1-bad-scene" "${common[@]}"
  refused rank0-bad-scene "geartopo: error: $dir/bad.yaml:3" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/bad.yaml" --out "$dir/rank0-bad-scene" "${common[@]}" : \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/rank0-bad-scene" "${common[@]}"
  refused rank1-bad-flag "--no-such-flag" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/rank1-bad-flag" "${common[@]}" : \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/rank1-bad-flag" "${common[@]}" --no-such-flag
  # Ranks that ran another seed: rank 0 refuses to merge what is not one run.
  refused other-seed "seed" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/other-seed" "${common[@]}" : \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/other-seed" --samples 7 --seed 6 --step 5
  # The same inside an adaptive run: a refused work estimate in the first batch, a rank with another seed (rank 0
  # refuses to merge the batch and tells the others with its stop), one rank alone with a bad scene.
  adaptive=(--step 5 --adaptive-tolerance-um 0.5 --max-samples 300)
  refused adaptive-time-limit "--max-time-s" mpirun_local -n 2 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/adaptive-time-limit" "${adaptive[@]}" --seed 5 --max-time-s 0.001
  refused adaptive-other-seed "seed" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/adaptive-other-seed" "${adaptive[@]}" --seed 5 : \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/adaptive-other-seed" "${adaptive[@]}" --seed 6
  refused adaptive-rank1-bad-scene "rank 1 of 2: geartopo: error: $dir/bad.yaml:3" mpirun_local \
    -n 1 "$geartopo_mpi" compensate "$dir/scene.yaml" --out "$dir/adaptive-rank1-bad-scene" "${adaptive[@]}" --seed 5 : \
    -n 1 "$geartopo_mpi" compensate "$dir/bad.yaml" --out "$dir/adaptive-rank1-bad-scene" "${adaptive[@]}" --seed 5
  ;;
*)
  echo "unknown case $case_name"
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "$case_name: passed"
