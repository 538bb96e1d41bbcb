"""Save the test scenes of tests/farm (Blender 3.4, development add-on):

    blender -b --factory-startup --python make_scene.py -- OUT.blend [--fail] [--size W H]

The demo scene at 96 x 72 (or W x H) with its camera moving over frames 1-6 (so every frame
differs), Whitted as the engine. --fail gives the camera a zero scale, which
Whitted refuses (an engine error after which Blender itself would exit 0).
"""

import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from demo_scene import build_demo_scene

args = sys.argv[sys.argv.index("--") + 1 :]
bpy.ops.wm.read_factory_settings(use_empty=True)
assert addon_utils.enable("whitted", default_set=True) is not None
scene = build_demo_scene()
scene.render.engine = "WHITTED"
size = args[args.index("--size") + 1 :][:2] if "--size" in args else (96, 72)
scene.render.resolution_x, scene.render.resolution_y = (int(v) for v in size)
scene.render.resolution_percentage = 100
scene.frame_start, scene.frame_end = 1, 6
camera = scene.camera
for frame in (1, 6):
    camera.location.x = -1.5 if frame == 1 else 1.5
    camera.keyframe_insert("location", index=0, frame=frame)
if "--fail" in args:
    camera.scale = (0.0, 0.0, 0.0)
bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args[0]))
