#!/usr/bin/env python3
"""Detect markers in a scan and show the cloud, the corners and the pose frames in Open3D.

    PYTHONPATH=build/python python3 examples/open3d_detect.py \
        data/sample/mid40_tag_wall.pcd --map data/sample/mid40_tag_wall_map.yaml [--sensor mid40]

Without --sensor the image resolution is estimated from the cloud. --out scene.ply writes the
coloured cloud with the marker corners (red) instead of opening a window (no display needed).
Needs Open3D (Debian: apt install python3-open3d); iilfm itself does not.
"""

import argparse
import sys

import numpy as np

import iilfm

OUTLINE = [1.0, 0.5, 0.0]
CORNER = [1.0, 0.1, 0.1]


def build_geometries(o3d, cloud, result):
    """Open3D geometries of a detection, in the world frame when the result has a pose:
    the cloud (gray by intensity), each marker's outline, corner spheres and axes (when its size
    is known), the LiDAR's axes and, with a pose, the world's. Returns (name, geometry) pairs."""
    to_world = result.pose.T_world_lidar if result.pose is not None else np.eye(4)
    points = o3d.geometry.PointCloud()
    points.points = o3d.utility.Vector3dVector(np.column_stack([cloud.x, cloud.y, cloud.z]))
    gray = np.clip(cloud.intensity / max(result.threshold * 2, 1e-6), 0, 1)
    points.colors = o3d.utility.Vector3dVector(np.column_stack([gray, gray, gray]))
    shown = [("cloud", points.transform(to_world))]

    for m in result.markers:
        corners = m.corners_lidar[~np.isnan(m.corners_lidar).any(axis=1)]  # NaN: not recovered
        name = f"{m.family}/{m.id}"
        outline = o3d.geometry.LineSet(
            points=o3d.utility.Vector3dVector(corners),
            lines=o3d.utility.Vector2iVector([[k, (k + 1) % len(corners)]
                                              for k in range(len(corners))]))
        outline.paint_uniform_color(OUTLINE)
        shown.append((f"{name} outline", outline.transform(to_world)))
        for k, corner in enumerate(corners):
            dot = o3d.geometry.TriangleMesh.create_sphere(radius=0.01).translate(corner)
            dot.paint_uniform_color(CORNER)
            shown.append((f"{name} corner {k + 1}", dot.transform(to_world)))
        if m.T_lidar_marker is not None:
            size = np.linalg.norm(corners[1] - corners[0]) if len(corners) > 1 else 0.1
            axes = o3d.geometry.TriangleMesh.create_coordinate_frame(size=size / 2)
            shown.append((f"{name} axes", axes.transform(to_world @ m.T_lidar_marker)))
    lidar = o3d.geometry.TriangleMesh.create_coordinate_frame(size=0.5)
    shown.append(("LiDAR axes", lidar.transform(to_world)))
    if result.pose is not None:
        shown.append(("world axes", o3d.geometry.TriangleMesh.create_coordinate_frame(size=1.0)))
    return shown


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cloud", help="point cloud file (.pcd, .bin, .ply, .txt)")
    parser.add_argument("--sensor", help="sensor preset (iilfm sensors); default: estimated")
    parser.add_argument("--map", help="marker map YAML: shows the scene in the world frame")
    parser.add_argument("--marker-size", type=float, help="marker size (m) for marker axes")
    parser.add_argument("--out", help="write the cloud and corners as a PLY instead of showing")
    args = parser.parse_args()

    try:
        import open3d as o3d
    except ImportError:
        sys.exit("this example needs Open3D: apt install python3-open3d (or pip install open3d); "
                 "`iilfm detect SCAN --html report.html` shows the same in a browser")

    cloud = iilfm.read_cloud(args.cloud)
    pipeline = iilfm.Pipeline(sensor=args.sensor, map=args.map, marker_size=args.marker_size)
    result = pipeline.detect(cloud)  # reads the cloud's columns in place
    print(f"{len(result.markers)} marker(s):",
          ", ".join(f"{m.family}/{m.id}" for m in result.markers))
    if result.pose is not None:
        print("LiDAR in the world: xyz", np.round(result.pose.xyz, 4), "rpy (deg)",
              np.round(result.pose.rpy_deg, 3))
    shown = build_geometries(o3d, cloud, result)
    if args.out:
        # The cloud with a red point at each corner: one file any viewer opens.
        scene = o3d.geometry.PointCloud(shown[0][1])
        for name, geometry in shown:
            if name.endswith("outline"):
                corners = o3d.geometry.PointCloud(geometry.points)
                corners.paint_uniform_color(CORNER)
                scene += corners
        if not o3d.io.write_point_cloud(args.out, scene):
            sys.exit(f"{args.out}: cannot write")
        print(f"wrote {args.out}")
        return
    o3d.visualization.draw_geometries([g for _, g in shown], window_name="iilfm detections")


if __name__ == "__main__":
    main()
