#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer (and LeakSanitizer) build of the library, the CLI
# and the whole test suite in its own folder, then ctest there. Any sanitizer report fails its test.
#   bash scripts/sanitize.sh                     # everything
#   bash scripts/sanitize.sh -R 'Obj|Ply'        # extra arguments go to ctest
#   SDMESH_SANITIZE_TESTS="test_io test_bad_input" bash scripts/sanitize.sh
#                                                # a subset (CI): build and run just these suites
# SDMESH_SANITIZE_DIR (default build-asan) and JOBS (default: all cores) adjust it.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${SDMESH_SANITIZE_DIR:-build-asan}
jobs=${JOBS:-$(nproc)}
# The Python module is left out: an extension linking ASan needs LD_PRELOAD into the interpreter.
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDMESH_SANITIZE=ON \
    -DSDMESH_BUILD_EXPERIMENTS=OFF -DSDMESH_BUILD_PYTHON=OFF >/dev/null
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
if [[ -n "${SDMESH_SANITIZE_TESTS:-}" ]]; then
    # shellcheck disable=SC2086  # a list of target names
    cmake --build "$dir" --parallel "$jobs" --target sdmesh_cli $SDMESH_SANITIZE_TESTS
    for suite in $SDMESH_SANITIZE_TESTS; do "$dir/tests/$suite" --gtest_brief=1; done
else
    cmake --build "$dir" --parallel "$jobs"
    ctest --test-dir "$dir" --output-on-failure --parallel "$jobs" "$@"
fi
