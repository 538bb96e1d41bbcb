"""Regenerate docs/images/demo.png: the demo scene as scripts/demo.sh renders it.

    .venv/bin/python -m whitted_tools docs-images

Renders scripts/demo_scene.py (the demo's own scene script) in Blender 3.4 at 480 x 360
at the Preview preset, as scripts/demo.sh does;
needs the set-up (scripts/setup.sh): Blender 3.4 with the add-on installed.
"""

import argparse
import sys

from whitted_tools import REPO
from whitted_tools.blender import blender_command, run_process
from whitted_tools.verbs import prog


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args(argv)
    image = REPO / "docs" / "images" / "demo.png"
    image.parent.mkdir(parents=True, exist_ok=True)
    command = blender_command(
        REPO / "scripts" / "demo_scene.py",
        *("--output", image, "--resolution", 480, 360, "--preset", "PREVIEW"),
        blender=args.blender,
    )
    _, problem = run_process(command, 600)
    if problem:
        sys.exit(f"docs-images: {problem}")
    print(f"wrote {image}")
