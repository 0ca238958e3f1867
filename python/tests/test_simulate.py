"""iilfm.simulate is `iilfm sim`: same scan for the same seed, ground truth that detection meets."""

import numpy as np
import pytest

import iilfm
from conftest import cli_error, run_cli


def test_same_scan_as_the_cli(tmp_path):
    pcd = tmp_path / "cli.pcd"
    run_cli("sim", "--scene", "tag-wall", "--frames", "5", "--seed", "11", "--out", pcd)
    cloud, truth = iilfm.simulate(scene="tag-wall", frames=5, seed=11)
    from_cli = iilfm.read_cloud(str(pcd))
    assert len(cloud) == len(from_cli) > 10000
    for column in ["x", "y", "z", "intensity"]:
        np.testing.assert_array_equal(getattr(cloud, column), getattr(from_cli, column))
    assert cloud.time is not None and len(cloud.time) == len(cloud)
    assert truth["sensor"] == "mid40" and truth["frames"] == 5 and truth["seed"] == 11


def test_detection_meets_the_ground_truth(tmp_path):
    marker_map = tmp_path / "map.yaml"
    cloud, truth = iilfm.simulate(scene="tag-wall", frames=20, seed=5, map=str(marker_map))
    assert marker_map.exists()
    result = iilfm.Pipeline(sensor="mid40", map=str(marker_map)).detect(cloud)
    assert [m.id for m in result.markers] == [0]
    true_corners = truth["markers"][0]["corners_lidar"]
    assert true_corners.shape == (4, 3)
    assert np.abs(result.markers[0].corners_lidar - true_corners).max() < 0.01
    assert np.linalg.norm(result.pose.xyz - truth["T_world_lidar"][:3, 3]) < 0.02


def test_bad_options_raise_the_cli_message():
    with pytest.raises(iilfm.InputError) as e:
        iilfm.simulate(scene="moon")
    assert str(e.value) == cli_error("sim", "--scene", "moon", "--out", "/tmp/never.pcd")
    with pytest.raises(iilfm.InputError) as e:
        iilfm.simulate(frames=0)
    assert str(e.value) == cli_error("sim", "--frames", "0", "--out", "/tmp/never.pcd")


def test_cloud_columns_are_read_only_views_that_keep_the_cloud_alive():
    cloud, _ = iilfm.simulate(frames=1, seed=2)
    x = cloud.x
    assert not x.flags.writeable and x.dtype == np.float32
    first = float(x[0])
    del cloud
    assert float(x[0]) == first
    with pytest.raises(ValueError):
        x[0] = 1.0


def test_preset_threshold_above_a_unit_scale_cloud_is_replaced_but_a_given_one_is_kept(tmp_path):
    # A VLP-16 sweep with its intensity scaled to 0..1 (KITTI's reflectance) against the
    # preset's threshold of 40.
    marker_map = tmp_path / "map.yaml"
    cloud, _ = iilfm.simulate(scene="tag-wall", sensor="vlp16", marker_size=0.6, distance=2,
                              map=str(marker_map))
    xyzi = cloud.xyzi().copy()
    xyzi[:, 3] /= 255.0
    result = iilfm.Pipeline(sensor="vlp16", map=str(marker_map)).detect(xyzi)
    assert [m.id for m in result.markers] == [0]
    image = result.to_json()["image"]
    assert image["threshold_replaced"]["given"] == 40
    assert image["threshold"] < 1
    kept = iilfm.Pipeline(sensor="vlp16", map=str(marker_map), threshold=40).detect(xyzi)
    assert kept.markers == [] and kept.threshold == 40
    assert "threshold_replaced" not in kept.to_json()["image"]


def test_print_above_the_presets_threshold_is_found_at_otsus_unless_the_threshold_is_given(
        tmp_path):
    # The same sweep with every return 50 brighter: ink at about 60, above the preset's 40.
    marker_map = tmp_path / "map.yaml"
    cloud, _ = iilfm.simulate(scene="tag-wall", sensor="vlp16", marker_size=0.6, distance=2,
                              map=str(marker_map))
    xyzi = cloud.xyzi().copy()
    xyzi[:, 3] += 50.0
    result = iilfm.Pipeline(sensor="vlp16", map=str(marker_map)).detect(xyzi)
    assert [m.id for m in result.markers] == [0]
    retry = result.to_json()["image"]["threshold_retry"]
    assert retry["fixed"] == 40 and retry["found"] == 1
    assert result.threshold == pytest.approx(retry["otsu"], abs=1e-3) and result.threshold > 60
    kept = iilfm.Pipeline(sensor="vlp16", map=str(marker_map), threshold=40).detect(xyzi)
    assert kept.markers == [] and kept.threshold == 40
    assert "threshold_retry" not in kept.to_json()["image"]


def test_column_offsets_say_where_rings_fired_off_the_grid():
    # A VLP-16 fires its 16 lasers microseconds apart: each ring's samples lie a ring's own
    # fraction of a column off the grid (docs/simulator.md).
    cloud, _ = iilfm.simulate(scene="tag-wall", sensor="vlp16", distance=3, seed=3)
    pipeline = iilfm.Pipeline(sensor="vlp16")
    result = pipeline.detect(cloud)
    offsets = result.column_offset_image
    assert offsets is not None
    assert offsets.shape == result.mask.shape and offsets.dtype == np.float32
    assert not offsets.flags.writeable
    assert np.all(offsets[result.mask == 0] == 0)
    assert np.abs(offsets).max() <= 0.5
    rows = [row[row != 0] for row in offsets]
    medians = [float(np.median(r)) for r in rows if len(r) > 100]
    assert len(medians) >= 12
    assert max(medians) - min(medians) > 0.2
    # Within a ring the offset is the ring's own (half a column off reads as -0.5 or +0.5).
    for r in rows:
        if len(r) > 100:
            spread = r - np.median(r)
            assert np.percentile(np.abs(spread - np.round(spread)), 90) < 0.01
    # The image belongs to the result: the pipeline's next frame does not change it.
    before = offsets.copy()
    pipeline.detect(iilfm.simulate(scene="tag-wall", sensor="vlp16", distance=5, seed=4)[0])
    np.testing.assert_array_equal(offsets, before)
    # A Livox scan has uniform rows: no offsets.
    cloud, _ = iilfm.simulate(frames=1, seed=2)
    assert iilfm.Pipeline(sensor="mid40").detect(cloud).column_offset_image is None
