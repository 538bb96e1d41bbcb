"""What the benchmarks and page generators of scripts/ share: running a process
under a time limit, describing the machine on a page, reading the arguments a
script gets after Blender's "--", and building a benchmark scene.

New benchmarks use these rather than carrying their own (scripts/bench_viewport.py,
scripts/bench_performance.py).
"""

import os
import platform
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = REPO / "scripts"


def script_args():
    """The command-line arguments of a script run by Blender (after "--") or by the
    bpy module's Python (all of them)."""
    return sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]


def build_scene(name, path, resolution, timeout, blender="blender", extra=()):
    """Save the performance suite's scene `name` (scripts/perf_scenes.py) to `path`;
    None, or why it failed."""
    command = [
        blender,
        "-b",
        "--factory-startup",
        "--python-exit-code",
        "1",
        "--python",
        str(SCRIPTS / "perf_scenes.py"),
        "--",
        "--scene",
        name,
        "--resolution",
        *map(str, resolution),
        "--save",
        str(path),
        *extra,
    ]
    _, problem = run_process(command, timeout)
    return problem


def run_process(command, timeout):
    """(stdout, None) or (None, why it failed). A process past its timeout is killed
    with its process group (POV-Ray runs as Blender's child)."""
    print(f"  $ {shlex.join(command)}", flush=True)
    started = time.perf_counter()
    with subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        errors="replace",
        start_new_session=True,
    ) as process:
        try:
            output, _ = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
            return None, f"timed out after {timeout:.0f} s"
    seconds = time.perf_counter() - started
    if process.returncode != 0:
        tail = " / ".join(line for line in output.splitlines()[-4:] if line.strip())
        return None, f"failed (exit {process.returncode} after {seconds:.0f} s): {tail[-300:]}"
    return output, None


def machine_lines():
    """CPU model, cores and memory from /proc, the load when the page was written."""
    cpuinfo = Path("/proc/cpuinfo").read_text().splitlines()

    def field_of(name):
        return next(
            (line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith(name)), "?"
        )

    processors = sum(1 for line in cpuinfo if line.startswith("processor"))
    meminfo = Path("/proc/meminfo").read_text().split()
    memory_gib = int(meminfo[meminfo.index("MemTotal:") + 1]) / 1024 / 1024
    load = ", ".join(f"{value:.2f}" for value in os.getloadavg())
    return [
        f"- CPU: {field_of('model name')}, {processors} logical processors "
        f"({field_of('cpu cores')} cores per package, {field_of('siblings')} siblings); "
        f"{memory_gib:.1f} GiB memory; {platform.system()} {platform.release()}",
        f"- Load average when the page was written (1, 5, 15 min): {load}",
    ]
