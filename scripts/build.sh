#!/usr/bin/env bash
# Configures and builds iilfm. Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
# Default: build/ in Release. The program lands in BUILD_DIR/bin/iilfm.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${1:-$root/build}"
shift || true
jobs="${IILFM_JOBS:-$(nproc)}"
launcher=()
# ccache, when installed, lets several checkouts (worktrees, CI clones) share compiled objects.
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="${IILFM_BUILD_TYPE:-Release}" \
  "${launcher[@]}" "$@" >/dev/null
cmake --build "$build_dir" -j "$jobs"
