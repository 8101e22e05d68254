#!/usr/bin/env bash
# Sets up and builds sdmesh, then runs the whole test suite with all cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --tests
ctest --test-dir build --output-on-failure --parallel "$(nproc)"
