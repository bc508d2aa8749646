#!/usr/bin/env bash
# Set-up-to-result main job: installs what is missing, builds the laplacian_deform tool and runs
# it on its default task (CGAL's cactus with its Botsch08 selection, vertex- and edge-based S*R1),
# then draws rest | vertex-based | edge-based side by side, coloured by the distortion field with
# one colour bar (viewer/render.mjs: headless Chromium), next to the OFF files and the summary.
# Without node (20 or newer) or Chromium there is no picture: the script says why and still succeeds.
#   usage: scripts/demo.sh            (results in build/laplacian_deform_output/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$here/build}
"$here/scripts/setup.sh" "$build/data"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" >/dev/null
cmake --build "$build" --target laplacian_deform laplacian_deform_figure -j"$(nproc)"
cd "$build"
"$build/demo/Laplacian_deformation/laplacian_deform"
out=$build/laplacian_deform_output
"$build/demo/Laplacian_deformation/laplacian_deform_figure" --task cactus \
  --title "CGAL's cactus, Botsch08 selection, S*R1, cotangent weights" "$build/data/cactus.off" \
  vertex="$out/cactus_vertex-based.off" edge="$out/cactus_edge-based.off" "$out/figure"
why=""
node_major=$(node --version 2>/dev/null | sed -E 's/^v([0-9]+).*/\1/' || true)
if ! command -v node >/dev/null 2>&1; then
  why="node is not installed"
elif [ "${node_major:-0}" -lt 20 ]; then
  why="node $(node --version) is older than 20 (the renderer's playwright-core needs 20)"
elif [ ! -x /usr/bin/chromium ]; then
  why="Chromium is not installed at /usr/bin/chromium (scripts/setup.sh installs Debian's)"
elif [ ! -d "$here/viewer/node_modules/playwright-core" ] &&
     ! (cd "$here/viewer" && npm ci --no-audit --no-fund >/dev/null 2>&1); then
  why="the viewer's npm packages could not be installed (npm ci in viewer/ failed: no access to the npm registry?)"
fi
if [ -z "$why" ]; then
  if node "$here/viewer/render.mjs" "$out/figure" "$out" >/dev/null 2>"$out/figure/render.log"; then
    echo "picture in  $out/cactus.png (rest | vertex-based | edge-based, one colour bar)"
  else
    why="the renderer failed: see $out/figure/render.log"
  fi
fi
[ -z "$why" ] || echo "no picture: $why (the OFF files and the summary are written)"
echo "results in $build/laplacian_deform_output/"
