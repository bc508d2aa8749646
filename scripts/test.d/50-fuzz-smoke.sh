#!/usr/bin/env bash
# Test stage: the libFuzzer targets (test/Laplacian_deformation/fuzz) built with clang in
# $1-fuzz (-fsanitize=fuzzer,address,undefined), each run ${FUZZ_SECONDS:-20} s from the
# committed seed corpus (a scratch copy: the committed corpus is not modified). A crash, a
# sanitizer finding or a violated property fails the stage.
#   usage: scripts/test.d/50-fuzz-smoke.sh <main build folder>
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(cd "$1" && pwd)   # absolute: the fuzzers run from their scratch folders
fuzz=$build-fuzz
seconds=${FUZZ_SECONDS:-20}
clang=$(command -v clang++-14 || command -v clang++)
CXX=$clang cmake -S "$here" -B "$fuzz" -DCMAKE_BUILD_TYPE=Debug -DLAPLACIAN_DEFORMATION_BUILD_FUZZERS=ON \
      -DLAPLACIAN_DEFORMATION_BUILD_TESTS=OFF -DLAPLACIAN_DEFORMATION_BUILD_EXAMPLES=OFF \
      -DLAPLACIAN_DEFORMATION_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$fuzz" --target fuzz_botsch08 fuzz_deformer fuzz_server -j"$(nproc)"
for target in botsch08 deformer server; do
  work=$fuzz/smoke-$target
  rm -rf "$work" && mkdir -p "$work/corpus"
  cp "$here/test/Laplacian_deformation/fuzz/corpus/$target/"* "$work/corpus/"
  echo "== fuzzing $target for $seconds s"
  (cd "$work" && "$fuzz/test/Laplacian_deformation/fuzz/fuzz_$target" -max_total_time="$seconds" \
     -print_final_stats=1 -timeout=20 corpus > log.txt 2>&1) || { tail -40 "$work/log.txt"; exit 1; }
  grep -E "^#[0-9]+[[:space:]]+DONE" "$work/log.txt" | tail -1
done
echo "== fuzz smoke: no crash"
