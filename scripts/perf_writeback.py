"""Where write-back time goes: Blender's own calls, timed on one 1920x1080 result.

A do-nothing render engine, registered by this script, writes one full frame of
RGBA and one single-channel pass the way the Whitted engine does (addon/result.py)
and times each step: begin_result, the first foreach_set into each freshly allocated
pass, a second foreach_set into the same pass, and end_result (which merges the
result into Blender's image). Medians of --repeats frames:

    blender -b --factory-startup --python scripts/perf_writeback.py -- [--repeats 5]
"""

import argparse
import json
import statistics
import time

import bpy
import numpy as np
from whitted_tools.cli import script_args

WIDTH, HEIGHT = 1920, 1080
EXTRA_PASS = "Extra"


class WritebackProbe(bpy.types.RenderEngine):
    bl_idname = "WRITEBACK_PROBE"
    bl_label = "Write-back probe"

    def render(self, depsgraph):
        rgba = np.random.default_rng(0).random((WIDTH * HEIGHT, 4), dtype=np.float32)
        value = np.ascontiguousarray(rgba[:, :1])
        flat = bpy.app.version >= (4, 1, 0)  # as addon/result.py: flat arrays from 4.1
        self.add_pass(EXTRA_PASS, 1, "X")
        times = {}
        t = time.perf_counter()
        result = self.begin_result(0, 0, WIDTH, HEIGHT)
        times["begin_result"] = time.perf_counter() - t
        passes = result.layers[0].passes
        for name, pixels in (("Combined", rgba), (EXTRA_PASS, value)):
            data = pixels.reshape(-1) if flat else pixels
            for attempt in ("first", "second"):
                t = time.perf_counter()
                passes[name].rect.foreach_set(data)
                times[f"{name} foreach_set, {attempt}"] = time.perf_counter() - t
        t = time.perf_counter()
        self.end_result(result)
        times["end_result"] = time.perf_counter() - t
        # The scene's custom property carries the figures out of the render call.
        depsgraph.scene.original["writeback_probe"] = json.dumps(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(script_args())
    bpy.utils.register_class(WritebackProbe)
    scene = bpy.context.scene
    scene.render.engine = WritebackProbe.bl_idname
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    runs = []
    for _ in range(args.repeats):
        bpy.ops.render.render()
        runs.append(json.loads(scene["writeback_probe"]))
    print(f"Blender {bpy.app.version_string}, {WIDTH}x{HEIGHT}, median of {args.repeats} frames:")
    for step in runs[0]:
        milliseconds = statistics.median(run[step] for run in runs) * 1000.0
        print(f"  {step:32s} {milliseconds:7.2f} ms")
    bpy.utils.unregister_class(WritebackProbe)


main()
