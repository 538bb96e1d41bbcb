#!/usr/bin/env bash
# Regenerates the images under docs/images/ from the built-in demo scene.
# Needs the set-up done (scripts/setup.sh): Blender 3.4 with the add-on installed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mkdir -p docs/images
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_scene.py -- \
  --output docs/images/demo.png --resolution 480 360
