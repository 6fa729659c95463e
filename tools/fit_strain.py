#!/usr/bin/env python3
"""Measures how far each panel of a draped garment is stretched, from the mesh alone.

    tools/fit_strain.py out/tshirt.obj

Reads an OBJ as `atelier-cli drape --out` writes it (one group per panel, UV = pattern
coordinates in metres, the rest shape) and prints per panel, as the drape report's
`panel_strain` lines do, the largest principal strain λ − 1 of its triangles (λ² the largest
eigenvalue of FᵀF, F the map from the rest triangle to the draped one) with the height of that
triangle's centroid, and the shares of its rest area stretched beyond 5% and 10%. Python's
standard library only, so that it checks Atelier's figures independently of Atelier's code.
"""
import argparse
import math

from obj_triangles import read_obj


def largest_stretch(x, u):
    """Largest principal stretch of the triangle u (2D rest) → x (3D)."""
    a = (u[1][0] - u[0][0], u[1][1] - u[0][1])
    b = (u[2][0] - u[0][0], u[2][1] - u[0][1])
    det = a[0] * b[1] - a[1] * b[0]
    if det == 0:
        return None, 0.0
    e1 = [x[1][k] - x[0][k] for k in range(3)]
    e2 = [x[2][k] - x[0][k] for k in range(3)]
    # F = [e1 e2] [a b]^-1, column by column.
    f1 = [(e1[k] * b[1] - e2[k] * a[1]) / det for k in range(3)]
    f2 = [(e2[k] * a[0] - e1[k] * b[0]) / det for k in range(3)]
    c11 = sum(v * v for v in f1)
    c22 = sum(v * v for v in f2)
    c12 = sum(p * q for p, q in zip(f1, f2))
    mean = 0.5 * (c11 + c22)
    radius = math.hypot(0.5 * (c11 - c22), c12)
    return math.sqrt(max(mean + radius, 0.0)), 0.5 * abs(det)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("obj")
    args = parser.parse_args()
    vertices, uvs, faces = read_obj(args.obj, need_uvs=True)
    panels = {}
    for corners, uv, group in faces:
        x = [vertices[i] for i in corners]
        stretch, area = largest_stretch(x, [uvs[i] for i in uv])
        if stretch is None:
            continue
        height = sum(p[1] for p in x) / 3
        panels.setdefault(group, []).append((stretch - 1, area, height))
    for group, triangles in panels.items():
        total = sum(area for _, area, _ in triangles)
        over5 = sum(area for s, area, _ in triangles if s > 0.05) / total
        over10 = sum(area for s, area, _ in triangles if s > 0.10) / total
        worst = max(triangles)
        print(f"{group}: strain up to {max(worst[0], 0):.4f} at {worst[2]:.3f} m height; "
              f"area beyond 5%: {over5:.4f}, beyond 10%: {over10:.4f}")


if __name__ == "__main__":
    main()
