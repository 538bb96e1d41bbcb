"""Experiment (issue 15): a render's camera rays traced again by Embree alone in groups of
1 (single rays), 4, 8 and 16 (packets of consecutive rays: a pixel's 2x2 samples, two and
four neighbouring pixels of a tile row), fastest of 7; prints ns per camera ray.

    PYTHONPATH=tools blender -b --factory-startup --addons whitted SCENE.blend \\
        --python scripts/perf_camera_groups.py [-- --aa 1]
"""

import argparse
import json

import bpy
from whitted.native import load_native
from whitted.sync.frame import sync_frame
from whitted_tools.cli import script_args
from whitted_tools.native_job import run_job

parser = argparse.ArgumentParser()
parser.add_argument("--aa", type=int, default=0, help="samples per axis; 0: the scene's")
parser.add_argument("--kind", type=int, default=1, help="RayKind bits: 1 camera, 4 reflection, 8 refraction")
args = parser.parse_args(script_args())
scene = bpy.context.scene
scene.render.threads_mode = "FIXED"
scene.render.threads = 1
if args.aa:
    scene.whitted.aa_samples = args.aa
native = load_native()
frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
job = run_job(frame.job(native, frame.settings, record_stride=1, record_results=True))
cameras = {1: "camera", 4: "reflection", 8: "refraction"}[args.kind]
cameras = job.stats()["rays"][cameras]
out = {"scene": bpy.data.filepath, "aa": scene.whitted.aa_samples, "camera_rays": cameras}
for width in (1, 4, 8, 16):
    seconds, differ = job.bench_camera_groups(width, 7, args.kind)
    out[f"ns_{width}"] = round(seconds / cameras * 1e9, 1)
    out[f"differ_{width}"] = differ
print("GROUPS", json.dumps(out))
