#!/usr/bin/env bash
# Test stage: the whole test suite again, built with AddressSanitizer + UndefinedBehaviorSanitizer
# in a second folder ($1-asan: Debug, so CGAL/Eigen assertions are on, at -O1): the library's
# test executables; examples, benchmarks, the laplacian_deform tool and the viewer are left out
# to keep CI short (the tool's 100-odd policy instantiations would double the build), so are the
# tests of the generic models and of the metrics (LAPLACIAN_DEFORMATION_BUILD_MODEL_TESTS=OFF: a
# third of this build; the same engine under other mesh types, checked by the main build's tests),
# and the engine's typed tests run on 8 of their 28 policy combinations
# (LAPLACIAN_DEFORMATION_TEST_FEWER_COMBINATIONS: the five rotation-fitting transforms edge-based
# with cotangent weights, one more pair each for the vertex-based representation and the uniform
# weights; every policy is tested by test_policies_and_solver here). Any sanitizer finding aborts its test, so ctest fails.
#   usage: scripts/test.d/40-sanitizers.sh <main build folder>
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$1
asan=$build-asan
# (-Wno-maybe-uninitialized: at -O1 with the sanitizers GCC 12 warns inside CGAL's own OFF reader,
# Constant_property_map's default argument, which the tests' read_OFF instantiates; the Release
# build has no such warning)
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all -O1 -g1 -Wno-maybe-uninitialized -DLAPLACIAN_DEFORMATION_TEST_FEWER_COMBINATIONS"
cmake -S "$here" -B "$asan" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="$flags" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
      -DLAPLACIAN_DEFORMATION_BUILD_EXAMPLES=OFF -DLAPLACIAN_DEFORMATION_BUILD_BENCHMARKS=OFF \
      -DLAPLACIAN_DEFORMATION_BUILD_TOOLS=OFF -DLAPLACIAN_DEFORMATION_BUILD_VIEWER_TESTS=OFF \
      -DLAPLACIAN_DEFORMATION_BUILD_MODEL_TESTS=OFF -DLAPLACIAN_DEFORMATION_FAST_GCC=ON \
      -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" >/dev/null
cmake --build "$asan" -j"$(nproc)"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$asan" --output-on-failure -j"$(nproc)"
echo "== sanitizers: every test passed under AddressSanitizer + UndefinedBehaviorSanitizer"
