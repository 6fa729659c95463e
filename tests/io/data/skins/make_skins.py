"""Makes the skinned test bodies of tests/io/body_animation_blender_test.cpp with Blender
(Debian's blender 3.4): `blender -b --factory-startup --python make_skins.py -- OUT_DIR`.

The body is the prism of body_animation_test.cpp (0.4 x 1.7 x 0.25 m, three rings of four
vertices at heights 0, 0.85 and 1.7 m, whose weights on the upper bone are 0, 1/2 and 1) on a
two-bone armature, with one animation "bend" over 1 s at 24 frames per second: the upper bone
turns 30 degrees about the prism's depth axis (+z when y is up) round the joint at 0.85 m, and
the root moves 0.1 m along +x, both linearly. Blender is z-up: a y-up point (x, y, z) is
Blender's (x, -z, y). Written as binary FBX and COLLADA by Blender's own exporters, so that
Atelier's importer is checked on files another tool wrote.
"""
import math
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = 24
scene.frame_start = 0
scene.frame_end = 24

PIVOT = 0.85
corners = [(-0.2, -0.125), (0.2, -0.125), (0.2, 0.125), (-0.2, 0.125)]
verts = []
upper = []
for r in range(3):
    for (x, z) in corners:
        verts.append((x, -z, PIVOT * r))  # y-up (x, PIVOT r, z) in Blender's z-up
        upper.append(0.5 * r)
faces = []
for r in range(2):
    for j in range(4):
        a, b = 4 * r + j, 4 * r + (j + 1) % 4
        faces.append((a, b, b + 4, a + 4))
faces.append((0, 3, 2, 1))
faces.append((8, 9, 10, 11))
mesh = bpy.data.meshes.new("prism")
mesh.from_pydata(verts, [], faces)
mesh.update()
body = bpy.data.objects.new("prism", mesh)
scene.collection.objects.link(body)

armature = bpy.data.armatures.new("skeleton")
rig = bpy.data.objects.new("skeleton", armature)
scene.collection.objects.link(rig)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.mode_set(mode="EDIT")
root = armature.edit_bones.new("root")
root.head = (0, 0, 0)
root.tail = (0, 0, PIVOT)
top = armature.edit_bones.new("upper")
top.head = (0, 0, PIVOT)
top.tail = (0, 0, 2 * PIVOT)
top.parent = root
top.use_connect = True
bpy.ops.object.mode_set(mode="OBJECT")

groups = {name: body.vertex_groups.new(name=name) for name in ("root", "upper")}
for i, w in enumerate(upper):
    if w < 1:
        groups["root"].add([i], 1 - w, "REPLACE")
    if w > 0:
        groups["upper"].add([i], w, "REPLACE")
body.parent = rig
modifier = body.modifiers.new("skin", "ARMATURE")
modifier.object = rig

# A bone pointing up (+z) with roll 0 has local x = +x and local z = -y: a turn about its local
# z is a turn about Blender's -y, which is the y-up prism's +z.
action = bpy.data.actions.new("bend")
rig.animation_data_create()
rig.animation_data.action = action
pose_root = rig.pose.bones["root"]
pose_upper = rig.pose.bones["upper"]
pose_upper.rotation_mode = "XYZ"
for frame, t in ((0, 0.0), (24, 1.0)):
    pose_root.location = (0.1 * t, 0, 0)
    pose_upper.rotation_euler = (0, 0, math.radians(30) * t)
    pose_root.keyframe_insert("location", frame=frame)
    pose_upper.keyframe_insert("rotation_euler", frame=frame)
for curve in action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"

bpy.ops.export_scene.fbx(filepath=out + "/bend.fbx", add_leaf_bones=False, bake_anim=True,
                         bake_anim_use_all_actions=False, bake_anim_use_nla_strips=False,
                         bake_anim_simplify_factor=0.0, armature_nodetype="NULL")
bpy.ops.wm.collada_export(filepath=out + "/bend.dae", include_animations=True,
                          sampling_rate=1, keep_keyframes=False)
