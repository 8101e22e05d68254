#!/usr/bin/env bash
# Sets up and builds sdmesh, then runs the pipeline on the bundled bunny (tests/data/bunny.obj):
# certificate of the input, conversion to a self-Delaunay mesh, its certificate, its operators and
# the 20 smallest eigenpairs of its Laplacian.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
out=build/quickstart
mkdir -p "$out"
# `check` exits 1 for "not self-Delaunay", the expected verdict for the input bunny.
./build/sdmesh check tests/data/bunny.obj || [ $? -eq 1 ]
./build/sdmesh convert tests/data/bunny.obj "$out/bunny_sd.obj" --report "$out/convert.json" > /dev/null
./build/sdmesh check "$out/bunny_sd.obj"
./build/sdmesh operators "$out/bunny_sd.obj" --out "$out/operators" --mass circumcentric > /dev/null
./build/sdmesh eigs "$out/bunny_sd.obj" -k 20 --out "$out/eigs" --mass circumcentric
echo "Outputs in $out: bunny_sd.obj, convert.json, operators/ (*.mtx, report.json), eigs/ (eigenvalues.csv, eigenvectors.bin, report.json)"
