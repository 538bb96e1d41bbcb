#!/usr/bin/env bash
# Set up what the demo needs (scripts/setup.sh --demo), then render the built-in demo
# scene (a glass sphere, a mirror sphere, diffuse objects on a floor, two lights)
# headless in Blender 3.4 with the Whitted engine, and print the image's absolute path.
#
#   scripts/demo.sh [--output FILE] [--resolution WIDTH HEIGHT]
#
# Defaults: out/demo.png (in the repository), 640 x 480. Run from anywhere; a
# relative --output is taken relative to the current directory.
set -euo pipefail

usage() {
  sed -n '2,9s/^# \{0,1\}//p' "${BASH_SOURCE[0]}" >&2
  exit 2
}

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
output="$REPO_ROOT/out/demo.png"
width=640
height=480
while [[ $# -gt 0 ]]; do
  case $1 in
    --output)
      [[ $# -ge 2 ]] || usage
      output=$(realpath -m -- "$2")
      shift 2
      ;;
    --resolution)
      [[ $# -ge 3 && $2 =~ ^[0-9]+$ && $3 =~ ^[0-9]+$ ]] || usage
      width=$2 height=$3
      shift 3
      ;;
    -h | --help) usage ;;
    *)
      echo "demo.sh: unknown argument: $1" >&2
      usage
      ;;
  esac
done
cd "$REPO_ROOT"

bash scripts/setup.sh --demo

echo
echo "==> [demo] rendering the demo scene at ${width}x${height} with Blender 3.4"
start=$(date +%s.%N)
mkdir -p "$(dirname "$output")"
rm -f "$output"
# --factory-startup ignores user preferences (and so user add-ons): demo_scene.py
# enables the add-on itself, so the demo does not depend on this user's settings.
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_scene.py -- \
  --output "$output" --resolution "$width" "$height" --preset PREVIEW
[[ -s $output ]] || { echo "[demo] error: Blender finished but wrote no $output" >&2; exit 1; }
echo "<== [demo] rendered in $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s"
echo
echo "Demo image: $output"
