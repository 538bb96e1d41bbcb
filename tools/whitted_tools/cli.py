"""The command-line arguments of a script or verb, wherever it runs."""

import argparse
import importlib.util
import os
import sys


def script_args(argv=None):
    """The arguments meant for the script.

    Inside the Blender binary (`blender -b --python S -- ARGS`) they follow "--", and
    without one there are none (what precedes is Blender's own); run by a Python
    (the bpy module's, or a plain one) they are all of argv after the script's name.
    """
    argv = sys.argv if argv is None else argv
    if "--" in argv:
        return argv[argv.index("--") + 1 :]
    return [] if inside_blender_binary(argv) else argv[1:]


def page_parser(name, doc, repeats=None):
    """The argument parser of a verb that writes a docs page (the module `name`): described
    by the first paragraph of its docstring `doc`, with --out (the docs directory,
    required) and, when `repeats` is given, --repeats (default `repeats`). The verb adds
    its own arguments and parses its argv."""
    from whitted_tools.verbs import prog

    parser = argparse.ArgumentParser(prog=prog(name), description=doc.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="the docs directory to write into")
    if repeats is not None:
        parser.add_argument("--repeats", type=int, default=repeats)
    return parser


def inside_blender_binary(argv=None):
    """Whether this process is the Blender program (not Python importing bpy): its
    argv[0] is the Blender executable."""
    argv = sys.argv if argv is None else argv
    return bool(argv) and os.path.basename(argv[0]).startswith("blender")


def load_script(name):
    """scripts/<name>.py as a module, for the test of that script (scripts/package.py,
    the packager, stays a script beside set-up; the tools are verbs of this package)."""
    from whitted_tools import SCRIPTS

    spec = importlib.util.spec_from_file_location(name, SCRIPTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
