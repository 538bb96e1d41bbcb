#!/usr/bin/env bash
# Where the trace time goes: a perf profile of the demo scene rendered on one thread,
# by library (Embree, our module, ...) and by function in our module.
#
#   bash scripts/profile_trace.sh [WIDTH HEIGHT]        (default 1280 720)
#
# Needs `perf` (Debian: apt-get install linux-perf) and the set-up of scripts/setup.sh.
# The release module is stripped, so this builds one with symbols (RelWithDebInfo, same
# -O3) in build-profile/, which puts it into addon/ for the run; the release module is
# rebuilt into addon/ at the end, whatever happens.
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO_ROOT"
WIDTH=${1:-1280}
HEIGHT=${2:-720}
command -v perf >/dev/null || { echo "perf not found: apt-get install linux-perf" >&2; exit 1; }

WORK=$(mktemp -d /tmp/whitted-profile-XXXXXX)
restore_release() { cmake --build build >/dev/null; }
trap restore_release EXIT

cmake -S . -B build-profile -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O3 -g -DNDEBUG -fno-omit-frame-pointer" \
  -Dpybind11_DIR="$(.venv/bin/python -m pybind11 --cmakedir)" \
  -DWHITTED_PYTHON_EXECUTABLES="$REPO_ROOT/.venv/bin/python" >/dev/null
cmake --build build-profile --target whitted_native_py311 --parallel "$(nproc)" >/dev/null

blender -b --factory-startup --python scripts/demo_scene.py -- \
  --save "$WORK/demo.blend" --resolution "$WIDTH" "$HEIGHT" --no-render >/dev/null
# One thread. The efficiency, from a run without the profiler:
blender -b "$WORK/demo.blend" --python scripts/perf_raw_embree.py -- \
  --json "$WORK/raw.json" --threads 1 >/dev/null 2>&1
echo "demo ${WIDTH}x${HEIGHT}, one thread: $(.venv/bin/python -c "
import json; r = json.load(open('$WORK/raw.json'))
print(f\"Whitted {r['whitted_rays_per_second'] / 1e6:.2f} Mrays/s, bare Embree \"
      f\"{r['embree_rays_per_second'] / 1e6:.2f} Mrays/s, efficiency {r['efficiency']:.2f}\")")"
# The profile: the same renders (a warm-up and three timed) without the bare loop.
perf record -F 2000 -o "$WORK/perf.data" -- blender -b "$WORK/demo.blend" \
  --python scripts/perf_raw_embree.py -- --json "$WORK/unused.json" --threads 1 \
  --renders-only >/dev/null 2>&1
echo
echo "Share of all samples by library (the process also starts Blender and exports):"
perf report -i "$WORK/perf.data" --no-children --sort dso --stdio 2>/dev/null |
  grep -E '^ +[0-9]' | head -8
echo
echo "Our module and libm by function (share of all samples):"
perf report -i "$WORK/perf.data" --no-children --sort symbol --stdio \
  --dsos "$(basename addon/whitted_native.cpython-311-*.so)",libm.so.6 2>/dev/null |
  grep -E '^ +[0-9]' | head -15
rm -rf "$WORK"
