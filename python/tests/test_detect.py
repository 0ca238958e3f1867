"""Pipeline.detect gives what `iilfm detect --json` gives, from every accepted input layout."""

import numpy as np
import pytest

import iilfm


def assert_same_as_cli(result, cli):
    got = result.to_json()
    assert [(m["family"], m["id"]) for m in got["markers"]] == \
        [(m["family"], m["id"]) for m in cli["markers"]]
    for mine, theirs in zip(got["markers"], cli["markers"]):
        np.testing.assert_allclose(mine["corners_px"], theirs["corners_px"], rtol=0, atol=1e-9)
        np.testing.assert_allclose(mine["corners_lidar"], theirs["corners_lidar"], rtol=0,
                                   atol=1e-9)
        assert mine["observed"] == theirs["observed"]
        np.testing.assert_allclose(mine["T_lidar_marker"], theirs["T_lidar_marker"], rtol=0,
                                   atol=1e-9)
    np.testing.assert_allclose(got["pose"]["T_world_lidar"], cli["pose"]["T_world_lidar"],
                               rtol=0, atol=1e-9)
    assert got["pose"]["markers_used"] == cli["pose"]["markers_used"]
    assert got["image"] == cli["image"]
    # The numpy arrays hold the unrounded values the JSON rounds (1e-4 px, 1e-6 m).
    for m, theirs in zip(result.markers, cli["markers"]):
        np.testing.assert_allclose(m.corners_px, theirs["corners_px"], rtol=0, atol=0.6e-4)
        np.testing.assert_allclose(m.corners_lidar, theirs["corners_lidar"], rtol=0, atol=0.6e-6)
        assert m.corners_px.shape == (4, 2) and m.corners_lidar.shape == (4, 3)
        assert m.T_lidar_marker.shape == (4, 4)
        assert m.turn_known and "turn_about_normal_known" not in theirs  # a square's turn is seen
        # The plane lift's plane, as the JSON reports it (surround_scale 3: the grid's wall).
        np.testing.assert_allclose(m.plane["normal"], theirs["plane"]["normal"], atol=0.6e-7)
        assert abs(m.plane["d"] - theirs["plane"]["d_m"]) <= 0.6e-6
        assert m.plane["points"] == theirs["plane"]["points"]
        assert m.plane["surround_scale"] == theirs["plane"]["surround_scale"]
    np.testing.assert_allclose(result.pose.T_world_lidar, cli["pose"]["T_world_lidar"], atol=1e-9)


@pytest.fixture(scope="module")
def pipeline(scan):
    return iilfm.Pipeline(sensor="mid40", map=scan["map"])


def test_cloud_from_file_matches_the_cli(scan, pipeline):
    assert len(scan["json"]["markers"]) >= 10  # many of the grid's 35 tags
    cloud = iilfm.read_cloud(scan["pcd"])
    result = pipeline.detect(cloud)
    assert_same_as_cli(result, scan["json"])
    assert result.input["copied"] is False
    assert result.input["path"] == scan["pcd"]
    assert result.to_json()["input"]["points"] == scan["json"]["input"]["points"]


@pytest.mark.parametrize("layout", ["c", "fortran", "wide", "columns", "float64", "columns64"])
def test_every_layout_matches_the_cli(scan, pipeline, layout):
    xyzi = iilfm.read_cloud(scan["pcd"]).xyzi()
    points = {
        "c": xyzi,
        "fortran": np.asfortranarray(xyzi),
        "wide": np.hstack([xyzi, np.ones((len(xyzi), 2), np.float32)]),
        "columns": {"x": xyzi[:, 0].copy(), "y": xyzi[:, 1].copy(), "z": xyzi[:, 2].copy(),
                    "intensity": xyzi[:, 3].copy()},
        "float64": xyzi.astype(np.float64),
        "columns64": {k: xyzi[:, i].astype(np.float64) for i, k in
                      enumerate(["x", "y", "z", "intensity"])},
    }[layout]
    result = pipeline.detect(points)
    assert_same_as_cli(result, scan["json"])
    assert result.input["copied"] is layout.endswith("64")


