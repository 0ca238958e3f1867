#!/usr/bin/env bash
# Regenerates the fuzz targets' seed corpora (fuzz/corpus/<target>/) from the simulator and the
# bag writers of the tests. Usage: scripts/fuzz_seeds.sh [BUILD_DIR]  (a normal build, default
# build/, with bin/iilfm and bin/iilfm_fuzz_seeds). Needs /usr/bin/python3 with python3-rosbag.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
corpus="$root/fuzz/corpus"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

rm -rf "$corpus"
mkdir -p "$corpus"/{ros1_bag,ros2_db3,mcap,marker_map}
# A VLP-16 sweep of one tag at 3 m; make_seeds keeps a few hundred of its points.
"$build/bin/iilfm" sim --sensor vlp16 --distance 3 --out "$work/scan.pcd" --map "$work/map.yaml" \
  >/dev/null
"$build/bin/iilfm_fuzz_seeds" "$work/scan.pcd" "$corpus"

# ROS 1: one small uncompressed message written from a seed PCD, the tests' bz2 and lz4 chunked
# bags and the Livox CustomMsg bag. ROS 2: the tests' sqlite3 bag.
python=/usr/bin/python3
"$python" "$root/tests/tools/make_bags.py" pcd2bag "$corpus/ros1_bag/small_none.bag" /points \
  --compression none "$corpus/pcd/binary.pcd"
"$python" "$root/tests/tools/make_bags.py" ros1 "$work"
cp "$work/clouds_bz2.bag" "$work/clouds_lz4.bag" "$work/livox.bag" "$corpus/ros1_bag/"
"$python" "$root/tests/tools/make_bags.py" ros2 "$work"
cp "$work/ros2_bag/ros2_bag_0.db3" "$corpus/ros2_db3/clouds.db3"
# MCAP: the tests' recordings from the official writer (tests/data/mcap/README.md).
cp "$root"/tests/data/mcap/*.mcap "$corpus/mcap/"

# Marker maps: the simulator's corner form and the size + pose forms.
cp "$work/map.yaml" "$corpus/marker_map/corners.yaml"
cat >"$corpus/marker_map/pose.yaml" <<'YAML'
markers:
  - family: apriltag:tag36h11
    id: 3
    size: 0.172
    pose: {position: [3, 0, 0.5], rpy_deg: [90, 0, -90]}
  - family: aruco:DICT_4X4_50
    id: 7
    size: 0.2
    pose: {position: [0, 4, 1], quat_xyzw: [0, 0, 0.7071068, 0.7071068]}
YAML
echo "fuzz seeds: $(find "$corpus" -type f | wc -l) files, $(du -sh "$corpus" | cut -f1)"
