"""iilfm: LiDAR fiducial markers from intensity images.

Read a cloud (or hand over numpy points), run a Pipeline, get corners and poses as numpy arrays::

    import iilfm
    cloud = iilfm.read_cloud("data/sample/mid40_tag_wall.pcd")
    pipeline = iilfm.Pipeline(sensor="mid40", map="data/sample/mid40_tag_wall_map.yaml")
    result = pipeline.detect(cloud)          # or an (N, 4) float32 array, or a dict of columns
    for m in result.markers:
        print(m.family, m.id, m.corners_lidar)
    print(result.pose.T_world_lidar)

Options, messages and results match the `iilfm` program's (`iilfm detect --json`); see
docs/python.md.
"""

from ._iilfm import (  # noqa: F401
    Cloud,
    FrameReader,
    InputError,
    Marker,
    Pipeline,
    Pose,
    Result,
    opencv_threads,
    read_cloud,
    read_frames,
    set_opencv_threads,
    simulate,
)

__all__ = [
    "Cloud",
    "FrameReader",
    "InputError",
    "Marker",
    "Pipeline",
    "Pose",
    "Result",
    "opencv_threads",
    "read_cloud",
    "read_frames",
    "set_opencv_threads",
    "simulate",
]
