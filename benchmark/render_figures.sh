#!/usr/bin/env bash
# Renders one figure per task of a harness output folder (rest | vertex-based | edge-based | CGAL ARAP,
# coloured by the distortion field) with the headless renderer of viewer/ (see viewer/README.md).
#   usage: bash benchmark/render_figures.sh RESULTS_DIR FIGURES_DIR
# Installs the viewer's pinned npm packages (npm ci) when viewer/node_modules is missing.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: bash benchmark/render_figures.sh RESULTS_DIR FIGURES_DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
results=$1
figures=$2
if [ ! -d "$results" ]; then
  echo "error: $results: no such folder" >&2
  exit 1
fi
if [ ! -d "$here/viewer/node_modules" ]; then
  (cd "$here/viewer" && npm ci --no-audit --no-fund)
fi
mkdir -p "$figures"
node "$here/viewer/render.mjs" "$results" "$figures"
