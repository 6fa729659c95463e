#!/usr/bin/env python3
"""Measures how sharply a draped garment folds across its seams, from the mesh alone.

    tools/seam_folds.py out/skirt.obj [--worst 5]

Reads a single-surface OBJ as `atelier-cli drape --out` writes it (welded seam vertices once,
one group per panel) and prints, as the drape report's `seam_fold_*` and
`cloth_fold_median_deg` figures do, the fold angle between the two faces of every edge:
the median and largest over the edges between two panels' groups (the seams), the median over
the edges inside a panel. A dart is sewn inside its panel: its edges count as the panel's.
`--worst N` lists the N sharpest seam edges with their heights. Python's standard library only,
so that it checks Atelier's figures independently of Atelier's code.
"""
import argparse
import math
import statistics
import sys

from obj_triangles import read_obj


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def fold_deg(n0, n1):
    """Angle between two face normals [deg] (0 = flat)."""
    dot = sum(x * y for x, y in zip(n0, n1))
    norm = math.sqrt(sum(x * x for x in n0) * sum(x * x for x in n1))
    if norm == 0:
        return 0.0
    return math.degrees(math.acos(max(-1.0, min(1.0, dot / norm))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("obj")
    parser.add_argument("--worst", type=int, default=0, help="list the N sharpest seam edges")
    args = parser.parse_args()
    vertices, _, faces = read_obj(args.obj)
    normals = []
    edges = {}
    for index, (corners, _, group) in enumerate(faces):
        a, b, c = (vertices[i] for i in corners)
        normals.append(cross(sub(b, a), sub(c, a)))
        for k in range(3):
            u, v = corners[k], corners[(k + 1) % 3]
            edges.setdefault((min(u, v), max(u, v)), []).append(index)
    seam, cloth = [], []
    for (u, v), sides in edges.items():
        if len(sides) != 2:
            continue  # a border, or non-manifold
        f0, f1 = sides
        angle = fold_deg(normals[f0], normals[f1])
        if faces[f0][2] != faces[f1][2]:
            height = 0.5 * (vertices[u][1] + vertices[v][1])
            seam.append((angle, height, faces[f0][2], faces[f1][2]))
        else:
            cloth.append(angle)
    if not seam:
        sys.exit(f"{args.obj}: no edge joins two panels' groups (written with --split-panels?)")
    angles = [s[0] for s in seam]
    print(f"seam edges {len(seam)}: fold median {statistics.median(angles):.3f} deg, "
          f"max {max(angles):.3f} deg; inside the panels: median "
          f"{statistics.median(cloth):.3f} deg over {len(cloth)} edges")
    for angle, height, g0, g1 in sorted(seam, reverse=True)[: args.worst]:
        print(f"  {angle:7.2f} deg at y = {height:.3f} m between {g0} and {g1}")


if __name__ == "__main__":
    main()
