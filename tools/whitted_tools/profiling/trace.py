"""Where the trace time goes: a perf profile of the demo rendered on one thread.

    .venv/bin/python -m whitted_tools profile-trace [WIDTH HEIGHT]      (default 1280 720)

By library (Embree, our module, ...) and by function in our module. Needs `perf`
(Debian: apt-get install linux-perf) and the set-up of scripts/setup.sh. The release
module is stripped, so this builds one with symbols (RelWithDebInfo, same -O3) in
build-profile/, which puts it into addon/ for the run; the release module is rebuilt
into addon/ at the end, whatever happens.
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from whitted_tools import REPO
from whitted_tools.blender import VENV_PYTHON, blender_command, verb_in_blender
from whitted_tools.verbs import prog


def quiet(command):
    subprocess.run(list(map(str, command)), cwd=REPO, check=True, stdout=subprocess.DEVNULL)


def report(data, *options, lines):
    """The first `lines` rows of `perf report` on `data`, sorted by `options`."""
    output = subprocess.run(
        ["perf", "report", "-i", str(data), "--no-children", *options, "--stdio"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rows = [line for line in output.splitlines() if line.lstrip()[:1].isdigit()]
    print("\n".join(rows[:lines]))


def build_profile_module():
    pybind11_dir = subprocess.run(
        [str(VENV_PYTHON), "-m", "pybind11", "--cmakedir"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    quiet(
        [
            *("cmake", "-S", ".", "-B", "build-profile", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"),
            "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O3 -g -DNDEBUG -fno-omit-frame-pointer",
            f"-Dpybind11_DIR={pybind11_dir}",
            f"-DWHITTED_PYTHON_EXECUTABLES={VENV_PYTHON}",
        ]
    )
    quiet(["cmake", "--build", "build-profile", "--target", "whitted_native_py311"])


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("size", nargs="*", type=int, default=[1280, 720], metavar="WIDTH HEIGHT")
    args = parser.parse_args(argv)
    if len(args.size) != 2:
        parser.error("give WIDTH HEIGHT, or neither")
    if shutil.which("perf") is None:
        sys.exit("perf not found: apt-get install linux-perf")
    width, height = args.size
    with tempfile.TemporaryDirectory(prefix="whitted-profile-") as tmp:
        work = Path(tmp)
        try:
            build_profile_module()
            profile(work, width, height)
        finally:
            quiet(["cmake", "--build", "build"])  # the release module back into addon/


def profile(work, width, height):
    blend = work / "demo.blend"
    demo = REPO / "scripts" / "demo_scene.py"
    quiet(blender_command(demo, "--save", blend, "--resolution", width, height, "--no-render"))

    def raw_embree(json_path, *extra):
        return verb_in_blender(
            "perf-raw-embree",
            *("--json", json_path, "--threads", 1, *extra),
            blend=blend,
            addons=("whitted",),
        )

    # One thread. The efficiency, from a run without the profiler:
    quiet(raw_embree(work / "raw.json"))
    raw = json.loads((work / "raw.json").read_text())
    print(
        f"demo {width}x{height}, one thread: Whitted "
        f"{raw['whitted_rays_per_second'] / 1e6:.2f} Mrays/s, bare Embree "
        f"{raw['embree_rays_per_second'] / 1e6:.2f} Mrays/s, efficiency {raw['efficiency']:.2f}"
    )
    # The profile: the same renders (a warm-up and three timed) without the bare loop.
    data = work / "perf.data"
    quiet(
        [
            "perf",
            "record",
            "-F",
            2000,
            "-o",
            data,
            "--",
            *raw_embree(work / "unused.json", "--renders-only"),
        ]
    )
    print("\nShare of all samples by library (the process also starts Blender and exports):")
    report(data, "--sort", "dso", lines=8)
    print("\nOur module and libm by function (share of all samples):")
    module = next((REPO / "addon").glob("whitted_native.cpython-311-*.so")).name
    report(data, "--sort", "symbol", "--dsos", f"{module},libm.so.6", lines=15)
