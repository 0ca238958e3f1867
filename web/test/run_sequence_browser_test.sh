#!/usr/bin/env bash
# ctest `html_sequence_report_browser`: simulates an ULTRA Puck walking past the 7 x 5 tag grid
# (8 scans, turning; in one the LiDAR faces backwards, and one is taken 40 m away, where no
# marker can be found, so the trajectory has a gap), writes
# them into a ROS 1 bag, runs
# `iilfm detect BAG --topic ... --jsonl --html` and checks the page in headless Chromium
# (sequence_browser_test.mjs).
# Usage: run_sequence_browser_test.sh IILFM_CLI WEB_BUILD_DIR ARTIFACT_DIR SOURCE_DIR
set -euo pipefail
cli="$1" web="$2" out="$3" source="$4"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
chromium="${IILFM_CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium" ]; then
  echo "html_sequence_report_browser: no Chromium at $chromium (scripts/setup.sh installs it)" >&2
  exit 1
fi
mkdir -p "$out" "$web/test"
# Next to web/node_modules, so that playwright-core resolves.
cp "$here/browser.mjs" "$here/sequence_browser_test.mjs" "$web/test/"
frames=8 turned=5 away=3  # scan 5 faces backwards (360 degrees: it still sees the grid)
pcds=()
for ((k = 0; k < frames; ++k)); do
  yaw=$(awk -v k=$k -v turned=$turned 'BEGIN { print (k == turned ? 180 : -9 + 1.5 * k) }')
  xyz=$(awk -v k=$k -v away=$away \
    'BEGIN { printf "%.3f %.3f %.3f", (k == away ? -40 : 0.1 + 0.09 * k), -0.5 + 0.08 * k,
             0.6 + 0.1 * sin(k / 2) }')
  "$cli" sim --scene grid --sensor ultrapuck --seed $((k + 1)) --lidar-xyz $xyz \
    --lidar-rpy 0.5 -1 "$yaw" --out "$out/scan$k.pcd" --map "$out/map.yaml" > /dev/null
  pcds+=("$out/scan$k.pcd")
done
/usr/bin/python3 "$source/tests/tools/make_bags.py" pcd2bag "$out/walk.bag" /velodyne_points \
  "${pcds[@]}"
rm -f "${pcds[@]}"
"$cli" detect "$out/walk.bag" --topic /velodyne_points --sensor ultrapuck --map "$out/map.yaml" \
  --jsonl "$out/walk.jsonl" --html "$out/sequence_report.html" -q
echo "report: $out/sequence_report.html ($(stat -c %s "$out/sequence_report.html") bytes)"
node "$web/test/sequence_browser_test.mjs" "$out/sequence_report.html" "$out/walk.jsonl" \
  "$out/map.yaml" "$out/sequence_report_screenshot.png" "$chromium"
