#!/usr/bin/env bash
# Installs the dependencies, builds iilfm and detects the markers of the bundled sample scan:
# prints them and the LiDAR pose, and writes out/demo.json and out/demo.png.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" "$root/build" -DIILFM_BUILD_TESTS=OFF -DIILFM_BUILD_BENCH=OFF
mkdir -p "$root/out"
"$root/build/bin/iilfm" detect "$root/data/sample/mid40_tag_wall.pcd" --sensor mid40 \
  --map "$root/data/sample/mid40_tag_wall_map.yaml" \
  --json "$root/out/demo.json" --image "$root/out/demo.png"
echo "wrote $root/out/demo.json and $root/out/demo.png"
