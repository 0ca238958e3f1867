"""The examples run for real: matplotlib draws the overlay into a PNG under the Agg backend, and the
Open3D example builds its geometries (and writes its PLY) without a window. Each test is skipped
when its library is missing (Debian python3-matplotlib, python3-open3d; scripts/setup.sh)."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import iilfm

EXAMPLES = Path(__file__).resolve().parents[1]
SAMPLE = EXAMPLES.parent / "data" / "sample"
SCAN, MAP = SAMPLE / "mid40_tag_wall.pcd", SAMPLE / "mid40_tag_wall_map.yaml"


def run_example(name, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=120)


def test_matplotlib_example_writes_the_overlay(tmp_path):
    pytest.importorskip("matplotlib")
    from matplotlib import image as mpimg

    png = tmp_path / "overlay.png"
    done = run_example("matplotlib_overlay.py", SCAN, "--sensor", "mid40", "--out", png)
    assert done.returncode == 0, done.stderr
    expected = iilfm.Pipeline(sensor="mid40").detect(iilfm.read_cloud(SCAN))
    assert len(expected.markers) == 1
    assert done.stdout.splitlines()[0] == "1 marker(s): " + str(expected.markers[0].id)
    assert f"wrote {png}" in done.stdout
    picture = mpimg.imread(png)
    height, width = picture.shape[:2]
    assert width > 600 and height > 300
    # The picture holds the gray image and the orange outline (matplotlib's "orange").
    rgb = picture[..., :3]
    orange = (rgb[..., 0] > 0.9) & (np.abs(rgb[..., 1] - 0.65) < 0.1) & (rgb[..., 2] < 0.2)
    assert orange.sum() > 50
    assert np.unique(rgb.reshape(-1, 3), axis=0).shape[0] > 50  # not a blank figure


def test_matplotlib_example_without_matplotlib_says_what_to_install(tmp_path):
    # A matplotlib that cannot be imported: the example exits with the install hint.
    (tmp_path / "matplotlib.py").write_text("raise ImportError('hidden for this test')\n")
    env = dict(os.environ, PYTHONPATH=f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    done = subprocess.run([sys.executable, str(EXAMPLES / "matplotlib_overlay.py"), str(SCAN)],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 1
    assert "apt install python3-matplotlib" in done.stderr


def test_open3d_example_builds_the_scene_in_the_world(tmp_path):
    o3d = pytest.importorskip("open3d")
    sys.path.insert(0, str(EXAMPLES))
    try:
        import open3d_detect
    finally:
        sys.path.remove(str(EXAMPLES))
    cloud = iilfm.read_cloud(SCAN)
    result = iilfm.Pipeline(map=MAP).detect(cloud)  # resolution estimated, as the example does
    assert [m.id for m in result.markers] == [0] and result.pose is not None
    shown = dict(open3d_detect.build_geometries(o3d, cloud, result))
    marker = "apriltag:tag36h11/0"
    assert set(shown) == {"cloud", f"{marker} outline", f"{marker} axes", "LiDAR axes",
                          "world axes"} | {f"{marker} corner {k}" for k in range(1, 5)}
    # Points in the world frame: T_world_lidar applied to the cloud.
    points = np.asarray(shown["cloud"].points)
    assert len(points) == len(cloud)
    T = result.pose.T_world_lidar
    lidar = np.column_stack([cloud.x, cloud.y, cloud.z]).astype(np.float64)
    np.testing.assert_allclose(points, lidar @ T[:3, :3].T + T[:3, 3], atol=1e-9)
    # The outline joins the four corners, which land on the map's corners (within 2 cm).
    outline = shown[f"{marker} outline"]
    assert np.asarray(outline.lines).tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    world_corners = np.asarray(outline.points)
    yaml = pytest.importorskip("yaml")
    mapped = np.array(yaml.safe_load(MAP.read_text())["markers"][0]["corners"])
    assert np.abs(world_corners - mapped).max() < 0.02

    ply = tmp_path / "scene.ply"
    done = run_example("open3d_detect.py", SCAN, "--map", MAP, "--out", ply)
    assert done.returncode == 0, done.stderr
    assert o3d.io.read_point_cloud(str(ply)).has_points()
    assert len(o3d.io.read_point_cloud(str(ply)).points) == len(cloud) + 4
