#!/usr/bin/env bash
# Configures and builds iilfm. Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
# Default: build/ in Release. The program lands in BUILD_DIR/bin/iilfm.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${1:-$root/build}"
shift || true
jobs="${IILFM_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="${IILFM_BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build_dir" -j "$jobs"
