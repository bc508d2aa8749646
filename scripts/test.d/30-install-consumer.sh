#!/usr/bin/env bash
# Test stage: `cmake --install` the package into a temporary prefix, then configure, build and run
# the out-of-tree consumer test/install_consumer against it (find_package(CGAL_Laplacian_deformation),
# target CGAL::Laplacian_deformation, and CGAL::Laplacian_deformation_cholmod when CHOLMOD is found).
set -euo pipefail
build=$1
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$here/test/install_consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" | grep "install_consumer:"
cmake --build "$work/build" -j"$(nproc)"
ctest --test-dir "$work/build" --output-on-failure
