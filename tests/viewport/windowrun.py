"""Run a tests/viewport scenario in a real Blender 3.4 window under Xvfb (pytest side).

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup DEMO.blend \\
        --python scenarios/SCENARIO.py -- --result RESULT.json --out DIR [ARGS]

with WHITTED_VIEWPORT_LOG pointing at DIR/viewport.jsonl, under a hard timeout.
"""

import json
import os
import shutil
import signal
import subprocess
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO_ROOT = os.path.dirname(os.path.dirname(HERE))
SCENARIOS = os.path.join(HERE, "scenarios")
SCREEN = "1280x800x24"
# Characters of stdout and stderr shown in a failure message (the end of each).
OUTPUT_TAIL = 6000


class BlenderRun:
    """One finished scenario process: exit status, output, result and viewport log."""

    def __init__(self, name, command, out_dir):
        self.name = name
        self.command = command
        self.out_dir = out_dir
        self.result_path = os.path.join(out_dir, "result.json")
        self.log_path = os.path.join(out_dir, "viewport.jsonl")
        self.returncode = None
        self.stdout = ""
        self.stderr = ""
        self.seconds = 0.0
        self.result = None

    def events(self, kind=None):
        """The viewport log's events (all, or those of one kind), in order."""
        if not os.path.exists(self.log_path):
            return []
        with open(self.log_path, encoding="utf-8") as file:
            events = [json.loads(line) for line in file if line.strip()]
        return [e for e in events if kind is None or e.get("event") == kind]

    @property
    def data(self):
        return self.result["data"]

    def screenshot(self, name):
        return self.result["screenshots"][name]

    def describe(self):
        steps = ""
        if self.result:
            steps = "\n".join(f"  {s['t']:.2f} {s['name']}" for s in self.result["steps"])
        return (
            f"scenario {self.name}: exit {self.returncode} after {self.seconds:.1f} s\n"
            f"command: {' '.join(self.command)}\n"
            f"result: ok={self.result and self.result['ok']}\n"
            f"error: {self.result and self.result['error']}\n"
            f"steps:\n{steps}\n"
            f"viewport log: {len(self.events())} events in {self.log_path}\n"
            f"--- stdout (end) ---\n{self.stdout[-OUTPUT_TAIL:]}\n"
            f"--- stderr (end) ---\n{self.stderr[-OUTPUT_TAIL:]}"
        )

    def assert_clean(self):
        """Exit 0, the scenario finished, and no Python exception anywhere.

        Blender prints an exception raised in an engine callback (view_update,
        view_draw, render) and goes on: "Traceback" in the output is the only trace.
        """
        assert self.result is not None, f"no result file\n{self.describe()}"
        assert self.result["ok"], f"scenario failed\n{self.describe()}"
        assert self.returncode == 0, f"Blender exited {self.returncode}\n{self.describe()}"
        for stream, text in (("stdout", self.stdout), ("stderr", self.stderr)):
            assert "Traceback" not in text, f"a Python exception in {stream}\n{self.describe()}"


def require(tool):
    path = shutil.which(tool)
    if path is None:
        pytest.fail(f"'{tool}' is not installed: run scripts/setup.sh (it installs xvfb, blender)")
    return path


def run_in_window(out_root, script, blend, *args, timeout=240.0, env=None, screen=SCREEN):
    """Run scenarios/SCRIPT on `blend` in a window; returns the finished BlenderRun.

    Fails the test (after killing the process group) when it runs past `timeout`.
    `screen` is Xvfb's screen (WxHxDEPTH); Blender's window fills it.
    """
    require("xvfb-run")
    require("blender")
    out_dir = os.path.join(str(out_root), os.path.splitext(script)[0])
    os.makedirs(out_dir, exist_ok=True)
    command = [
        "xvfb-run",
        "-a",
        "-s",
        f"-screen 0 {screen}",
        "blender",
        "--factory-startup",
        blend,
        "--python",
        os.path.join(SCENARIOS, script),
        "--",
        "--result",
        os.path.join(out_dir, "result.json"),
        "--out",
        out_dir,
        # The driver's own limit comes first, so a slow run still writes its result.
        "--timeout",
        str(timeout - 30.0),
        *args,
    ]
    blender_run = BlenderRun(script, command, out_dir)
    environment = dict(os.environ)
    environment["WHITTED_VIEWPORT_LOG"] = blender_run.log_path
    environment.update(env or {})
    started = time.perf_counter()
    # A session of its own: on timeout the whole group (xvfb-run, Xvfb, Blender) is
    # killed by its id, and nothing else.
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=environment,
        start_new_session=True,
    )
    try:
        blender_run.stdout, blender_run.stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        blender_run.stdout, blender_run.stderr = process.communicate()
        blender_run.returncode = process.returncode
        blender_run.seconds = time.perf_counter() - started
        pytest.fail(f"killed after the hard timeout of {timeout} s\n{blender_run.describe()}")
    blender_run.returncode = process.returncode
    blender_run.seconds = time.perf_counter() - started
    if os.path.exists(blender_run.result_path):
        with open(blender_run.result_path, encoding="utf-8") as file:
            blender_run.result = json.load(file)
    print(f"{script}: {blender_run.seconds:.1f} s, output in {out_dir}")
    return blender_run
