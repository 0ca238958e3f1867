#!/usr/bin/env bash
# Installs the dependencies, builds iilfm (Release, with the Python module) and runs the whole test
# suite with ctest (GoogleTest, pytest, the HTML report in headless Chromium).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" "$root/build" -DIILFM_PYTHON=ON
cd "$root/build"
ctest --output-on-failure -j "${IILFM_JOBS:-$(nproc)}"
