"""Type stubs of the iilfm extension module (python/src/*.cpp). Keep in step with the bindings."""

from os import PathLike
from typing import Iterable, Mapping, Sequence, Union

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
Points = Union["Cloud", npt.ArrayLike, Mapping[str, npt.ArrayLike]]

class InputError(ValueError):
    """Bad input: the message is what the `iilfm` program prints after "iilfm: "."""

class Cloud:
    """A point cloud owned by iilfm; columns are read-only numpy views (no copy)."""

    def __len__(self) -> int: ...
    @property
    def x(self) -> npt.NDArray[np.float32]: ...
    @property
    def y(self) -> npt.NDArray[np.float32]: ...
    @property
    def z(self) -> npt.NDArray[np.float32]: ...
    @property
    def intensity(self) -> npt.NDArray[np.float32]: ...
    @property
    def ring(self) -> npt.NDArray[np.uint16] | None: ...
    @property
    def time(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def stats(self) -> dict[str, int]:
        """points_in_file, valid_points, non_finite, zero."""
    @property
    def path(self) -> str:
        """The file it was read from, 'rec.bag:/topic#12' for a recording's frame, '' if simulated."""
    @property
    def stamp(self) -> float | None:
        """A recording's frame (read_frames): when it was taken, in seconds; else None."""
    def xyzi(self) -> npt.NDArray[np.float32]:
        """A new (N, 4) float32 array of x, y, z, intensity."""

class FrameReader:
    """The frames of a recording in time order; iterate for Clouds (with stamp and path)."""

    def __iter__(self) -> FrameReader: ...
    def __next__(self) -> Cloud: ...
    def __len__(self) -> int: ...
    @property
    def name(self) -> str: ...

class Marker:
    """One detected marker."""

    @property
    def family(self) -> str: ...
    @property
    def id(self) -> int: ...
    @property
    def corners_px(self) -> FloatArray:
        """(K, 2) sub-pixel corners: top-left, top-right, bottom-right, bottom-left."""
    @property
    def corners_lidar(self) -> FloatArray:
        """(K, 3) corners in the LiDAR frame, metres; NaN rows where not recoverable."""
    @property
    def observed(self) -> npt.NDArray[np.bool_]: ...
    @property
    def T_lidar_marker(self) -> FloatArray | None:
        """(4, 4) marker pose in the LiDAR frame, or None when the size is unknown."""
    @property
    def marker_fit_rms(self) -> float: ...
    @property
    def measured_size(self) -> float:
        """Edge of the nearest square to the four lifted corners, metres (NaN when not measured)."""
    @property
    def square_rms(self) -> float:
        """How far the lifted corners were from that square, metres (NaN when not measured)."""
    @property
    def size_disagrees(self) -> bool:
        """The measured size differs from the known one by more than its error allows."""
    @property
    def hamming(self) -> int: ...
    @property
    def decision_margin(self) -> float: ...
    @property
    def in_map(self) -> bool: ...
    @property
    def coverage(self) -> float:
        """Share of the marker's image pixels holding a point (before hole filling)."""

class Pose:
    """The LiDAR's pose in the world."""

    @property
    def T_world_lidar(self) -> FloatArray:
        """(4, 4): maps LiDAR points into the world."""
    @property
    def xyz(self) -> FloatArray: ...
    @property
    def quat_xyzw(self) -> FloatArray: ...
    @property
    def rpy_deg(self) -> FloatArray: ...
    @property
    def rms(self) -> float: ...
    @property
    def markers_used(self) -> list[str]: ...
    @property
    def markers_rejected(self) -> list[tuple[str, float]]: ...
    @property
    def corners_used(self) -> int: ...

class Result:
    """What Pipeline.detect found in one frame."""

    @property
    def markers(self) -> list[Marker]: ...
    @property
    def pose(self) -> Pose | None: ...
    @property
    def pose_missing_reason(self) -> str: ...
    @property
    def markers_not_reported(self) -> int:
        """Markers found whose ids were not among the ids= given (left out of markers)."""
    @property
    def detections_not_square(self) -> int:
        """Detections dropped because their lifted corners are no square (chance matches)."""
    @property
    def intensity_image(self) -> npt.NDArray[np.float32]: ...
    @property
    def range_image(self) -> npt.NDArray[np.float32]: ...
    @property
    def mask(self) -> npt.NDArray[np.uint8]: ...
    @property
    def column_offset_image(self) -> npt.NDArray[np.float32] | None:
        """Where each single-point pixel's sample lies, in columns right of its centre.

        0 for other pixels; None when every ring lies on the column grid, and for uniform rows.
        """
    @property
    def index_image(self) -> npt.NDArray[np.int32]: ...
    @property
    def gray_image(self) -> npt.NDArray[np.uint8]: ...
    @property
    def detect_image(self) -> npt.NDArray[np.uint8]: ...
    @property
    def threshold(self) -> float: ...
    @property
    def image(self) -> dict[str, float]: ...
    @property
    def timing_ms(self) -> dict[str, float]: ...
    @property
    def input(self) -> dict[str, object]:
        """path, points, valid_points, non_finite, zero, copied."""
    def to_json(self) -> dict[str, object]:
        """The result as `iilfm detect --json` writes it."""
    def overlay(self) -> npt.NDArray[np.uint8]:
        """(H, W, 3) RGB picture of the intensity image with the detections."""
    def write_html(self, path: str | PathLike[str], title: str = ...,
                   max_points: int = ...) -> None:
        """Writes the self-contained HTML report of this frame (as `iilfm detect --html`)."""

class Pipeline:
    """Projection, preprocessing, detection, lifting, pose; options mirror `iilfm detect`.

    Without sensor or both res_h and res_v, the resolution is estimated from the first cloud.
    """

    def __init__(
        self,
        sensor: str | None = None,
        markers: Sequence[str] = ...,
        map: str | PathLike[str] | None = None,
        *,
        res_h: float | None = None,
        res_v: float | None = None,
        marker_size: float | None = None,
        ids: Sequence[int] | None = None,
        threshold: float | str | None = None,
        lift: str = "plane",
        collision: str = "mean",
        blur: float = 0.0,
        gray: bool = False,
        decimate: float = 1.0,
        quad_sigma: float = 0.0,
        refine_edges: bool = True,
        threads: int = 1,
        max_hamming: int = -1,
        aruco_refine: str = "contour",
        aruco_window_min: int = 3,
        aruco_window_max: int = 23,
        aruco_window_step: int = 10,
        pose_refine: str = "none",
        normalise_intensity: str = "",
        ring_decode: bool = True,
        ring_candidates: bool = True,
        search_regions: bool = True,
        gray_decode: bool = True,
        half_resolution: bool = True,
        square_check: bool = True,
    ) -> None: ...
    def detect(self, points: Points) -> Result:
        """Runs every stage on one frame; float32 points are read in place."""
    def detect_frames(self, frames: Iterable[Points], window: int = 1) -> list[Result]:
        """A recording: one Result per frame, or per sliding window of `window` frames."""
    @property
    def resolution(self) -> dict[str, object] | None:
        """res_h_deg, res_v_deg, rows, source[, rings]; None until estimated."""
    def _last_x_address(self) -> int: ...

def read_cloud(path: str | PathLike[str]) -> Cloud:
    """Reads a .pcd or KITTI .bin file (NaN/Inf and zero points skipped, counted in stats)."""

def read_frames(path: str | PathLike[str], topic: str | None = None) -> FrameReader:
    """A bag's topic (.bag, ROS 2 folder or .db3, .mcap; default its only point cloud topic) or a
    folder of cloud files, frame by frame."""

def set_opencv_threads(threads: int) -> None:
    """Threads for OpenCV's own parallel loops in this process (`iilfm` sets its --threads)."""

def opencv_threads() -> int:
    """Threads OpenCV's parallel loops may use in this process."""

def simulate(
    *,
    scene: str = "tag-wall",
    scene_file: str | PathLike[str] | None = None,
    sensor: str | None = None,
    frames: int | None = None,
    seed: int = 1,
    family: str | None = None,
    id: int | None = None,
    marker_size: float | None = None,
    distance: float | None = None,
    range_sigma: float | None = None,
    intensity_sigma: float | None = None,
    angle_sigma: float = 0.0,
    footprint: bool = False,
    footprint_samples: int = 5,
    dark_dropout: float = 0.0,
    invalid_fraction: float = 0.0,
    invalid_as: str = "nan",
    min_range: float | None = None,
    lidar_xyz: Sequence[float] | None = None,
    lidar_rpy: Sequence[float] | None = None,
    out: str | PathLike[str] | None = None,
    map: str | PathLike[str] | None = None,
    truth: str | PathLike[str] | None = None,
    intensity_model: str = "sensor",
) -> tuple[Cloud, dict[str, object]]:
    """Simulates a scan as `iilfm sim` does; returns (cloud, ground truth)."""