def address(a):
    return a.__array_interface__["data"][0]


def test_float32_rows_are_read_in_place(scan, pipeline):
    xyzi = iilfm.read_cloud(scan["pcd"]).xyzi()
    assert xyzi.flags.c_contiguous and xyzi.dtype == np.float32
    result = pipeline.detect(xyzi)
    assert result.input["copied"] is False
    assert pipeline._last_x_address() == address(xyzi)
    # Any float32 strides: a column-major array and every other row of a wider one.
    fortran = np.asfortranarray(xyzi)
    pipeline.detect(fortran)
    assert pipeline._last_x_address() == address(fortran)
    wide = np.zeros((2 * len(xyzi), 6), np.float32)
    wide[::2, :4] = xyzi
    every_other = wide[::2]
    result = pipeline.detect(every_other)
    assert result.input["copied"] is False
    assert pipeline._last_x_address() == address(wide)
    # Columns and clouds from read_cloud too; a float64 array is converted once.
    columns = {k: np.ascontiguousarray(xyzi[:, i]) for i, k in
               enumerate(["x", "y", "z", "intensity"])}
    pipeline.detect(columns)
    assert pipeline._last_x_address() == address(columns["x"])
    cloud = iilfm.read_cloud(scan["pcd"])
    pipeline.detect(cloud)
    assert pipeline._last_x_address() == address(cloud.x)
    as64 = xyzi.astype(np.float64)
    assert pipeline.detect(as64).input["copied"] is True
    assert pipeline._last_x_address() != address(as64)


def test_invalid_points_are_skipped_and_counted(scan, pipeline):
    xyzi = iilfm.read_cloud(scan["pcd"]).xyzi()
    bad = np.array([[np.nan, 1, 1, 5], [0, 0, 0, 9], [1, np.inf, 1, 5], [1, 1, 1, np.nan]],
                   np.float32)
    mixed = np.vstack([bad[:2], xyzi[:1000], bad[2:], xyzi[1000:]])
    result = pipeline.detect(mixed)
    assert result.input["copied"] is True
    assert (result.input["points"], result.input["valid_points"]) == (len(mixed), len(xyzi))
    assert (result.input["non_finite"], result.input["zero"]) == (3, 1)
    assert_same_as_cli(result, scan["json"])
    # The index image names rows of the caller's array, not of the internal copy.
    index = result.index_image
    rows = index[index >= 0]
    assert rows.min() >= 2 and not np.isin(rows, [0, 1, 1002, 1003]).any()
    clean = pipeline.detect(xyzi).index_image
    expected = np.where(clean >= 1000, clean + 4, np.where(clean >= 0, clean + 2, -1))
    np.testing.assert_array_equal(index, expected)


def test_images_are_arrays(scan, pipeline):
    result = pipeline.detect(iilfm.read_cloud(scan["pcd"]))
    h, w = scan["json"]["image"]["height"], scan["json"]["image"]["width"]
    for name, dtype in [("intensity_image", np.float32), ("range_image", np.float32),
                        ("mask", np.uint8), ("index_image", np.int32), ("gray_image", np.uint8),
                        ("detect_image", np.uint8)]:
        image = getattr(result, name)
        assert image.shape == (h, w) and image.dtype == dtype, name
    assert (result.mask > 0).sum() == scan["json"]["image"]["observed_pixels"]
    # The range at an observed corner pixel is that corner's distance (2 cm noise, mean of hits).
    m = result.markers[0]
    for (u, v), p, seen in zip(m.corners_px, m.corners_lidar, m.observed):
        if seen:
            assert abs(result.range_image[round(v), round(u)] - np.linalg.norm(p)) < 0.1
    overlay = result.overlay()
    assert overlay.ndim == 3 and overlay.shape[2] == 3 and overlay.shape[1] >= w
    # Images survive the next detect() (the pipeline reuses its buffers).
    before = result.intensity_image.copy()
    pipeline.detect(iilfm.read_cloud(scan["pcd"]).xyzi()[::3].copy())
    np.testing.assert_array_equal(result.intensity_image, before)


