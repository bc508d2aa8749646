#!/usr/bin/env bash
# Test stage: the whole test suite again, built with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in a second folder ($1-asan: Debug, so CGAL/Eigen assertions are on,
# at -O1; see sanitizer-build.bash), together with the libFuzzer targets that the next stage runs:
# the library's test executables; examples, benchmarks, the laplacian_deform tool and the viewer
# are left out to keep CI short (the tool's 100-odd policy instantiations would double the build;
# the editor server's request handling is covered here by the fuzz target fuzz_server), so are the
# tests of the generic models and of the metrics (LAPLACIAN_DEFORMATION_BUILD_MODEL_TESTS=OFF: a
# third of this build; the same engine under other mesh types, checked by the main build's tests),
# and the engine's typed tests run on 8 of their 28 policy combinations
# (LAPLACIAN_DEFORMATION_TEST_FEWER_COMBINATIONS: the five rotation-fitting transforms edge-based
# with cotangent weights, one more pair each for the vertex-based representation and the uniform
# weights; every policy is tested by test_policies_and_solver here). Any sanitizer finding aborts its test, so ctest fails.
#   usage: scripts/test.d/40-sanitizers.sh <main build folder>
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$here/scripts/test.d/sanitizer-build.bash"
configure_sanitizer_build "$1"
cmake --build "$asan" -j"$(nproc)"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$asan" --output-on-failure -j"$(nproc)"
echo "== sanitizers: every test passed under AddressSanitizer + UndefinedBehaviorSanitizer"
