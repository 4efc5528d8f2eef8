#!/usr/bin/env bash
# Installs geartopo from the build tree into a scratch prefix, then configures, builds and runs a user's project
# (tests/install/consumer) that finds it with find_package(geartopo), and, when the build has the Python module,
# imports the installed module and simulates with it. Usage: consumer_test.sh BUILD_DIR SOURCE_DIR
#
# The installed libraries are static, so the consumer must be compiled and linked with the flags the libraries were
# built with: under scripts/sanitize.sh they carry ASan/UBSan instrumentation, and a consumer linked without
# -fsanitize fails with undefined __asan_*/__ubsan_* references. Those flags are read from the build's CMakeCache.txt.
# Each step's output is kept and printed when the step fails (ctest shows it with --output-on-failure).
set -euo pipefail
build=$1 source=$(cd "$2" && pwd) # absolute: the Python check runs from the scratch folder
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cache_value() {  # the value of a CMakeCache.txt entry, empty when absent
  sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt" | head -n 1
}
cxx_flags=$(cache_value CMAKE_CXX_FLAGS)
exe_linker_flags=$(cache_value CMAKE_EXE_LINKER_FLAGS)

step() {  # step NAME COMMAND...: runs the command, printing its output only if it fails
  local log="$work/$1.log"
  if ! "${@:2}" >"$log" 2>&1; then
    echo "consumer_test: step '$1' failed: ${*:2}" >&2
    cat "$log" >&2
    exit 1
  fi
}
step install cmake --install "$build" --prefix "$work/prefix"
step configure cmake -S "$source/tests/install/consumer" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="$exe_linker_flags"
step build cmake --build "$work/build"
"$work/build/consumer"

# The Python module beside the C++ package (docs/python.md): imported from the prefix, not from the build tree.
# Only when this build has the module: GEARTOPO_PYTHON_INSTALL_DIR stays in the cache of a tree reconfigured with
# -DGEARTOPO_PYTHON=OFF (scripts/sanitize.sh after a --python run), where nothing is installed there.
python_dir=$(cache_value GEARTOPO_PYTHON_INSTALL_DIR)
if [ -n "$python_dir" ] && [ "$(cache_value GEARTOPO_PYTHON)" = ON ] && compgen -G "$build/python/geartopo*.so" >/dev/null; then
  python=$(cache_value Python3_EXECUTABLE)
  (cd "$work" && PYTHONPATH="$work/prefix/$python_dir" "$python" -c "
import sys, geartopo
assert geartopo.__file__.startswith('$work/prefix/'), geartopo.__file__
topo = geartopo.simulate(geartopo.load_scene('$source/scenes/skmc1200w-mn14-z35.yaml'), teeth=[1], method='linear')
assert len(topo['deviation_um']) == 2 * 7 * 9
print('installed Python module:', geartopo.__file__)
")
else
  echo "consumer_test: this build has no Python module; its installed import not checked"
fi
