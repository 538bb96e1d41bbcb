"""Run the in-Blender test suite (tests/blender) with pytest, inside real Blender.

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run.py -- [ARGS]
    .venv/bin/python tests/blender/run.py [ARGS]                    (bpy 5.0 module)

ARGS go to pytest. The process exits with pytest's exit code. With WHITTED_RESULTS=FILE
set, the counts (passed, failed, skipped, ...) are also written to FILE as JSON, with
the Blender and Python versions (whitted_tools blender-versions reads them).
"""

import json
import os
import sys
import time

import bpy
from whitted_tools.blender import exit_process
from whitted_tools.cli import script_args

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))


def pytest_args():
    argv = script_args()
    # All of tests/blender unless test files or ids were named.
    named = any(os.path.exists(arg.split("::")[0]) for arg in argv if not arg.startswith("-"))
    # No cache directory in the repository; tests/blender's conftest.py is the root one.
    return [
        *([] if named else [TESTS_DIR]),
        "-p",
        "no:cacheprovider",
        f"--rootdir={TESTS_DIR}",
        *argv,
    ]


class Results:
    """A pytest plugin that writes the session's counts to a JSON file."""

    def __init__(self, path):
        self.path = path
        self.started = time.monotonic()

    def pytest_terminal_summary(self, terminalreporter, exitstatus):
        counts = {
            key: len(reports)
            for key, reports in terminalreporter.stats.items()
            if key in ("passed", "failed", "skipped", "error", "xfailed", "xpassed")
        }
        failed = [
            report.nodeid
            for key in ("failed", "error")
            for report in terminalreporter.stats.get(key, [])
        ]
        record = {
            "blender": bpy.app.version_string,
            "python": ".".join(map(str, sys.version_info[:3])),
            "tests": script_args(),
            "counts": counts,
            "failed": failed,
            "exit_status": int(exitstatus),
            "seconds": round(time.monotonic() - self.started, 1),
        }
        os.makedirs(os.path.dirname(os.path.abspath(self.path)), exist_ok=True)
        with open(self.path, "w", encoding="utf-8") as out:
            json.dump(record, out, indent=1)


def main():
    import pytest  # after bpy: Blender's Python must be the one that runs the tests

    print(f"tests/blender: Blender {bpy.app.version_string}, pytest {pytest.__version__}")
    results = os.environ.get("WHITTED_RESULTS")
    plugins = [Results(results)] if results else []
    # Inside `blender --python`, SystemExit ends Blender at once with this code.
    exit_process(int(pytest.main(pytest_args(), plugins=plugins)))


if __name__ == "__main__":
    main()
