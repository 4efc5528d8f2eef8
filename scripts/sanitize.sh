#!/usr/bin/env bash
# CI step: build geartopo with AddressSanitizer + UndefinedBehaviorSanitizer (Debug, -O1) in build-asan/ and run the whole
# ctest suite under them. Any ASan error, leak (LeakSanitizer) or UBSan report fails the step.
#
#   bash scripts/sanitize.sh            # from the repository root or anywhere
#   BUILD_DIR=/tmp/asan JOBS=4 bash scripts/sanitize.sh
#   TIMEOUT_FACTOR=8 bash scripts/sanitize.sh   # the tests' ctest TIMEOUTs × 8 (default × 4) on a loaded machine
#   bash scripts/sanitize.sh --python   # instead: the Python module built in the same tree, python/tests under ASan
#   bash scripts/sanitize.sh --python python/tests/test_strict.py   # only those tests
#
# Duration on an idle 2-core machine: about 50 minutes, 26 of them the tests (docs/performance.md, "Sanitizers").
# Needs the packages of scripts/install-deps.sh (run it first on a fresh machine).
set -euo pipefail
cd "$(dirname "$0")/.."

python=OFF
case "${1:-}" in
  "") ;;
  --python) python=ON; shift ;;
  *) echo "usage: bash scripts/sanitize.sh [--python [pytest files or -k …]]" >&2; exit 2 ;;
esac
# --python's tests: the arguments after it, or every file of python/tests (under ASan the CLI the tests start is
# instrumented too: about 10× slower than Release).
pytest_args=("${@:-python/tests}")

build_dir=${BUILD_DIR:-build-asan}
jobs=${JOBS:-$(nproc)}
# Debug (assertions on, -g) at -O1, the level ASan recommends: at Debug's -O0 the Eigen-heavy diagnosis, compensation
# and report tests made the run take 62 minutes on 2 cores (docs/performance.md); -O1 keeps every check, and with the
# frame pointers kept the stack traces stay readable. OPT=-O0 restores the slow variant.
opt=${OPT:--O1}
flags="-fsanitize=address,undefined -fno-omit-frame-pointer"

# The Python module is built only with --python: an instrumented extension loads into Debian's uninstrumented
# python3 only with libasan preloaded (LD_PRELOAD), and the C++ it calls is what the C++ tests check.
start=$(date +%s)
cmake -S . -B "$build_dir" -G Ninja -DGEARTOPO_PYTHON=$python \
  -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS="$flags $opt" -DCMAKE_C_FLAGS="$flags $opt" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  -DCMAKE_MODULE_LINKER_FLAGS="$flags" \
  -DGEARTOPO_BUILD_TESTS=ON -DGEARTOPO_BUILD_BENCH=OFF -DGEARTOPO_TEST_TIMEOUT_FACTOR=${TIMEOUT_FACTOR:-4} >/dev/null
if [ "$python" = ON ]; then
  # The module and the CLI its tests compare it with; python3 is the interpreter CMake chose (Debian's, with pytest).
  cmake --build "$build_dir" -j "$jobs" --target geartopo_python geartopo
  built=$(date +%s)
  interpreter=$(sed -n 's/^Python3_EXECUTABLE:FILEPATH=//p' "$build_dir/CMakeCache.txt")
  # libasan first in the process (the interpreter is not instrumented); the module's libubsan loads as its dependency.
  # libstdc++ preloaded beside it: python3 does not link it, so without it ASan's __cxa_throw interceptor finds no real
  # __cxa_throw when the module's first exception is thrown and aborts ("CHECK failed: asan_interceptors.cpp:320",
  # google/sanitizers#934). --capture=sys: pytest leaves file descriptor 2 alone, so a report reaches the log.
  # detect_leaks=0: CPython does not free all its own memory at exit, and LeakSanitizer fails the interpreter for it
  # (`python3 -c "import numpy, pytest"` alone: 265 blocks, 260 557 bytes, exit 1); the C++ behind the module is
  # leak-checked by the C++ suite, which calls the same library functions. Overflows, use-after-free and UBSan reports
  # stay fatal (exit 1): checked with a probe module that overflows a vector and shifts an int by 40.
  status=0
  compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
  LD_PRELOAD="$("$compiler" -print-file-name=libasan.so) $("$compiler" -print-file-name=libstdc++.so)" \
    ASAN_OPTIONS=detect_leaks=0:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1 \
    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    PYTHONPATH="$PWD/$build_dir/python" GEARTOPO_CLI="$PWD/$build_dir/bin/geartopo" MPLBACKEND=Agg \
    "$interpreter" -m pytest -q -p no:cacheprovider --capture=sys "${pytest_args[@]}" || status=$?
  end=$(date +%s)
  echo "sanitize --python: build $((built - start)) s, tests $((end - built)) s, total $((end - start)) s; pytest exit $status"
  exit "$status"
fi
cmake --build "$build_dir" -j "$jobs"
built=$(date +%s)

# detect_leaks: LeakSanitizer works on this machine (Debian 12, x86-64); it must be off under ptrace (gdb, strace).
# halt_on_error: the first UBSan report aborts the test, so ctest marks it failed (UBSan reports are otherwise only
# printed). abort_on_error=0 keeps ASan's exit code (1) instead of a core dump.
# intercept_tls_get_addr=0: GCC 12's runtime (as LLVM's up to 16) takes a dynamic TLS block whose address is 16 bytes
# past a page boundary for glibc 2.19's layout and records the two words before it as the block; with glibc 2.36 that is
# garbage ("DTLS 11 at 0x1107-0x1800002209"), and LeakSanitizer's exit check crashed reading it ("Tracer caught signal
# 11", google/sanitizers#1322) — by chance of where malloc put a block: RenderErrors.UnwritableOutputIsARuntimeError,
# a shared library's thread_local; under ctest 3 runs of 3 crashed, with the option 15 of 15 passed. Off, dynamic TLS
# is not a root of its own; no test run with the option reported a leak.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:intercept_tls_get_addr=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
status=0
# --timeout: tests without their own TIMEOUT (the GoogleTest cases); those with one have it × TIMEOUT_FACTOR.
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" --timeout 1500 || status=$?
end=$(date +%s)

echo "sanitize: build $((built - start)) s, tests $((end - built)) s, total $((end - start)) s; ctest exit $status"
exit "$status"
