#!/usr/bin/env python3
"""Plots plane sections of a draped garment and its body, one panel per colour.

Where a seam stays open or panels start through each other, a few sections show why faster
than a render: which panel lies where, how far from the body, and which edges overshoot.

    tools/drape_sections.py out/tshirt.obj --y 1.2 1.0 --x -0.1 --out sections.png

The body is read from DRAPED.body.obj (as `atelier-cli drape` writes it) unless --body names
it. --y cuts horizontal sections (x across, the front, +z, at the bottom), --x sagittal ones
(z across, the front to the right; y up). Frames written with --frames-dir work too (pass
--body). For each horizontal cut it also prints the body's girth there (the convex hull of its
section, as a tape spans hollows; --max-x leaves out the hands, which hang level with the
hips) and the length of the garment's section. Needs numpy and matplotlib (Debian:
python3-numpy python3-matplotlib).
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


def hull_perimeter(points):
    """Perimeter of the convex hull of 2D points (monotone chain)."""
    pts = sorted(set(map(tuple, np.round(points, 9))))
    if len(pts) < 3:
        return 0.0

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    hull = np.array(lower[:-1] + upper[:-1])
    return float(np.linalg.norm(hull - np.roll(hull, 1, axis=0), axis=1).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("garment")
    parser.add_argument("--body")
    parser.add_argument("--y", type=float, nargs="*", default=[], help="heights [m]")
    parser.add_argument("--x", type=float, nargs="*", default=[], help="sagittal planes [m]")
    parser.add_argument("--max-x", type=float, default=0.3,
                        help="girths count body points with |x| below this [m]")
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
        if axis == 1:
            line = f"y = {value:.3f} m: garment section {np.linalg.norm(segments[:, 0] - segments[:, 1], axis=1).sum():.3f} m"
            if body is not None:
                points = section(body[0], body[1], axis, value)[0].reshape(-1, 3)
                points = points[np.abs(points[:, 0]) < args.max_x]
                line += f", body girth {hull_perimeter(points[:, [0, 2]]):.3f} m"
            print(line)
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
