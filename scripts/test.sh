#!/usr/bin/env bash
# Set-up-to-result test command: installs what is missing, configures, builds and runs every test,
# then every further stage in scripts/test.d/ (in name order; each gets the build folder as $1).
#   usage: scripts/test.sh            (build folder: build/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$here/build}
"$here/scripts/setup.sh" "$build/data"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" \
      -DLAPLACIAN_DEFORMATION_DOC_WARN_AS_ERROR=FAIL_ON_WARNINGS >/dev/null
cmake --build "$build" -j"$(nproc)"
ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
for stage in "$here"/scripts/test.d/*.sh; do
  [ -e "$stage" ] || continue
  echo "== test stage $(basename "$stage")"
  bash "$stage" "$build"
done
echo "== all tests passed"
