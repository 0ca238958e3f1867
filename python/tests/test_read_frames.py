"""iilfm.read_frames: a recording frame by frame, as `iilfm detect --topic` reads it. The MCAP
files of tests/data/mcap were written by the official MCAP writer (see its README.md)."""

import json
import shutil

import numpy as np
import pytest

import iilfm
from conftest import SOURCE_DIR, cli_error

MCAP = SOURCE_DIR / "tests" / "data" / "mcap"


def expected_points(name):
    files = json.loads((MCAP / "expected.json").read_text())["files"]
    return files[name]["messages"]["/points"]


@pytest.mark.parametrize("name", ["points_zstd.mcap", "points_no_summary.mcap", "ros2_folder"])
def test_every_frame_with_its_stamp_and_points(name):
    frames = iilfm.read_frames(MCAP / name, "/points")
    assert len(frames) == 5
    assert frames.name == f"{MCAP / name}:/points"
    want = expected_points(name)
    got = list(frames)
    assert len(got) == len(want)
    for k, (cloud, message) in enumerate(zip(got, want)):
        assert isinstance(cloud, iilfm.Cloud)
        stamp = message["stamp"]
        assert cloud.stamp == pytest.approx(stamp["sec"] + stamp["nanosec"] * 1e-9, abs=1e-9)
        assert cloud.path == f"{MCAP / name}:/points#{k}"
        points = np.array(message["points"], dtype=np.float64)
        np.testing.assert_array_equal(cloud.x, points[:, 0].astype(np.float32))
        np.testing.assert_array_equal(cloud.intensity, points[:, 3].astype(np.float32))
        np.testing.assert_array_equal(cloud.ring, points[:, 4].astype(np.uint16))
    assert iilfm.read_cloud(MCAP.parent.parent.parent / "data" / "sample" /
                            "mid40_tag_wall.pcd").stamp is None


def test_folder_of_clouds_and_detect_frames(tmp_path):
    """A folder of PCDs named by their stamps; the frames go straight into detect_frames."""
    folder = tmp_path / "scans"
    folder.mkdir()
    sample = SOURCE_DIR / "data" / "sample" / "mid40_tag_wall.pcd"
    for stamp in ("1600000000.5", "1600000001.5"):
        shutil.copy(sample, folder / f"{stamp}.pcd")
    frames = list(iilfm.read_frames(folder))
    assert [f.stamp for f in frames] == [1600000000.5, 1600000001.5]
    pipeline = iilfm.Pipeline(sensor="mid40",
                              map=SOURCE_DIR / "data" / "sample" / "mid40_tag_wall_map.yaml")
    results = pipeline.detect_frames(frames)
    assert len(results) == 2
    assert all(len(r.markers) >= 1 and r.pose is not None for r in results)


def test_errors_are_the_programs(tmp_path):
    with pytest.raises(iilfm.InputError) as missing_topic:
        iilfm.read_frames(MCAP / "points_zstd.mcap", "/nothing")
    assert str(missing_topic.value) == cli_error("detect", MCAP / "points_zstd.mcap", "--topic",
                                                 "/nothing")
    assert "no topic '/nothing'" in str(missing_topic.value)
    # Without a topic, the file's only point cloud topic (it also holds /chatter).
    only = iilfm.read_frames(MCAP / "points_zstd.mcap")
    assert only.name.endswith("points_zstd.mcap:/points")
    assert [f.path for f in only] == \
        [f.path for f in iilfm.read_frames(MCAP / "points_zstd.mcap", "/points")]
    # A file cut in its data section: the frames before the cut, then the damage.
    whole = (MCAP / "points_zstd.mcap").read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(whole[:1300])
    frames = iilfm.read_frames(cut, "/points")
    seen = 0
    with pytest.raises(iilfm.InputError, match="cut off"):
        for _ in frames:
            seen += 1
    assert 0 < seen < 5


def test_opencv_threads_are_the_callers_to_set():
    before = iilfm.opencv_threads()
    try:
        iilfm.set_opencv_threads(1)
        assert iilfm.opencv_threads() == 1
        iilfm.set_opencv_threads(2)
        assert iilfm.opencv_threads() == 2
        with pytest.raises(iilfm.InputError, match="at least 1, got 0"):
            iilfm.set_opencv_threads(0)
        assert iilfm.opencv_threads() == 2
    finally:
        iilfm.set_opencv_threads(max(1, before))
