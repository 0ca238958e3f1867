"""Bad input raises iilfm.InputError (a ValueError) with the message the program prints."""

import numpy as np
import pytest

import iilfm
from conftest import cli_error


def test_missing_and_malformed_files(tmp_path):
    missing = tmp_path / "missing.pcd"
    with pytest.raises(iilfm.InputError) as e:
        iilfm.read_cloud(str(missing))
    assert str(e.value) == cli_error("detect", missing, "--sensor", "mid40")
    assert isinstance(e.value, ValueError)

    broken = tmp_path / "broken.pcd"
    broken.write_text("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                      "WIDTH 5\nHEIGHT 1\nPOINTS 5\nDATA binary\n\x01\x02")
    with pytest.raises(iilfm.InputError) as e:
        iilfm.read_cloud(str(broken))
    assert str(e.value) == cli_error("detect", broken, "--sensor", "mid40")
    assert str(broken) in str(e.value)


def test_bad_options_match_the_cli(scan, tmp_path):
    cases = [
        (dict(sensor="nope"), ["--sensor", "nope"]),
        (dict(sensor="mid40", markers=["apriltag:tag99"]), ["--sensor", "mid40", "--marker",
                                                            "apriltag:tag99"]),
        (dict(sensor="mid40", threshold="high"), ["--sensor", "mid40", "--threshold", "high"]),
        (dict(sensor="mid40", lift="magic"), ["--sensor", "mid40", "--lift", "magic"]),
        (dict(sensor="mid40", collision="max"), ["--sensor", "mid40", "--collision", "max"]),
        (dict(sensor="mid40", pose_refine="best"), ["--sensor", "mid40", "--pose-refine", "best"]),
        (dict(sensor="mid40", aruco_refine="x"), ["--sensor", "mid40", "--aruco-refine", "x"]),
        (dict(res_h=1e-6, res_v=1e-6), ["--res-h", "1e-6", "--res-v", "1e-6"]),
    ]
    bad_map = tmp_path / "bad_map.yaml"
    bad_map.write_text("markers:\n  - family: apriltag:tag36h11\n    id: 0\n"
                       "    corners: [[0, 0, 0], [1, 0, 0]]\n")
    cases.append((dict(sensor="mid40", map=str(bad_map)), ["--sensor", "mid40", "--map", bad_map]))
    for kwargs, args in cases:
        with pytest.raises(iilfm.InputError) as e:
            iilfm.Pipeline(**kwargs).detect(iilfm.read_cloud(scan["pcd"]))
        cli = cli_error("detect", scan["pcd"], *args)
        if "--res-h" in args:
            # The image-size refusal: the CLI names the file it read and its --max-image-pixels
            # flag around the library's message; Python has neither.
            assert cli.startswith(str(scan["pcd"]) + ": "), cli
            assert str(e.value) in cli, kwargs
            assert "--max-image-pixels" in cli
        else:
            assert str(e.value) == cli, kwargs


def test_points_that_are_not_points():
    pipeline = iilfm.Pipeline(sensor="mid40")
    for bad in [np.zeros((10, 3), np.float32), np.zeros(8, np.float32), "cloud.pcd",
                {"x": np.zeros(3), "y": np.zeros(3), "z": np.zeros(3)},
                {"x": np.ones(3), "y": np.ones(3), "z": np.ones(2), "intensity": np.ones(3)}]:
        with pytest.raises(iilfm.InputError):
            pipeline.detect(bad)
    with pytest.raises(iilfm.InputError, match=r"^points: no valid points \(1 non-finite, 2 zero"):
        pipeline.detect(np.array([[0, 0, 0, 1], [np.nan, 0, 1, 1], [0, 0, 0, 5]], np.float32))
