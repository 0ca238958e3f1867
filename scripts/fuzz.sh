#!/usr/bin/env bash
# Builds the fuzz targets with clang + libFuzzer + ASan/UBSan (build-fuzz/) and runs each for the
# given time. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET...]
#   IILFM_FUZZ_RUNS=N   also stop each target after N inputs (the CI smoke run: whichever first)
# Each target's corpus grows in build-fuzz/corpus/<target> (seeded from fuzz/corpus/<target>);
# crashes land in build-fuzz/crashes/<target>/ and stop the script with status 1. Replay one with
# build/bin/fuzz_<target>_replay FILE.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(pcd kitti ply xyz ros1_bag ros2_db3 mcap marker_map pipeline)
build="${IILFM_FUZZ_BUILD:-$root/build-fuzz}"

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "${launcher[@]}" -DIILFM_FUZZ=ON -DIILFM_BUILD_TESTS=OFF -DIILFM_BUILD_BENCH=OFF \
  -DIILFM_HTML_REPORT=OFF -DIILFM_PYTHON=OFF >/dev/null
cmake --build "$build" -j "${IILFM_JOBS:-$(nproc)}" --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
limit=(-max_total_time="$seconds")
[ -z "${IILFM_FUZZ_RUNS:-}" ] || limit+=(-runs="$IILFM_FUZZ_RUNS")
status=0
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target"
  crashes="$build/crashes/$target"
  mkdir -p "$corpus" "$crashes"
  regressions=()
  [ ! -d "$root/fuzz/regressions/$target" ] || regressions=("$root/fuzz/regressions/$target")
  # -rss_limit_mb / -malloc_limit_mb: an allocation sized by an unchecked header value is a bug
  # even when the machine could satisfy it. -timeout: a hang is too.
  if "$build/bin/fuzz_$target" "${limit[@]}" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -timeout=10 -artifact_prefix="$crashes/" -print_final_stats=1 \
    "$corpus" "$root/fuzz/corpus/$target" "${regressions[@]}" >"$build/fuzz_$target.log" 2>&1; then
    echo "fuzz $target: $(grep -o 'stat::number_of_executed_units: *[0-9]*' \
      "$build/fuzz_$target.log" | grep -o '[0-9]*$') executions, no crash"
  else
    echo "fuzz $target: FAILED, see $build/fuzz_$target.log and $crashes/"
    status=1
  fi
done
exit $status
