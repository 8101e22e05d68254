#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz and fuzzes them one after the
# other, on a corpus that starts from the seeds tests/fuzz/make_seeds.cpp writes.
#   bash scripts/fuzz.sh                 # CI: 45 s per target (under 2 minutes with the build cached)
#   bash scripts/fuzz.sh --long [SECS]   # developers: SECS per target (default 1800), corpus kept
# A crash, leak, sanitizer report or timeout stops the run with exit 1; the input is saved as
# build-fuzz/artifacts/<kind>-<hash> (reproduce: build-fuzz/tests/fuzz/fuzz_<target> FILE) and
# belongs in a regression test, or in tests/fuzz/regressions/<target>/, which every run replays
# first. Environment: SDMESH_FUZZ_DIR (default build-fuzz), JOBS.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=45
if [[ "${1:-}" == "--long" ]]; then seconds=${2:-1800}; fi
dir=${SDMESH_FUZZ_DIR:-build-fuzz}
CC=${CC:-clang} CXX=${CXX:-clang++} cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSDMESH_BUILD_FUZZERS=ON -DSDMESH_BUILD_TESTS=OFF -DSDMESH_BUILD_EXPERIMENTS=OFF \
    -DSDMESH_BUILD_PYTHON=OFF >/dev/null
cmake --build "$dir" --target fuzz_read_mesh fuzz_pipeline fuzz_make_seeds --parallel "${JOBS:-$(nproc)}"
"$dir/tests/fuzz/fuzz_make_seeds" "$dir/seeds" >/dev/null
mkdir -p "$dir/artifacts" "$dir/logs"
export OMP_NUM_THREADS=1  # one core per fuzzer; the meshes are small
for target in read_mesh pipeline; do
    mkdir -p "$dir/corpus/$target"
    inputs=("$dir/corpus/$target" "$dir/seeds")
    if [[ -d "tests/fuzz/regressions/$target" ]]; then inputs+=("tests/fuzz/regressions/$target"); fi
    echo "fuzz_$target: $seconds s"
    # -timeout: generous, because a starved (niced, shared-machine) run stalls for seconds; the
    # slowest pipeline input so far (a 12-vertex spike converted to 1,715 vertices, then decimated)
    # takes 6 s under the sanitizers. -rss_limit_mb: the capped inputs never need more.
    "$dir/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 \
        -max_len=16384 -print_final_stats=1 -artifact_prefix="$dir/artifacts/" \
        "${inputs[@]}" >"$dir/logs/$target.log" 2>&1 || {
        tail -n 60 "$dir/logs/$target.log"
        echo "fuzz_$target found a bug: see $dir/logs/$target.log and $dir/artifacts/" >&2
        exit 1
    }
    grep -E "^#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb" "$dir/logs/$target.log"
done
