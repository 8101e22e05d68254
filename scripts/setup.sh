#!/usr/bin/env bash
# Installs the Debian packages sdmesh needs (only those missing), then configures and builds
# Release with all cores into build/. Idempotent: a second run installs nothing and rebuilds
# only what changed. `--tests` also installs what only the test suite needs (pytest for the
# Python bindings, clang's libFuzzer for the short fuzz runs, matplotlib for the plot scripts).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config zlib1g-dev libeigen3-dev libspectra-dev libsuitesparse-dev
          libopenmesh-dev libgtest-dev libbenchmark-dev libomp-dev
          python3-dev pybind11-dev python3-numpy python3-scipy
          libblas-dev           # cblas.h and libblas.so, for block Lanczos's products
          liblapack-dev         # liblapack.so, for its Ritz pairs
          libopenblas0-openmp)  # CHOLMOD's BLAS: 5–10× faster supernodal kernels than reference BLAS
if [ "${1:-}" = "--tests" ]; then
  packages+=(python3-pytest python3-matplotlib clang libclang-rt-dev)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel "$(nproc)"

# `import sdmesh` for the system python3: a .pth file in the user's site-packages names the package
# folder of build/ (no root needed; `cmake --install build` installs the package instead).
if [ -d build/python/sdmesh ]; then
  site_dir=$(/usr/bin/python3 -c 'import site; print(site.getusersitepackages())')
  mkdir -p "$site_dir"
  echo "$PWD/build/python" > "$site_dir/sdmesh.pth"
fi
