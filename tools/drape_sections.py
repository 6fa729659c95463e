#!/usr/bin/env python3
"""Plots plane sections of a draped garment and its body, one panel per colour.

Where a seam stays open or panels start through each other, a few sections show why faster
than a render: which panel lies where, how far from the body, and which edges overshoot.

    tools/drape_sections.py out/tshirt.obj --y 1.2 1.0 --x -0.1 --out sections.png

The body is read from DRAPED.body.obj (as `atelier-cli drape` writes it) unless --body names
it. --y cuts horizontal sections (x across, the front, +z, at the bottom), --x sagittal ones
(z across, the front to the right; y up). Frames written with --frames-dir work too (pass --body). Needs numpy and
matplotlib (Debian: python3-numpy python3-matplotlib).
"""
import argparse
import os
import sys

try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"drape_sections: {e.name} is missing (apt install python3-numpy python3-matplotlib)")


def read_obj(path):
    """Vertices, triangles (fans of polygons) and each triangle's group index; group names."""
    vertices, triangles, groups, names = [], [], [], []
    if not os.path.isfile(path):
        sys.exit(f"drape_sections: {path}: no such file")
    with open(path) as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v":
                vertices.append([float(t) for t in fields[1:4]])
            elif fields[0] in ("g", "o"):
                names.append(fields[1] if len(fields) > 1 else f"group {len(names)}")
            elif fields[0] == "f":
                try:
                    idx = [int(t.split("/")[0]) - 1 for t in fields[1:]]
                except ValueError:
                    sys.exit(f"drape_sections: {path}:{number}: bad face line")
                for k in range(1, len(idx) - 1):
                    triangles.append([idx[0], idx[k], idx[k + 1]])
                    groups.append(max(len(names) - 1, 0))
    if not vertices or not triangles:
        sys.exit(f"drape_sections: {path}: no triangles")
    return np.array(vertices), np.array(triangles), np.array(groups), names or ["mesh"]


def section(vertices, triangles, axis, value):
    """Segments where the plane coordinate[axis] = value cuts the mesh, and their triangles."""
    s = vertices[:, axis] - value
    sides = s[triangles] > 0
    cut = sides.any(axis=1) & ~sides.all(axis=1)
    segments, which = [], []
    for t in np.nonzero(cut)[0]:
        points = []
        for i in range(3):
            p, q = triangles[t, i], triangles[t, (i + 1) % 3]
            if (s[p] > 0) != (s[q] > 0):
                points.append(vertices[p] + s[p] / (s[p] - s[q]) * (vertices[q] - vertices[p]))
        if len(points) == 2:
            segments.append(points)
            which.append(t)
    return np.array(segments).reshape(-1, 2, 3), np.array(which, dtype=int)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("garment")
    parser.add_argument("--body")
    parser.add_argument("--y", type=float, nargs="*", default=[], help="heights [m]")
    parser.add_argument("--x", type=float, nargs="*", default=[], help="sagittal planes [m]")
    parser.add_argument("--out", default="sections.png")
    args = parser.parse_args()
    cuts = [(1, v) for v in args.y] + [(0, v) for v in args.x]
    if not cuts:
        parser.error("give at least one --y or --x")
    body_path = args.body or os.path.splitext(args.garment)[0] + ".body.obj"
    garment = read_obj(args.garment)
    body = read_obj(body_path) if os.path.exists(body_path) else None

    fig, axes = plt.subplots(1, len(cuts), figsize=(5 * len(cuts), 5), dpi=90, squeeze=False)
    palette = plt.get_cmap("tab10")
    for ax, (axis, value) in zip(axes[0], cuts):
        # Horizontal cuts plot (x, z) with the front (+z) down; sagittal ones (z, y).
        u, v = (0, 2) if axis == 1 else (2, 1)
        if body is not None:
            for seg in section(body[0], body[1], axis, value)[0]:
                ax.plot(seg[:, u], seg[:, v], color="black", lw=1)
        segments, which = section(garment[0], garment[1], axis, value)
        for seg, t in zip(segments, which):
            ax.plot(seg[:, u], seg[:, v], color=palette(garment[2][t] % 10), lw=1.3)
        ax.set_aspect("equal")
        if axis == 1:
            ax.invert_yaxis()
        ax.set_title(("y" if axis == 1 else "x") + f" = {value:.3f} m")
    handles = [plt.Line2D([], [], color=palette(i % 10)) for i in range(len(garment[3]))]
    axes[0][0].legend(handles, garment[3], fontsize=7)
    fig.savefig(args.out, bbox_inches="tight")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
