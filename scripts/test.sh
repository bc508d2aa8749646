#!/usr/bin/env bash
# Set-up-to-result test command: installs what is missing, configures, builds and runs every test,
# then every further stage in scripts/test.d/ (in name order; each gets the build folder as $1).
# Each step prints its wall time (CI keeps the whole run well under 30 minutes on 2 cores).
# The GoogleTest suites are compiled at -O2 (LAPLACIAN_DEFORMATION_TEST_OPTIMIZATION: about 40% less
# compile time than -O3), the examples, the tool and the benchmarks, which ctest runs too, at
# Release's -O3: both levels are tested.
#   usage: scripts/test.sh            (build folder: build/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$here/build}
step_start=$SECONDS
step_done() { echo "== $1: $((SECONDS - step_start)) s (total $SECONDS s)"; step_start=$SECONDS; }
"$here/scripts/setup.sh" "$build/data"
step_done "set-up"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" \
      -DLAPLACIAN_DEFORMATION_DOC_WARN_AS_ERROR=FAIL_ON_WARNINGS -DLAPLACIAN_DEFORMATION_FAST_GCC=ON \
      -DLAPLACIAN_DEFORMATION_TEST_OPTIMIZATION=-O2 >/dev/null
cmake --build "$build" -j"$(nproc)"
step_done "build"
ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
step_done "tests"
for stage in "$here"/scripts/test.d/*.sh; do
  [ -e "$stage" ] || continue
  echo "== test stage $(basename "$stage")"
  bash "$stage" "$build"
  step_done "stage $(basename "$stage")"
done
echo "== all tests passed"
