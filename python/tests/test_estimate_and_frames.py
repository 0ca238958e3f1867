"""Pipeline() without a sensor estimates the resolution from the cloud as `iilfm detect` does, and
Pipeline.detect_frames runs a recording as `iilfm detect FOLDER --jsonl` does (window or not)."""

import json

import numpy as np
import pytest

import iilfm
from conftest import SOURCE_DIR, cli_error, run_cli
from test_detect import assert_same_as_cli


def same_detections(result, line):
    """Markers and pose of a Result against a JSON line of the CLI (values rounded there)."""
    got = result.to_json()
    assert [(m["family"], m["id"]) for m in got["markers"]] == \
        [(m["family"], m["id"]) for m in line["markers"]]
    for mine, theirs in zip(got["markers"], line["markers"]):
        np.testing.assert_allclose(mine["corners_lidar"], theirs["corners_lidar"], atol=1e-9)
    assert (got["pose"] is None) == (line["pose"] is None)
    if got["pose"] is not None:
        np.testing.assert_allclose(got["pose"]["T_world_lidar"], line["pose"]["T_world_lidar"],
                                   atol=1e-9)
    # Both name the resolution's source; Python words it for its own API.
    assert "resolution" in line["image"]
    def without_source(image):
        return {k: v for k, v in image.items() if k != "resolution"}
    assert without_source(got["image"]) == without_source(line["image"])


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """Three ULTRA Puck scans of the tag grid from a LiDAR moving sideways, in a folder."""
    d = tmp_path_factory.mktemp("walk")
    (d / "scans").mkdir()
    for k in range(3):
        iilfm.simulate(scene="grid", sensor="ultrapuck", seed=k + 1,
                       lidar_xyz=(0.1 + 0.1 * k, -0.3 + 0.1 * k, 0.6), lidar_rpy=(0, 0, -3 + 2 * k),
                       out=d / "scans" / f"s{k}.pcd", map=d / "map.yaml")
    return d


def test_no_sensor_estimates_like_the_cli_rosette(tmp_path):
    """Mid-40 (non-repetitive): resolution from the point density."""
    sample = SOURCE_DIR / "data" / "sample"
    pcd, marker_map = sample / "mid40_tag_wall.pcd", sample / "mid40_tag_wall_map.yaml"
    out = tmp_path / "no_sensor.json"
    run_cli("detect", pcd, "--map", marker_map, "--json", out, "-q")
    cli = json.loads(out.read_text())
    assert cli["image"]["resolution"] == "estimated (point density)"
    pipeline = iilfm.Pipeline(map=marker_map)
    assert pipeline.resolution is None  # nothing to estimate from yet
    result = pipeline.detect(iilfm.read_cloud(pcd))
    assert_same_as_cli(result, cli)  # includes the image geometry and the resolution's source
    assert [m.id for m in result.markers] == [0]
    assert pipeline.resolution["source"] == "estimated (point density)"
    assert pipeline.resolution["res_h_deg"] == pytest.approx(cli["image"]["res_h_deg"], abs=1e-9)
    # Kept for later frames: a sparser cloud does not change it.
    first = dict(pipeline.resolution)
    pipeline.detect(iilfm.read_cloud(pcd).xyzi()[::4])
    assert pipeline.resolution == first


def test_no_sensor_estimates_like_the_cli_spinning(walk):
    """ULTRA Puck: one row per ring; a given res_h overrides the estimate's, as on the CLI."""
    pcd, marker_map = walk / "scans" / "s0.pcd", walk / "map.yaml"
    for extra, kwargs in [([], {}), (["--res-h", "0.21"], {"res_h": 0.21})]:
        out = walk / "one.json"
        run_cli("detect", pcd, "--map", marker_map, "--json", out, "-q", *extra)
        cli = json.loads(out.read_text())
        pipeline = iilfm.Pipeline(map=marker_map, **kwargs)
        result = pipeline.detect(iilfm.read_cloud(pcd))
        assert cli["markers"], "the scan shows markers"
        assert_same_as_cli(result, cli)
        assert pipeline.resolution["rows"] == "rings" and pipeline.resolution["rings"] == 32
        assert pipeline.resolution["source"] == "estimated (ring field)"
        assert pipeline.resolution["res_h_deg"] == pytest.approx(cli["image"]["res_h_deg"])


