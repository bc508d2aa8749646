#!/usr/bin/env bash
# Test stage: the reference and user manual build with doxygen, every warning an error
# (undocumented public API fails here).
set -euo pipefail
build=$1
cmake --build "$build" --target doc
