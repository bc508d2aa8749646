# Sourced by the test stages 40-sanitizers.sh and 50-fuzz-smoke.sh (not a stage itself: the stages
# are the *.sh files). One clang build folder, <main build folder>-asan, holds both: the test suite
# built with AddressSanitizer + UndefinedBehaviorSanitizer, and the libFuzzer targets
# (test/Laplacian_deformation/fuzz, which add -fsanitize=fuzzer). Clang compiles these units about
# 1.6 times faster than GCC with the same sanitizers (test_Edge_midpoint_graph.cpp: 35 against
# 58 s), and one folder lets the fuzz targets fill the second core while the longest test unit
# compiles.
#   configure_sanitizer_build <main build folder>   (sets $asan to the folder)
configure_sanitizer_build() {
  local build here clang flags
  build=$(cd "$1" && pwd)
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  asan=$build-asan
  clang=$(command -v clang++-14 || command -v clang++) || { echo "error: clang++ not found (scripts/setup.sh installs it)" >&2; return 1; }
  flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all -O1 -g1 -DLAPLACIAN_DEFORMATION_TEST_FEWER_COMBINATIONS"
  # (the compiler is named on the command line: a folder configured before with another compiler
  # is then reconfigured from scratch by CMake; Debug carries the sanitizer flags at -O1 on purpose,
  # so CGAL's notice about Debug builds is turned off)
  cmake -S "$here" -B "$asan" -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="$flags" \
        -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
        -DLAPLACIAN_DEFORMATION_BUILD_FUZZERS=ON \
        -DLAPLACIAN_DEFORMATION_BUILD_EXAMPLES=OFF -DLAPLACIAN_DEFORMATION_BUILD_BENCHMARKS=OFF \
        -DLAPLACIAN_DEFORMATION_BUILD_TOOLS=OFF -DLAPLACIAN_DEFORMATION_BUILD_VIEWER_TESTS=OFF \
        -DLAPLACIAN_DEFORMATION_BUILD_MODEL_TESTS=OFF \
        -DLAPLACIAN_DEFORMATION_DATA_DIR="$build/data" >/dev/null
}
