#!/usr/bin/env python3
"""Show the intensity image with the detected markers' corners and ids in matplotlib.

    PYTHONPATH=build/python python3 examples/matplotlib_overlay.py \
        data/sample/mid40_tag_wall.pcd [--sensor mid40] [--out overlay.png]

Without --sensor the image resolution is estimated from the cloud. --out saves the figure
(Agg backend, no display needed) instead of showing it.
Needs matplotlib (Debian: apt install python3-matplotlib); iilfm itself does not.
"""

import argparse
import sys

import numpy as np

import iilfm

CORNER_COLORS = ["red", "limegreen", "dodgerblue", "gold"]  # top-left .. bottom-left


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cloud", help="point cloud file (.pcd, .bin, .ply, .txt)")
    parser.add_argument("--sensor", help="sensor preset (iilfm sensors); default: estimated")
    parser.add_argument("--out", help="save the figure here instead of showing it")
    args = parser.parse_args()

    try:
        import matplotlib
        if args.out:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("this example needs matplotlib: apt install python3-matplotlib "
                 "(or pip install matplotlib)")

    result = iilfm.Pipeline(sensor=args.sensor).detect(iilfm.read_cloud(args.cloud))
    print(f"{len(result.markers)} marker(s):", " ".join(str(m.id) for m in result.markers))
    image = result.gray_image
    geometry = result.image
    # Pixels are res_h x res_v degrees: stretch so a marker looks square.
    aspect = geometry["res_v_deg"] / geometry["res_h_deg"]

    fig, ax = plt.subplots(figsize=(10, 10 * image.shape[0] * aspect / image.shape[1]))
    ax.imshow(np.ma.masked_where(result.mask == 0, image), cmap="gray", aspect=aspect,
              interpolation="nearest")
    for m in result.markers:
        u, v = m.corners_px[:, 0], m.corners_px[:, 1]  # pixel centres at integers, as imshow
        ax.plot(np.append(u, u[0]), np.append(v, v[0]), color="orange", linewidth=1.5)
        ax.scatter(u, v, c=CORNER_COLORS[:len(u)], s=25, zorder=3)
        ax.text(u.mean(), v.mean(), f"#{m.id}", color="red", ha="center", va="center",
                fontsize=12, fontweight="bold")
    ax.set_title(f"{len(result.markers)} marker(s); threshold {result.threshold:g}")
    ax.set_xlabel("column (azimuth)")
    ax.set_ylabel("row (elevation)")
    if args.out:
        fig.savefig(args.out, dpi=120, bbox_inches="tight")
        print(f"wrote {args.out}")
    else:
        plt.show()


if __name__ == "__main__":
    main()