def test_pose_and_marker_values(scan, pipeline):
    result = pipeline.detect(iilfm.read_cloud(scan["pcd"]))
    pose = result.pose
    cli = scan["json"]["pose"]
    np.testing.assert_allclose(pose.xyz, cli["xyz"], atol=1e-6)
    np.testing.assert_allclose(pose.quat_xyzw, cli["quat_xyzw"], atol=1e-6)
    np.testing.assert_allclose(pose.rpy_deg, cli["rpy_deg"], atol=1e-5)
    assert pose.rms == pytest.approx(cli["rms_m"], abs=1e-6)
    # T_world_lidar maps each marker's lifted corners onto its map corners (within the rms).
    T = pose.T_world_lidar
    assert np.allclose(T[3], [0, 0, 0, 1]) and np.allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3))
    assert result.pose_missing_reason == ""
    no_map = iilfm.Pipeline(sensor="mid40").detect(iilfm.read_cloud(scan["pcd"]))
    assert no_map.pose is None and no_map.pose_missing_reason == "no marker map given"
    assert all(m.T_lidar_marker is None for m in no_map.markers)


def test_paths_and_the_html_report(scan, pipeline, tmp_path):
    from pathlib import Path
    result = pipeline.detect(iilfm.read_cloud(Path(scan["pcd"])))
    page = tmp_path / "report.html"
    result.write_html(page, title="python <report>", max_points=5000)
    text = page.read_text()
    assert text.startswith("<!doctype html>") and "<title>python &lt;report&gt;</title>" in text
    import json
    import re
    data = json.loads(re.search(r'<script id="iilfm-data" type="application/json">(.*?)</script>',
                                text, re.S).group(1).replace("<\\/", "</"))
    frame = data["frames"][0]
    assert [m["id"] for m in frame["markers"]] == [m["id"] for m in scan["json"]["markers"]]
    assert frame["cloud"]["shown"] <= 5000 and frame["cloud"]["total"] == len(
        iilfm.read_cloud(scan["pcd"]))
    assert "Three.js Authors" in text  # the MIT notice stays in the bundle
    assert frame["overlay_image"].startswith("data:image/jpeg;base64,")


def test_ring_decoding_options_reach_the_pipeline():
    """A 1 m tag36h11 4.5 m from a VLP-16 is beyond what the detectors read (7 rings for its 8 cell
    rows); the ring candidates (on by default) decode it from the rings (docs/pipeline.md,
    "Ring-sample decoding"), and ring_decode=False turns the whole stage off."""
    cloud, _ = iilfm.simulate(sensor="vlp16", marker_size=1.0, distance=4.5, seed=1,
                              footprint=True, lidar_rpy=[0, -0.8, 0.5])
    def ids(**options):
        return [m.id for m in iilfm.Pipeline("vlp16", **options).detect(cloud).markers]
    assert ids() == [0]
    assert ids(ring_candidates=False) == []
    assert ids(ring_decode=False) == []


def test_search_regions_find_the_markers_of_the_whole_image():
    """AprilTag and ArUco search only around quad-shaped boundaries by default
    (docs/detectors.md, "Search regions"); search_regions=False searches every pixel. Same markers,
    corners within libapriltag's rounding; by default a region of large outlines (the VLP-16's 60
    cm tag, over 6 pixels a cell) has its quads found at half resolution, which moves corners by
    up to a quarter pixel (measured 0.2), and half_resolution=False finds them at full resolution."""
    for sensor, size, frames in (("vlp16", 0.6, 1), ("mid40", 0.172, 10)):
        cloud, _ = iilfm.simulate(sensor=sensor, seed=2, frames=frames, marker_size=size,
                                  distance=2.0)
        def corners(**options):
            markers = iilfm.Pipeline(sensor, marker_size=size, **options).detect(cloud).markers
            assert [m.id for m in markers] == [0], (sensor, options)
            return np.asarray(markers[0].corners_px)
        whole = corners(search_regions=False)
        assert np.abs(corners(half_resolution=False) - whole).max() < 0.15, sensor
        assert np.abs(corners() - whole).max() < 0.25, sensor


