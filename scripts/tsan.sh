#!/usr/bin/env bash
# Builds only the core libraries and the parallel-pipelines test under ThreadSanitizer
# (build-tsan/) and runs it: several Pipelines in threads at once, any data race fails the run.
# Usage: scripts/tsan.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build-tsan}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DIILFM_TSAN=ON -DIILFM_BUILD_BENCH=OFF -DIILFM_HTML_REPORT=OFF -DIILFM_PYTHON=OFF >/dev/null
cmake --build "$build" -j "${IILFM_JOBS:-$(nproc)}" --target iilfm_thread_tests
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 ${TSAN_OPTIONS:-}" \
  "$build/bin/iilfm_thread_tests"
