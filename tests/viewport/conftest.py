"""pytest outside Blender: each test runs a scenario in a real Blender 3.4 window under Xvfb.

    .venv/bin/python -m pytest tests/viewport -q

The scenarios (scenarios/*.py) drive Blender with whitted_tools/viewport_driver.py;
windowrun.py starts them under xvfb-run with a hard timeout and reads back their JSON
result, screenshots and the Whitted viewport log. On failure the process's exit status,
steps, stdout and stderr are in the assertion message.
"""

import os
import subprocess

import pytest
from whitted_tools.blender import blender_command
from windowrun import OUTPUT_TAIL, REPO_ROOT, require, run_in_window


@pytest.fixture(scope="session")
def demo_blend(tmp_path_factory):
    """The demo scene (scripts/demo_scene.py) saved as a .blend, once per session."""
    require("blender")
    folder = tmp_path_factory.mktemp("demo")
    path = folder / "demo.blend"
    command = blender_command(
        os.path.join(REPO_ROOT, "scripts", "demo_scene.py"),
        *("--no-render", "--save", path),
        # demo_scene.py makes the output's folder even with --no-render: keep it here.
        *("--output", folder / "unused.png"),
    )
    done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0 and path.exists(), (
        f"demo_scene.py failed ({done.returncode}):\n{done.stdout[-OUTPUT_TAIL:]}\n"
        f"{done.stderr[-OUTPUT_TAIL:]}"
    )
    return str(path)


@pytest.fixture
def run_scenario(tmp_path):
    """run_in_window with this test's tmp_path: run_scenario(script, blend, *args, ...)."""

    def run(script, blend, *args, **kwargs):
        return run_in_window(tmp_path, script, blend, *args, **kwargs)

    return run
