"""The verbs of `python -m whitted_tools VERB [ARGS]`: which module runs each, grouped by
the subpackage it lives in, and the help that lists them.

Every verb module has `main(argv)` (argv: the verb's own arguments) and a docstring
whose first line is its description. The same verbs run inside Blender 3.4 through the
package's one entry file (`blender -b ... --python tools/whitted_tools/__main__.py --
VERB [ARGS]`, what blender.verb_in_blender makes) and in the bpy module's Python
(`.venv/bin/python -m whitted_tools VERB [ARGS]`).
"""

import ast
import importlib
import importlib.util
import shlex
import sys

# group (a subpackage, whose docstring describes it) -> verb -> module under whitted_tools.
GROUPS = {
    "bench": {
        "bench-effects": "bench.effects",
        "bench-hair": "bench.hair",
        "bench-materials": "bench.materials",
        "bench-memory": "bench.memory",
        "bench-noise": "bench.noise",
        "bench-passes": "bench.passes",
        "bench-rounds": "bench.rounds",
        "bench-viewport": "bench.viewport",
        "bench-viewport-clean": "bench.viewport_clean",
        "bench-volumes": "bench.volumes",
        "bench-world-light": "bench.world_light",
    },
    "perf": {
        "bench-performance": "perf.suite",
        "perf-scenes": "perf.scenes",
        "perf-render": "perf.render",
        "perf-raw-embree": "perf.raw_embree",
        "perf-povray": "perf.povray_render",
    },
    "gallery": {
        "gallery-lights": "gallery.lights",
        "gallery-materials": "gallery.materials",
        "gallery-effects": "gallery.effects",
        "gallery-features": "gallery.features",
    },
    "pages": {
        "passes-page": "pages.passes",
        "passes-render": "pages.passes_render",
        "ray-tree-page": "pages.ray_tree",
        "robustness-images": "pages.robustness_images",
        "docs-images": "pages.docs_images",
        "blender-versions": "pages.blender_versions",
    },
    "cost": {
        "accuracy-cost": "cost.report",
        "cost-render": "cost.render",
        "cost-scenes": "cost.scenes",
        "estimate-accuracy": "cost.estimate_accuracy",
    },
    "farm": {
        "farm": "farm.command",
        "farm-scene": "farm.scene",
        "bench-farm": "farm.bench",
    },
    "check": {
        "image-hashes": "check.image_hashes",
        "fuzz": "check.fuzz",
        "compare-kernels": "check.compare_kernels",
        "compare-kernels-table": "check.kernels_table",
        "compare-builds": "builds",
        "codebase": "check.codebase",
    },
    "generate": {
        "hosek-wilkie-data": "generate.hosek_wilkie",
    },
    "profiling": {
        "profile-trace": "profiling.trace",
    },
}
VERBS = {verb: module for verbs in GROUPS.values() for verb, module in verbs.items()}

ENTRY_FILE = "tools/whitted_tools/__main__.py"
BLENDER = "blender -b --factory-startup --python-exit-code 1"


def verb_of(module_name):
    """The verb that runs the module `module_name` (whitted_tools.X.Y)."""
    return next(verb for verb, module in VERBS.items() if f"whitted_tools.{module}" == module_name)


def prog(module_name):
    """The command a verb module's argument parser names in its usage line."""
    return f"python -m whitted_tools {verb_of(module_name)}"


def python_line(verb, *args, python=".venv/bin/python"):
    """The verb as typed from the repository root with the .venv's Python."""
    return shlex.join([python, "-m", "whitted_tools", verb, *map(str, args)])


def blender_line(verb, *args, blender=BLENDER):
    """The verb as typed from the repository root for Blender 3.4 in the background."""
    return f"{blender} --python {ENTRY_FILE} -- {shlex.join([verb, *map(str, args)])}"


def first_line(module):
    """The first line of the docstring of whitted_tools.`module`, read without importing
    it (most verb modules import bpy, or start Blender)."""
    spec = importlib.util.find_spec(f"whitted_tools.{module}")
    with open(spec.origin, encoding="utf-8") as source:
        doc = ast.get_docstring(ast.parse(source.read())) or ""
    return doc.splitlines()[0].rstrip(":") if doc else ""


def help_text():
    """Every verb, grouped by subpackage, with its description."""
    lines = [
        "usage: python -m whitted_tools VERB [ARGS]      (VERB --help: its arguments)",
        f"  inside Blender 3.4: {BLENDER} --python {ENTRY_FILE} -- VERB [ARGS]",
    ]
    width = max(map(len, VERBS))
    for group, verbs in GROUPS.items():
        lines += ["", f"{group}: {first_line(group)}"]
        lines += [f"  {verb:<{width}}  {first_line(module)}" for verb, module in verbs.items()]
    return "\n".join(lines)


def run(args):
    """Run the verb args[0] with the arguments after it; None, or the exit status."""
    if not args or args[0] in ("-h", "--help"):
        print(help_text())
        return None
    verb, *rest = args
    if verb not in VERBS:
        print(help_text(), file=sys.stderr)
        return f"whitted_tools: unknown verb '{verb}'"
    return importlib.import_module(f"whitted_tools.{VERBS[verb]}").main(rest)
