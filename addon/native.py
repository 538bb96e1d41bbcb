"""The compiled core, `whitted_native`, which the build copies beside this file: one
file per CPython it was built for (whitted_native.cpython-3XY-x86_64-linux-gnu.so),
of which Python imports the one matching its own ABI."""

import glob
import os
import platform
import re
import sys

BUILD_COMMAND = "bash scripts/setup.sh  (or: cmake -S . -B build && cmake --build build)"
FOLDER = os.path.dirname(os.path.abspath(__file__))


def carried_pythons(folder=FOLDER):
    """The CPython versions ("3.11", ...) of the whitted_native modules in `folder`."""
    tags = set()
    for path in glob.glob(os.path.join(folder, "whitted_native.cpython-*.so")):
        match = re.match(r"whitted_native\.cpython-3(\d+)", os.path.basename(path))
        if match:
            tags.add(int(match.group(1)))
    return [f"3.{minor}" for minor in sorted(tags)]


def is_package(folder=FOLDER):
    """True for an installed package (scripts/package.py writes the manifest into it),
    False for the add-on folder of a repository checkout."""
    return os.path.isfile(os.path.join(folder, "blender_manifest.toml"))


def import_problem(error, blender_version, folder=FOLDER):
    """What to tell the user when `from . import whitted_native` raised `error`."""
    python = f"{sys.version_info[0]}.{sys.version_info[1]}"
    carried = carried_pythons(folder)
    if python not in carried:
        what = (
            f"Blender {blender_version} runs Python {python}, and this Whitted "
            f"{'package' if is_package(folder) else 'add-on folder'} ({folder}) carries the "
            f"native module for Python {', '.join(carried) or 'none'} only"
        )
    else:
        what = f"the native module for Python {python} in {folder} does not load ({error})"
    if is_package(folder):
        advice = (
            f"Install a Whitted package built for Python {python} on {platform.system()} "
            f"{platform.machine()} (the README's 'Supported Blender versions' table says which "
            "package fits which Blender)"
        )
    else:
        advice = (
            f"Build it from the repository root with: {BUILD_COMMAND}; the build copies "
            "whitted_native*.so into addon/"
        )
    return f"Whitted: {what}. {advice}."


def load_native():
    """Import whitted_native, or raise ImportError that says what to do."""
    try:
        from . import whitted_native
    except ImportError as error:
        import bpy

        raise ImportError(import_problem(error, bpy.app.version_string)) from error
    return whitted_native
