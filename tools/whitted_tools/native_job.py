"""A native render job run to its end by a benchmark, outside the add-on's engine.

bpy-free: the benchmark that drives the bindings alone (whitted_tools.builds) uses it as
well as the scripts inside Blender (perf_raw_embree, bench_effects).
"""


def run_job(job, poll_seconds=1.0):
    """Start `job` (whitted_native.RenderJob) and wait for every worker; returns the job.
    A worker's exception is raised here, by `wait`, once all workers have stopped."""
    job.start()
    while not job.wait(poll_seconds):
        pass
    return job
