#!/usr/bin/env python3
"""Detect markers in a scan and show the cloud, the corners and the pose frames in Open3D.

    PYTHONPATH=build/python python3 examples/open3d_detect.py \
        data/sample/mid40_tag_wall.pcd --sensor mid40 --map data/sample/mid40_tag_wall_map.yaml

Needs Open3D (Debian: apt install python3-open3d); iilfm itself does not.
"""

import argparse
import sys

import numpy as np

import iilfm


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cloud", help="point cloud file (.pcd, .bin)")
    parser.add_argument("--sensor", default="mid40", help="sensor preset (iilfm sensors)")
    parser.add_argument("--map", help="marker map YAML: shows the scene in the world frame")
    parser.add_argument("--marker-size", type=float, help="marker size (m) for marker axes")
    args = parser.parse_args()

    try:
        import open3d as o3d
    except ImportError:
        sys.exit("this example needs Open3D: apt install python3-open3d (or pip install open3d)")

    cloud = iilfm.read_cloud(args.cloud)
    pipeline = iilfm.Pipeline(sensor=args.sensor, map=args.map, marker_size=args.marker_size)
    result = pipeline.detect(cloud)  # reads the cloud's columns in place
    print(f"{len(result.markers)} marker(s):", ", ".join(f"{m.family}/{m.id}" for m in result.markers))

    # Everything is in the LiDAR frame; with a pose, move it into the world.
    to_world = result.pose.T_world_lidar if result.pose is not None else np.eye(4)
    points = o3d.geometry.PointCloud()
    points.points = o3d.utility.Vector3dVector(np.column_stack([cloud.x, cloud.y, cloud.z]))
    gray = np.clip(cloud.intensity / max(result.threshold * 2, 1e-6), 0, 1)
    points.colors = o3d.utility.Vector3dVector(np.column_stack([gray, gray, gray]))
    points.transform(to_world)
    shown = [points]

    for m in result.markers:
        corners = m.corners_lidar[~np.isnan(m.corners_lidar).any(axis=1)]
        outline = o3d.geometry.LineSet(
            points=o3d.utility.Vector3dVector(corners),
            lines=o3d.utility.Vector2iVector([[k, (k + 1) % len(corners)] for k in range(len(corners))]))
        outline.paint_uniform_color([1.0, 0.5, 0.0])
        shown.append(outline.transform(to_world))
        for corner in corners:
            dot = o3d.geometry.TriangleMesh.create_sphere(radius=0.01).translate(corner)
            shown.append(dot.transform(to_world))
        if m.T_lidar_marker is not None:
            size = np.linalg.norm(corners[1] - corners[0]) if len(corners) > 1 else 0.1
            axes = o3d.geometry.TriangleMesh.create_coordinate_frame(size=size / 2)
            shown.append(axes.transform(to_world @ m.T_lidar_marker))
    lidar = o3d.geometry.TriangleMesh.create_coordinate_frame(size=0.5)
    shown.append(lidar.transform(to_world))
    if result.pose is not None:
        print("LiDAR in the world: xyz", np.round(result.pose.xyz, 4), "rpy (deg)",
              np.round(result.pose.rpy_deg, 3))
        shown.append(o3d.geometry.TriangleMesh.create_coordinate_frame(size=1.0))
    o3d.visualization.draw_geometries(shown, window_name="iilfm detections")


if __name__ == "__main__":
    main()
