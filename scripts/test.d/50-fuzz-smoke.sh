#!/usr/bin/env bash
# Test stage: the libFuzzer targets (test/Laplacian_deformation/fuzz, -fsanitize=fuzzer,address,undefined),
# built by the sanitizer stage in $1-asan with clang (built here if that stage did not run), each
# run ${FUZZ_SECONDS:-20} s from the committed seed corpus (a scratch copy: the committed corpus is
# not modified). A crash, a sanitizer finding or a violated property fails the stage.
#   usage: scripts/test.d/50-fuzz-smoke.sh <main build folder>
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(cd "$1" && pwd)   # absolute: the fuzzers run from their scratch folders
seconds=${FUZZ_SECONDS:-20}
source "$here/scripts/test.d/sanitizer-build.bash"
configure_sanitizer_build "$build"
cmake --build "$asan" --target fuzz_botsch08 fuzz_deformer fuzz_server -j"$(nproc)"
for target in botsch08 deformer server; do
  work=$asan/smoke-$target
  rm -rf "$work" && mkdir -p "$work/corpus"
  cp "$here/test/Laplacian_deformation/fuzz/corpus/$target/"* "$work/corpus/"
  echo "== fuzzing $target for $seconds s"
  (cd "$work" && "$asan/test/Laplacian_deformation/fuzz/fuzz_$target" -max_total_time="$seconds" \
     -print_final_stats=1 -timeout=20 corpus > log.txt 2>&1) || { tail -40 "$work/log.txt"; exit 1; }
  grep -E "^#[0-9]+[[:space:]]+DONE" "$work/log.txt" | tail -1
done
echo "== fuzz smoke: no crash"
