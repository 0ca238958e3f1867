#!/usr/bin/env bash
# Regenerates the measured section of docs/performance.md: `iilfm bench` (every stage, 1 and 2
# threads) and iilfm side by side with the paper's implementation approach
# (iilfm_bench_baseline, built when PCL is installed: scripts/setup.sh --bench).
# Usage: scripts/perf_report.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
repeat="${2:-30}"
out="$(mktemp)"
{
  echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC') on $(nproc) cores of \"$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')\","
  echo "load average before the run: $(cut -d' ' -f1-3 /proc/loadavg). Command: \`scripts/perf_report.sh\`."
  echo
  echo "### Every stage (\`iilfm bench --markdown --repeat $repeat\`)"
  echo
  "$build/bin/iilfm" bench --markdown --repeat "$repeat"
  echo
  echo "With two threads for the projection, the preprocessing and the lift (\`--threads 2\`; the default is 1):"
  echo
  "$build/bin/iilfm" bench --markdown --repeat "$repeat" --threads 2 | grep -v '^iilfm bench'
  if [ -x "$build/bin/iilfm_bench_baseline" ]; then
    echo
    echo "### Side by side with the paper's implementation approach (\`iilfm_bench_baseline\`)"
    echo
    "$build/bin/iilfm_bench_baseline" --benchmark_repetitions=5 --benchmark_min_time=0.2 \
      --benchmark_format=json 2>/dev/null | /usr/bin/python3 "$root/scripts/baseline_table.py"
  fi
} > "$out"
/usr/bin/python3 - "$root/docs/performance.md" "$out" <<'PY'
import sys
doc, table = sys.argv[1], open(sys.argv[2]).read()
text = open(doc).read()
begin, end = "<!-- measured:begin -->", "<!-- measured:end -->"
head, rest = text.split(begin)
_, tail = rest.split(end)
open(doc, "w").write(head + begin + "\n" + table + end + tail)
PY
rm -f "$out"
echo "perf_report: docs/performance.md updated"
