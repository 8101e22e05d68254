#!/usr/bin/env bash
# Peak resident memory (/usr/bin/time -v) of `sdmesh check`, `convert`, `operators` and `eigs` on
# the large corpus meshes, with bytes per input face; prints a Markdown table (copied by hand to
# experiments/results/memory.md). Runs one command at a time, so each peak is its own.
#   bash scripts/measure_memory.sh [BUILD_DIR] [MESH...]
# BUILD_DIR (default build-rel) must hold a Release `sdmesh`; MESH defaults to the two corpus
# meshes over a million faces. Scratch outputs go to a temporary folder, removed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-rel}
shift || true
corpus=${SDMESH_CORPUS_DIR:-../shared/data/meshes}
meshes=("$@")
if [[ ${#meshes[@]} -eq 0 ]]; then meshes=("$corpus/oded_skull_midsub2.obj.gz" "$corpus/igea_midsub1.obj.gz"); fi
sdmesh="$build/sdmesh"
[[ -x "$sdmesh" ]] || { echo "no $sdmesh: cmake --build $build --target sdmesh_cli" >&2; exit 2; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

echo "| mesh | faces | command | exit | seconds | peak RSS (MB) | bytes / face |"
echo "|---|---:|---|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
    faces=$("$sdmesh" check "$mesh" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["faces"])' || true)
    name=$(basename "$mesh")
    declare -a commands=(
        "check $mesh"
        "convert $mesh $scratch/converted.ply"
        "operators $mesh --out $scratch/operators"
        "eigs $mesh -k 10 --out $scratch/eigs"
    )
    for command in "${commands[@]}"; do
        set +e
        /usr/bin/time -v -o "$scratch/time.txt" "$sdmesh" $command >/dev/null 2>"$scratch/err.txt"
        code=$?
        set -e
        kb=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$scratch/time.txt")
        wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$scratch/time.txt")
        seconds=$(python3 -c "import sys; p=[float(x) for x in sys.argv[1].split(':')]; print(round(sum(v*60**i for i,v in enumerate(reversed(p))),1))" "$wall")
        printf '| %s | %s | %s | %s | %s | %.0f | %.0f |\n' "$name" "$faces" "${command%% *}" "$code" "$seconds" \
            "$(echo "$kb / 1024" | bc -l)" "$(echo "$kb * 1024 / $faces" | bc -l)"
        rm -rf "$scratch/converted.ply" "$scratch/operators" "$scratch/eigs"
    done
done
