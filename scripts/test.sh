#!/usr/bin/env bash
# Installs the dependencies, builds iilfm (Release) and runs the whole test suite with ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" "$root/build"
cd "$root/build"
ctest --output-on-failure -j "${IILFM_JOBS:-$(nproc)}"
