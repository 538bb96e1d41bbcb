#!/usr/bin/env bash
# Build the installable package: dist/whitted-VERSION-linux-x64.zip (and nothing else
# in dist/). One zip for both Blender targets: Blender 4.2+ installs it as an
# extension (Preferences > Get Extensions > Install from Disk), Blender 3.x as an
# add-on (Preferences > Add-ons > Install). Its compiled module carries its own
# Embree and TBB (scripts/package.py says how). Sets up first (scripts/setup.sh),
# so the native build is current; Blender 5.0's `extension validate` checks the zip.
# Run from anywhere; prints the zip's path last.
set -euo pipefail
REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO_ROOT"
bash scripts/setup.sh
echo
echo "==> [package] building dist/"
.venv/bin/python scripts/package.py "$@"
