#!/usr/bin/env bash
# Test stage: the libFuzzer targets (test/Laplacian_deformation/fuzz, -fsanitize=fuzzer,address,undefined),
# built by the sanitizer stage in $1-asan with clang (built here if that stage did not run), each
# run ${FUZZ_SECONDS:-20} s from the committed seed corpus (a scratch copy: the committed corpus is
# not modified), the three at once (libFuzzer runs one process per target: on 2 cores the stage
# takes 20 s instead of 60, each target getting about two thirds of a core, so fewer runs each).
# A crash, a sanitizer finding or a violated property fails the stage.
#   usage: scripts/test.d/50-fuzz-smoke.sh <main build folder>
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(cd "$1" && pwd)   # absolute: the fuzzers run from their scratch folders
seconds=${FUZZ_SECONDS:-20}
source "$here/scripts/test.d/sanitizer-build.bash"
configure_sanitizer_build "$build"
cmake --build "$asan" --target fuzz_botsch08 fuzz_deformer fuzz_server -j"$(nproc)"
targets=(botsch08 deformer server)
pids=()
# a stage that stops early (set -e) stops the fuzzers it started
trap '[ ${#pids[@]} -eq 0 ] || kill "${pids[@]}" 2>/dev/null || true' EXIT
for target in "${targets[@]}"; do
  work=$asan/smoke-$target
  rm -rf "$work" && mkdir -p "$work/corpus"
  cp "$here/test/Laplacian_deformation/fuzz/corpus/$target/"* "$work/corpus/"
  echo "== fuzzing $target for $seconds s"
  (cd "$work" && exec "$asan/test/Laplacian_deformation/fuzz/fuzz_$target" -max_total_time="$seconds" \
     -print_final_stats=1 -timeout=20 corpus > log.txt 2>&1) &
  pids+=($!)
done
failed=0
for k in "${!targets[@]}"; do
  log=$asan/smoke-${targets[$k]}/log.txt
  if wait "${pids[$k]}"; then
    echo "== ${targets[$k]}: $(grep -E "^#[0-9]+[[:space:]]+DONE" "$log" | tail -1)"
  else
    echo "== ${targets[$k]} failed:"; tail -40 "$log"; failed=1
  fi
done
[ "$failed" = 0 ] || exit 1
echo "== fuzz smoke: no crash"
