"""Experiment (issue 15): the recorded hits of a one-thread render reconstructed one by one
(CompiledScene::interaction), from triangles packed 18 floats each (interaction_packed),
and eight at a time in structure-of-arrays form (interactions, SSE2 and AVX2); prints
nanoseconds per hit and how many batch results differ from interaction in any bit.

    PYTHONPATH=tools blender -b --factory-startup --addons whitted SCENE.blend \\
        --python scripts/perf_interaction_batch.py
"""

import json
import os

import bpy
from whitted.native import load_native
from whitted.sync.frame import sync_frame
from whitted_tools.native_job import run_job

scene = bpy.context.scene
scene.render.threads_mode = "FIXED"
scene.render.threads = 1
native = load_native()
frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
job = run_job(frame.job(native, frame.settings, record_stride=1, record_results=True))
r = job.bench_interaction(int(os.environ.get("REPEATS", "7")))
r["ns_scalar"] = r["scalar_seconds"] / r["hits"] * 1e9
r["ns_batch"] = r["batch_seconds"] / r["hits"] * 1e9
r["ns_packed"] = r["packed_seconds"] / r["hits"] * 1e9
r["ns_avx2"] = r["batch_avx2_seconds"] / r["hits"] * 1e9
r["speedup_sse2"] = r["scalar_seconds"] / r["batch_seconds"]
r["speedup_avx2"] = r["scalar_seconds"] / r["batch_avx2_seconds"]
st = job.stats()
r["rays"] = st["rays"]["total"]
r["trace_seconds"] = st["trace_seconds"]
print("BENCH", bpy.data.filepath, json.dumps(r))
