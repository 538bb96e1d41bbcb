"""Run the in-Blender test suite (tests/blender) with pytest, inside real Blender.

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run.py -- [ARGS]
    .venv/bin/python tests/blender/run.py [ARGS]                    (bpy 5.0 module)

ARGS go to pytest. The process exits with pytest's exit code.
"""

import os
import sys

import bpy
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


def main():
    import pytest  # after bpy: Blender's Python must be the one that runs the tests

    print(f"tests/blender: Blender {bpy.app.version_string}, pytest {pytest.__version__}")
    # Inside `blender --python`, SystemExit ends Blender at once with this code.
    sys.exit(int(pytest.main(pytest_args())))


if __name__ == "__main__":
    main()
