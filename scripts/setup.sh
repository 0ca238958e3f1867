#!/usr/bin/env bash
# Installs every build and test dependency of iilfm from Debian packages. Idempotent: packages that
# are already installed are not touched, and apt is only called when something is missing.
# `--bench` adds PCL's headers for the paper-baseline benchmark (bench/paper_baseline.cpp; about
# 60 MB of packages, not needed by iilfm itself).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libapriltag-dev libopencv-dev libopencv-contrib-dev zlib1g-dev
  # image files (PNG, JPEG, TIFF) without OpenCV's codec module (include/iilfm/image_files.hpp)
  libpng-dev libjpeg-dev libtiff-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  # bag readers (ROS 1 bz2/lz4 chunks, ROS 2 sqlite3, MCAP lz4/zstd chunks) and real bag writers
  # for their tests
  libbz2-dev liblz4-dev libzstd-dev libsqlite3-dev python3-rosbag python3-sensor-msgs python3-genpy
  # PCL's command-line tools: PCD/PLY interoperability tests (about 20 MB download)
  pcl-tools
  # Python bindings and their tests
  pybind11-dev python3-dev python3-numpy python3-pytest
  # the Python examples, run as tests (ctest python_example_*; skipped when missing)
  python3-matplotlib python3-open3d python3-yaml
  # HTML report tested in a real headless browser
  chromium chromium-driver
)

[ "${1:-}" = "--bench" ] && packages+=(libpcl-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} dependencies present"
  exit 0
fi

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
