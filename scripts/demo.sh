#!/usr/bin/env bash
# Set-up-to-result main job: installs what is missing, builds the laplacian_deform tool and runs
# it on its default task (CGAL's cactus with its Botsch08 selection, vertex- and edge-based S*R1).
#   usage: scripts/demo.sh            (results in build/laplacian_deform_output/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$here/build}
"$here/scripts/setup.sh" "$build/data"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" >/dev/null
cmake --build "$build" --target laplacian_deform -j"$(nproc)"
cd "$build"
"$build/demo/Laplacian_deformation/laplacian_deform"
echo "results in $build/laplacian_deform_output/"
