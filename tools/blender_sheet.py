"""Blender's cloth on the sheet scenes of docs/benchmarks.md ("Against Blender"), for timing.

Run with Debian's Blender 3.4 (no display needed):

    blender -b --factory-startup --python tools/blender_sheet.py -- \
        --scene hanging|sphere --cells N [--seconds 2] [--threads 1] [--out sheet.obj]

Builds a 1 m × 1 m sheet of N × N cells with Blender's default cloth settings at quality 5 (or its vertex mass
from Atelier's cotton, --cotton-mass)
(5 steps per 1/24 s frame), either pinned at its two top corners and hanging (the scene of
assets/bench/hanging-sheet-64.json) or falling 0.2 m onto a 0.3 m sphere with self-collision
(assets/scenes/sheet-on-sphere.json's geometry), bakes the cloth for the simulated seconds
asked and prints one JSON line: the bake's wall time, its seconds per simulated second, and
the final mesh's area ratio (triangle area over the flat sheet's). The final mesh is written
as OBJ when --out is given, so that Atelier's own tools can check it.
"""

import argparse
import json
import sys
import time

import bmesh
import bpy


def parse():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--scene", choices=["hanging", "sphere"], required=True)
    p.add_argument("--cells", type=int, required=True)
    p.add_argument("--seconds", type=float, default=2.0)
    p.add_argument("--threads", type=int, default=0, help="0: Blender's default (all cores)")
    p.add_argument("--out", default="")
    p.add_argument(
        "--cotton-mass",
        action="store_true",
        help="vertex mass from Atelier's cotton (0.12 kg/m²) instead of Blender's default 0.3 kg",
    )
    return p.parse_args(argv)


def sheet(cells, height, pinned_corners, cotton):
    bpy.ops.mesh.primitive_grid_add(
        x_subdivisions=cells, y_subdivisions=cells, size=1.0, location=(0, 0, height)
    )
    obj = bpy.context.active_object
    # Blender 2.x counted the grid's subdivisions as vertices per side, 3.x as cells: check
    # the count, so that both programs run the same sheet.
    n = len(obj.data.vertices)
    if n != (cells + 1) ** 2:
        raise SystemExit(f"grid has {n} vertices, expected {(cells + 1) ** 2}")
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(obj.data)
    bm.free()
    mod = obj.modifiers.new("Cloth", "CLOTH")
    mod.settings.quality = 5
    if cotton:
        mod.settings.mass = 0.12 / n
    if pinned_corners:
        group = obj.vertex_groups.new(name="pins")
        top = max(v.co.y for v in obj.data.vertices)
        xs = [v.co.x for v in obj.data.vertices]
        corners = [
            v.index
            for v in obj.data.vertices
            if abs(v.co.y - top) < 1e-9 and (abs(v.co.x - min(xs)) < 1e-9 or abs(v.co.x - max(xs)) < 1e-9)
        ]
        group.add(corners, 1.0, "REPLACE")
        mod.settings.vertex_group_mass = "pins"
    return obj, mod


def area(obj):
    dg = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(dg).to_mesh()
    a = sum(p.area for p in mesh.polygons)
    obj.evaluated_get(dg).to_mesh_clear()
    return a


def main():
    args = parse()
    scene = bpy.context.scene
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    if args.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = args.threads
    fps = 24
    scene.render.fps = fps
    frames = int(round(args.seconds * fps))
    if args.scene == "hanging":
        obj, mod = sheet(args.cells, 1.5, True, args.cotton_mass)
    else:
        obj, mod = sheet(args.cells, 0.9, False, args.cotton_mass)
        mod.collision_settings.use_self_collision = True
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(0, 0, 0.4))
        sphere = bpy.context.active_object
        sphere.modifiers.new("Collision", "COLLISION")
        bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0, 0, 0))
        floor = bpy.context.active_object
        floor.modifiers.new("Collision", "COLLISION")
    cache = mod.point_cache
    cache.frame_start = 1
    cache.frame_end = frames + 1
    scene.frame_start = 1
    scene.frame_end = frames + 1
    rest = area(obj)
    start = time.perf_counter()
    for f in range(1, frames + 2):
        scene.frame_set(f)
    wall = time.perf_counter() - start
    ratio = area(obj) / rest
    if args.out:
        bpy.ops.object.select_all(action="DESELECT")
        obj.select_set(True)
        bpy.context.view_layer.objects.active = obj
        bpy.ops.export_scene.obj(
            filepath=args.out, use_selection=True, use_materials=False, axis_forward="-Z", axis_up="Y"
        )
    print(
        "BLENDER-SHEET "
        + json.dumps(
            {
                "scene": args.scene,
                "cells": args.cells,
                "vertices": len(obj.data.vertices),
                "simulated_s": frames / fps,
                "wall_s": wall,
                "wall_s_per_simulated_s": wall * fps / frames,
                "area_ratio": ratio,
                "quality": mod.settings.quality,
                "vertex_mass_kg": mod.settings.mass,
                "threads": scene.render.threads,
                "blender": bpy.app.version_string,
            }
        )
    )


main()
