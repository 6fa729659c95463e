"""Checks a draped garment's OBJ with Blender's own geometry code, independently of Atelier's.

    blender -b --factory-startup --python tools/blender_check.py -- GARMENT.obj BODY.obj [--json out.json]

Reads both OBJ files with tools/obj_triangles.py (positions and faces only; no importer
settings to get wrong), builds Blender's BVH trees (mathutils.bvhtree) and prints one JSON
line with what `atelier-cli drape --report` also states, so the two can be compared:

- `garment_pairs`: pairs of garment triangles that intersect (Blender's triangle-triangle
  test) and share no vertex; `atelier-cli drape` writes each welded seam vertex once, so
  triangles that meet across a seam share vertices, as neighbours inside a panel do;
- `body_pairs`: pairs of a garment triangle and a body triangle that intersect;
- `inside_vertices` and `max_penetration_m`: garment vertices behind the body's nearest face
  (the side its normal points away from) and the deepest of them.
"""

import json
import os
import sys

from mathutils import Vector
from mathutils.bvhtree import BVHTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import obj_triangles  # noqa: E402  (Atelier's own OBJ reader for the tools: triangles only)


def read_obj(path):
    """Positions as Blender vectors and faces as vertex triples, by tools/obj_triangles.py."""
    vertices, _, faces = obj_triangles.read_obj(path)
    if not faces:
        sys.exit(f"{path}: no faces")
    return [Vector(v) for v in vertices], [tuple(f[0]) for f in faces]


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    out = None
    if "--json" in argv:
        k = argv.index("--json")
        out = argv[k + 1]
        del argv[k : k + 2]
    if len(argv) != 2:
        sys.exit("usage: blender -b --python tools/blender_check.py -- GARMENT.obj BODY.obj [--json OUT]")
    gv, gf = read_obj(argv[0])
    bv, bf = read_obj(argv[1])
    garment = BVHTree.FromPolygons(gv, gf, all_triangles=True, epsilon=0.0)
    body = BVHTree.FromPolygons(bv, bf, all_triangles=True, epsilon=0.0)

    pairs = set()
    for a, b in garment.overlap(garment):
        if a == b or set(gf[a]) & set(gf[b]):
            continue
        pairs.add((min(a, b), max(a, b)))
    body_pairs = len(garment.overlap(body))

    inside = 0
    deepest = 0.0
    for p in gv:
        location, normal, _, distance = body.find_nearest(p)
        if location is None:
            continue
        if (p - location).dot(normal) < 0:
            inside += 1
            deepest = max(deepest, distance)

    result = {
        "garment": argv[0],
        "garment_triangles": len(gf),
        "body_triangles": len(bf),
        "garment_pairs": len(pairs),
        "body_pairs": body_pairs,
        "inside_vertices": inside,
        "max_penetration_m": deepest,
    }
    print("BLENDER-CHECK " + json.dumps(result))
    if out:
        with open(out, "w", encoding="utf-8") as f:
            json.dump(result, f, indent=1)


main()
