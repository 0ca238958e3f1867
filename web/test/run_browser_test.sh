#!/usr/bin/env bash
# ctest `html_report_browser`: simulates a scan of the 7 x 5 tag grid, writes its HTML report with
# `iilfm detect --html`, and checks the page in headless Chromium (browser_test.mjs).
# Usage: run_browser_test.sh IILFM_CLI WEB_BUILD_DIR ARTIFACT_DIR
set -euo pipefail
cli="$1" web="$2" out="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
chromium="${IILFM_CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium" ]; then
  echo "html_report_browser: no Chromium at $chromium (scripts/setup.sh installs it)" >&2
  exit 1
fi
mkdir -p "$out" "$web/test"
# Next to web/node_modules, so that playwright-core resolves.
cp "$here/browser.mjs" "$here/browser_test.mjs" "$web/test/"
"$cli" sim --scene grid --frames 20 --seed 3 --out "$out/grid.pcd" --map "$out/grid_map.yaml"
"$cli" detect "$out/grid.pcd" --sensor mid40 --map "$out/grid_map.yaml" --json "$out/report.json" \
  --html "$out/report.html" -q
echo "report: $out/report.html ($(stat -c %s "$out/report.html") bytes)"
node "$web/test/browser_test.mjs" "$out/report.html" "$out/report.json" \
  "$out/report_screenshot.png" "$chromium"
