#!/usr/bin/env bash
# Reproduces every study of experiments/README.md: builds the study programs (Release), runs each
# one, then its plot script, and prints how long each step and the whole run took.
#   scripts/experiments.sh [OUT]     OUT defaults to experiments/results
# The build folder is $SDMESH_EXPERIMENTS_BUILD, default build-exp. Needs the corpus
# (../shared/data/meshes, or -DSDMESH_CORPUS_DIR) and /usr/bin/python3 with Debian's
# python3-matplotlib, python3-numpy and python3-scipy (scripts/setup.sh --tests installs them).
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(realpath -m "${1:-experiments/results}")
build=${SDMESH_EXPERIMENTS_BUILD:-build-exp}
python=/usr/bin/python3  # Debian's NumPy, SciPy and matplotlib belong to the system interpreter
studies=(robustness accuracy wardetzky negative_dual geodesics)
start=$SECONDS

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --parallel "$(nproc)" --target conversion_table decimation_table "${studies[@]}"
mkdir -p "$out"

step() {  # step NAME COMMAND...: runs the command and prints its wall time
  local name=$1 began=$SECONDS
  shift
  "$@"
  echo "== $name: $((SECONDS - began)) s"
}

step conversion_table "$build/experiments/conversion_table" --out "$out"
step conversion_table_tables "$python" experiments/conversion_table/make_table.py "$out/conversion_table.csv"
step conversion_table_plot "$python" experiments/conversion_table/plot.py "$out"
step decimation_table "$build/experiments/decimation_table" --out "$out"
for study in "${studies[@]}"; do
  step "$study" "$build/experiments/$study" --out "$out"
  step "${study}_plot" "$python" "experiments/$study/plot.py" "$out"
done
if [ -e /usr/share/doc/libcgal-dev/data.tar.gz ]; then
  cmake --build "$build" --parallel "$(nproc)" --target sdmesh_cli
  step unseen_meshes "$python" experiments/unseen_meshes/sweep.py "$build/sdmesh" "$out"
  step unseen_commands "$python" experiments/unseen_meshes/every_command.py "$build/sdmesh" "$out"
else
  echo "== unseen_meshes: skipped (apt-get install libcgal-demo occt-misc geomview assimp-testmodels openscad-testing-data)"
fi
echo "== all studies: $((SECONDS - start)) s; results in $out"
