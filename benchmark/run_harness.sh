#!/usr/bin/env bash
# Regenerates benchmark/RESULTS.md: builds the comparison harness and the micro-benchmarks in
# Release, runs every task of benchmark/Laplacian_deformation/tasks/ (all representation x weights x
# transform combinations and CGAL's Surface_mesh_deformation, 10 iterations, tolerance 0), runs the
# micro-benchmarks, renders the figures when the renderer is there, and writes RESULTS.md.
#   usage: bash benchmark/run_harness.sh [OUT]      (OUT default: build/harness_output)
#   env:   BUILD_DIR (default build), LEVELS (micro-benchmark armadillo levels, default 0,1;
#          0,1,2 adds the 416k-vertex Loop subdivision, slow), ITERATIONS (default 10)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$here/build}
out=${1:-$build/harness_output}
levels=${LEVELS:-0,1}
iterations=${ITERATIONS:-10}

"$here/scripts/setup.sh" "$build/data"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" >/dev/null
cmake --build "$build" --target compare_deformations bench_Mesh_deformer -j"$(nproc)"

mkdir -p "$out"
echo "== harness: $out"
"$build/benchmark/Laplacian_deformation/compare_deformations" --iterations "$iterations" "$out" \
    "$here"/benchmark/Laplacian_deformation/tasks/*.task 2> "$out/harness.log"
echo "== micro-benchmarks (levels $levels)"
"$build/benchmark/Laplacian_deformation/bench_Mesh_deformer" --levels="$levels" \
    --benchmark_out="$out/bench.json" --benchmark_out_format=json | tee "$out/bench.txt"

# Figures (rest | vertex-based | edge-based | CGAL ARAP) by the headless renderer, when present.
if [ -f "$here/benchmark/render_figures.sh" ]; then
  echo "== figures"
  bash "$here/benchmark/render_figures.sh" "$out" "$here/benchmark/figures"
fi

python3 "$here/benchmark/make_results.py" "$out" "$here/benchmark" "$iterations" "$levels" > "$here/benchmark/RESULTS.md.tmp"
mv "$here/benchmark/RESULTS.md.tmp" "$here/benchmark/RESULTS.md"
cp "$out/results.csv" "$here/benchmark/results.csv"
echo "== wrote $here/benchmark/RESULTS.md and benchmark/results.csv"