def test_too_few_points_to_estimate(scan, tmp_path):
    tiny = tmp_path / "tiny.xyz"
    tiny.write_text("".join(f"{2 + 0.01 * i} {0.01 * i} 0.5 10\n" for i in range(50)))
    with pytest.raises(iilfm.InputError) as e:
        iilfm.Pipeline().detect(iilfm.read_cloud(tiny))
    assert str(e.value) == cli_error("detect", tiny)
    with pytest.raises(iilfm.InputError, match=r"^points: too few points \(50\)"):
        iilfm.Pipeline().detect(iilfm.read_cloud(tiny).xyzi())
    # Option errors do not wait for a cloud.
    with pytest.raises(iilfm.InputError) as e:
        iilfm.Pipeline(markers=["apriltag:tag99"])
    assert str(e.value) == cli_error("detect", scan["pcd"], "--marker", "apriltag:tag99")


@pytest.mark.parametrize("window", [1, 2])
def test_detect_frames_matches_the_cli_on_a_folder(walk, window):
    jsonl = walk / f"walk{window}.jsonl"
    run_cli("detect", walk / "scans", "--map", walk / "map.yaml", "--frames", window, "--jsonl",
            jsonl, "-q")
    lines = [json.loads(line) for line in jsonl.read_text().splitlines()]
    assert len(lines) == 3 - window + 1
    clouds = [iilfm.read_cloud(walk / "scans" / f"s{k}.pcd") for k in range(3)]
    pipeline = iilfm.Pipeline(map=walk / "map.yaml")
    results = pipeline.detect_frames(clouds, window=window)
    assert len(results) == len(lines)
    assert sum(len(r.markers) for r in results) > 0
    for result, line in zip(results, lines):
        same_detections(result, line)
        assert result.input["copied"] is (window > 1)  # a window's union is a copy
        assert result.input["points"] == line["input"]["points"]
    assert results[-1].input["path"] == str(walk / "scans" / "s2.pcd")
    if window == 1:  # one frame at a time is detect() itself, read in place
        again = iilfm.Pipeline(map=walk / "map.yaml")
        for cloud, result in zip(clouds, results):
            assert again.detect(cloud).to_json()["markers"] == result.to_json()["markers"]


def test_spinning_preset_takes_the_columns_of_the_clouds_mode(tmp_path):
    """The simulated OS1-128 runs 2048 columns, the preset assumes 1024: Pipeline("os1-128")
    takes the cloud's, as `iilfm detect --sensor os1-128` does; a given res_h keeps its own."""
    pcd = tmp_path / "os1.pcd"
    iilfm.simulate(sensor="os1-128", marker_size=0.6, distance=3.0, out=pcd)
    out = tmp_path / "os1.json"
    run_cli("detect", pcd, "--sensor", "os1-128", "--marker-size", "0.6", "--json", out, "-q")
    cli = json.loads(out.read_text())
    assert cli["image"]["resolution"] == "preset os1-128, columns from the cloud (2048)"
    pipeline = iilfm.Pipeline("os1-128", marker_size=0.6)
    assert pipeline.resolution is None  # until the first cloud
    result = pipeline.detect(iilfm.read_cloud(pcd))
    got = result.to_json()
    assert got["image"] == cli["image"]
    assert [m.id for m in result.markers] == [0] == [m["id"] for m in cli["markers"]]
    np.testing.assert_allclose(got["markers"][0]["corners_lidar"],
                               cli["markers"][0]["corners_lidar"], atol=1e-9)
    assert pipeline.resolution["source"] == cli["image"]["resolution"]
    assert pipeline.resolution["res_h_deg"] == pytest.approx(360 / 2048, abs=1e-12)
    given = iilfm.Pipeline("os1-128", res_h=360 / 1024)
    given.detect(iilfm.read_cloud(pcd))
    assert given.resolution["source"] == "preset os1-128"
    assert given.resolution["res_h_deg"] == pytest.approx(360 / 1024, abs=1e-12)
