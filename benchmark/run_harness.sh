#!/usr/bin/env bash
# Regenerates benchmark/RESULTS.md: builds the comparison harness and the micro-benchmarks in
# Release, runs every task of benchmark/Laplacian_deformation/tasks/ (all representation x weights x
# transform combinations, each with the identity and the rotation start, and CGAL's
# Surface_mesh_deformation, 10 iterations, tolerance 0), the convergence runs (50 iterations of
# cylinder_bend, cylinder_twist and bar_twist), the micro-benchmarks (each case in its own process,
# for its peak memory), renders the figures when the renderer is there, and writes RESULTS.md (with
# the convergence figures benchmark/figures/convergence_*.svg).
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
echo "before: $(date -u '+%F %T UTC') $(cat /proc/loadavg)" > "$out/load.txt"
echo "== harness: $out"
"$build/benchmark/Laplacian_deformation/compare_deformations" --iterations "$iterations" "$out" \
    "$here"/benchmark/Laplacian_deformation/tasks/*.task 2> "$out/harness.log"
# Convergence (issue 15): the bend / twist metrics after every iteration 1..50 of the cotangent
# combinations (both starts) and CGAL's three variants, into $out/convergence.csv.
echo "convergence: $(date -u '+%F %T UTC') $(cat /proc/loadavg)" >> "$out/load.txt"
echo "== convergence (50 iterations): cylinder_bend, cylinder_twist, bar_twist"
tasks="$here/benchmark/Laplacian_deformation/tasks"
"$build/benchmark/Laplacian_deformation/compare_deformations" --convergence 50 "$out" \
    "$tasks/cylinder_bend.task" "$tasks/cylinder_twist.task" "$tasks/bar_twist.task" 2> "$out/convergence.log"
# Micro-benchmarks: every case in its own process (its peak memory is then its own), merged into bench.json.
echo "micro-benchmarks: $(date -u '+%F %T UTC') $(cat /proc/loadavg)" >> "$out/load.txt"
echo "== micro-benchmarks (levels $levels), one process per case"
bench="$build/benchmark/Laplacian_deformation/bench_Mesh_deformer"
rm -rf "$out/bench_cases"
mkdir -p "$out/bench_cases"
: > "$out/bench.txt"
i=0
"$bench" --levels="$levels" --benchmark_list_tests | while read -r name; do
  i=$((i + 1))
  "$bench" --levels="$levels" --benchmark_filter="^${name}\$" \
      --benchmark_out="$out/bench_cases/$(printf %03d $i).json" --benchmark_out_format=json < /dev/null | tee -a "$out/bench.txt"
done
echo "after: $(date -u '+%F %T UTC') $(cat /proc/loadavg)" >> "$out/load.txt"
python3 - "$out/bench_cases" "$out/bench.json" <<'PY'
import glob, json, os, sys
merged = None
for f in sorted(glob.glob(os.path.join(sys.argv[1], '*.json'))):
    d = json.load(open(f))
    if merged is None:
        merged = d
    else:
        merged['benchmarks'] += d['benchmarks']
json.dump(merged or {'benchmarks': []}, open(sys.argv[2], 'w'), indent=1)
PY

# Figures (rest | vertex-based | edge-based | CGAL ARAP) by the headless renderer, when present.
if [ -f "$here/benchmark/render_figures.sh" ]; then
  echo "== figures"
  bash "$here/benchmark/render_figures.sh" "$out" "$here/benchmark/figures"
fi

python3 "$here/benchmark/make_results.py" "$out" "$here/benchmark" "$iterations" "$levels" > "$here/benchmark/RESULTS.md.tmp"
mv "$here/benchmark/RESULTS.md.tmp" "$here/benchmark/RESULTS.md"
cp "$out/results.csv" "$here/benchmark/results.csv"
echo "== wrote $here/benchmark/RESULTS.md and benchmark/results.csv"
