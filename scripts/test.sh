#!/usr/bin/env bash
# Installs the dependencies, builds iilfm (Release, with the Python module) and runs the whole test
# suite with ctest (GoogleTest, pytest, the HTML report in headless Chromium).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
# Tests and benchmarks on explicitly: scripts/demo.sh configures the same build directory without
# them, and CMake's cache would keep that, leaving ctest nothing to run.
"$root/scripts/build.sh" "$root/build" -DIILFM_PYTHON=ON -DIILFM_BUILD_TESTS=ON -DIILFM_BUILD_BENCH=ON
cd "$root/build"
ctest --output-on-failure --no-tests=error -j "${IILFM_JOBS:-$(nproc)}"
