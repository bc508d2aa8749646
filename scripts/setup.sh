#!/usr/bin/env bash
# Installs the Debian packages Laplacian_deformation needs (only the missing ones) and unpacks the
# real meshes the tests, examples and demo use from Debian's libcgal-demo into a build-time data
# folder (default: build/data). Idempotent and quiet when everything is already there.
#   usage: scripts/setup.sh [DATA_DIR]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
data_dir=${1:-$here/build/data}

packages=(g++ cmake make libcgal-dev libcgal-demo libeigen3-dev libboost-graph-dev
          libgtest-dev googletest libbenchmark-dev libsuitesparse-dev libtbb-dev
          libopenblas0-pthread                      # optimised BLAS for CHOLMOD's supernodal Cholesky
          doxygen                                   # the manual (doc target, built by CI)
          libopenmesh-dev                           # OpenMesh as a FaceGraph (generic tests)
          nlohmann-json3-dev libcpp-httplib-dev     # JSON report, laplacian_deform --serve
          clang libclang-rt-14-dev                  # sanitizers and libFuzzer targets
          chromium)                                 # headless figures and browser tests

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Real meshes (never committed): unpacked from libcgal-demo's tarballs.
doc=/usr/share/doc/libcgal-dev
meshes=(armadillo cactus dino elephant camel man head)
mkdir -p "$data_dir"
stamp="$data_dir/.unpacked-v1"
if [ ! -f "$stamp" ]; then
  members=()
  for m in "${meshes[@]}"; do members+=("data/meshes/$m.off"); done
  tar -xzf "$doc/data.tar.gz" -C "$data_dir" --strip-components=2 "${members[@]}"
  tar -xzf "$doc/examples.tar.gz" -C "$data_dir" --strip-components=3 \
      examples/Surface_mesh_deformation/data/cactus.sel \
      examples/Surface_mesh_deformation/data/cactus.def
  touch "$stamp"
  echo "setup: meshes unpacked into $data_dir"
fi