def test_gray_decode_reads_a_small_far_ouster_marker():
    """A 40 cm tag36h11 5 m from an OS1-128 in 1024-column mode has cells 1.6 pixels wide: the
    binary image loses its code, AprilTag on the search region's gray pixels reads it
    (docs/detectors.md, "Gray pixels where the binary ones decode nothing"); gray_decode=False is
    the binary image alone. (The simulated OS1-128 runs 2048 columns: res_h sets 1024.)"""
    cloud, _ = iilfm.simulate(sensor="os1-128", marker_size=0.4, distance=5.0, seed=2,
                              footprint=True, lidar_rpy=[0, 0.912, 1.791])
    def ids(**options):
        pipeline = iilfm.Pipeline("os1-128", res_h=360 / 1024, **options)
        return [m.id for m in pipeline.detect(cloud).markers]
    assert ids() == [0]
    assert ids(gray_decode=False) == []


def test_a_ring_marker_alone_has_a_pose_whose_turn_is_a_convention():
    """A ring marker's code is the same at every turn: its centre and the fitted plane give its
    pose, y taken as the LiDAR's up seen in the face (docs/detectors.md)."""
    cloud, truth = iilfm.simulate(sensor="mid40", seed=1, distance=2.0, family="rings:ring9h3",
                                  id=5, marker_size=0.3)
    markers = iilfm.Pipeline("mid40", ["rings:ring9h3"], marker_size=0.3).detect(cloud).markers
    assert [m.id for m in markers] == [5]
    assert not markers[0].turn_known
    estimated, true = markers[0].T_lidar_marker, np.array(truth["markers"][0]["T_lidar_marker"])
    assert np.linalg.norm(estimated[:3, 3] - true[:3, 3]) < 0.005
    # The face normal within half a degree; an upright marker seen by a level LiDAR also has
    # the conventional turn right.
    assert np.degrees(np.arccos(np.clip(estimated[:3, 2] @ true[:3, 2], -1, 1))) < 0.5
    assert estimated[:3, 1] @ true[:3, 1] > np.cos(np.radians(0.5))


def test_ids_report_only_the_markers_given(scan):
    everything = iilfm.Pipeline(sensor="mid40").detect(iilfm.read_cloud(scan["pcd"]))
    found = sorted(m.id for m in everything.markers)
    assert len(found) >= 10
    wanted = [found[0], found[3], 34 if found[-1] != 34 else 33]
    some = iilfm.Pipeline(sensor="mid40", ids=wanted).detect(iilfm.read_cloud(scan["pcd"]))
    assert sorted(m.id for m in some.markers) == sorted(set(wanted) & set(found))
    assert some.markers_not_reported == len(found) - len(some.markers)
    assert some.to_json()["markers_not_reported"] == some.markers_not_reported
    assert everything.markers_not_reported == 0
    assert everything.detections_not_square == 0  # a printed marker lifts to a square
    with pytest.raises(iilfm.InputError, match="marker id 600 is not in apriltag:tag36h11"):
        iilfm.Pipeline(sensor="mid40", ids=[0, 600])


def test_the_measured_size_is_the_black_squares_edge():
    """Each marker's four lifted corners measure its size (the nearest square's edge); a size
    given a quarter too large (the whole tag36h11 with its white margin) is flagged."""
    cloud, _ = iilfm.simulate(sensor="mid40", seed=1, distance=2.0, marker_size=0.172)
    right = iilfm.Pipeline("mid40", marker_size=0.172).detect(cloud).markers
    assert [m.id for m in right] == [0]
    assert abs(right[0].measured_size - 0.172) < 0.002
    assert right[0].square_rms < 0.002
    assert not right[0].size_disagrees
    wrong = iilfm.Pipeline("mid40", marker_size=0.215).detect(cloud)
    assert wrong.markers[0].size_disagrees
    assert wrong.to_json()["markers"][0]["size_disagrees"] is True
    # square_check=False (--no-square-check) keeps every detection; the printed tag is kept either way.
    unchecked = iilfm.Pipeline("mid40", marker_size=0.172, square_check=False).detect(cloud)
    assert [m.id for m in unchecked.markers] == [0]
    assert unchecked.detections_not_square == 0
