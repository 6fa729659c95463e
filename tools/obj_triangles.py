"""Reads the triangles of an OBJ as `atelier-cli drape --out` writes it, for the checking tools.

Python's standard library only, so that the tools check Atelier's figures independently of
Atelier's code.
"""
import sys


def read_obj(path, need_uvs=False):
    """Returns (vertices, uvs, faces): faces as (vertex indices, uv indices or None, group)."""
    vertices, uvs, faces, group = [], [], [], None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append(tuple(float(c) for c in parts[1:4]))
            elif parts[0] == "vt":
                uvs.append(tuple(float(c) for c in parts[1:3]))
            elif parts[0] == "g":
                group = " ".join(parts[1:])
            elif parts[0] == "f":
                corners = [p.split("/") for p in parts[1:]]
                if len(corners) != 3:
                    sys.exit(f"{path}:{number}: only triangles are measured")
                has_uvs = all(len(c) > 1 and c[1] for c in corners)
                if need_uvs and not has_uvs:
                    sys.exit(f"{path}:{number}: a face without UVs (the pattern) to measure")
                faces.append(([int(c[0]) - 1 for c in corners],
                              [int(c[1]) - 1 for c in corners] if has_uvs else None, group))
    return vertices, uvs, faces
